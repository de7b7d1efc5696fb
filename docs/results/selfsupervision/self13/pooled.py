#!/usr/bin/python3
"""c and the ladder's rungs by theta (eq 7.3) and by the pooled words classifier, paired per run.

usage: python3 docs/results/selfsupervision/self13/pooled.py [--weight W] FILE...
  FILE: `proprio selfsupervise --oracle-ladder --pooled-score --json` records (one per seed).
Per rung: theta and pooled (weight W, default 0.25) means with 95% t intervals over the runs,
the paired difference and its per-run values; then c per object, theta against pooled and
against pooled with each push's views counted once ("once").
"""
import json
import math
import sys

T95 = {2: 12.71, 3: 4.30, 4: 3.18, 5: 2.78, 6: 2.57, 7: 2.45}


def ci(v):
    n = len(v)
    m = sum(v) / n
    if n < 2:
        return m, 0.0
    sd = math.sqrt(sum((x - m) ** 2 for x in v) / (n - 1))
    return m, T95.get(n, 2.0) * sd / math.sqrt(n)


def fmt(v):
    m, h = ci(v)
    return f"{100 * m:5.1f} +- {100 * h:4.1f}"


def main():
    args = sys.argv[1:]
    weight = 0.25
    if args[:1] == ["--weight"]:
        weight, args = float(args[1]), args[2:]
    runs = [json.load(open(f))["ground_truth"] for f in args]
    names = [r["name"] for r in runs[0]["oracle_ladder"]["rungs"]]
    objects = [o["name"] for o in runs[0]["objects"]]

    def pick(rung, once=False):
        return next(f for f in rung["pooled"] if f["weight"] == weight and f["once"] == once)

    print(f"{len(runs)} runs; pooled at w = {weight}")
    print(f"| rung | theta | pooled | pooled - theta | per run (points) |")
    print("|---|---|---|---|---|")
    for k, name in enumerate(names):
        rs = [g["oracle_ladder"]["rungs"][k] for g in runs]
        if not all(r.get("pooled") for r in rs):
            continue
        th = [r["accuracy"] for r in rs]
        po = [pick(r)["accuracy"] for r in rs]
        d = [p - t for p, t in zip(po, th)]
        print(f"| {name} | {fmt(th)}% | {fmt(po)}% | {fmt(d)} | "
              + " ".join(f"{100 * x:+.0f}" for x in d) + " |")
    c = [g["oracle_ladder"]["rungs"][-1] for g in runs]
    if all(r.get("pooled") and any(f["once"] for f in r["pooled"]) for r in c):
        th = [r["accuracy"] for r in c]
        on = [pick(r, True)["accuracy"] for r in c]
        d = [p - t for p, t in zip(on, th)]
        print(f"| c, pushes once | {fmt(th)}% | {fmt(on)}% | {fmt(d)} | "
              + " ".join(f"{100 * x:+.0f}" for x in d) + " |")
    print()
    print("| object (c) | theta | pooled | pooled, pushes once |")
    print("|---|---|---|---|")
    for i, o in enumerate(objects):
        th = [g["objects"][i]["mot_accuracy"] for g in runs]
        po = [pick(r)["per_object"][i] for r in c]
        on = [pick(r, True)["per_object"][i] for r in c] if all(
            any(f["once"] for f in r["pooled"]) for r in c) else []
        cell = lambda v: f"{fmt(v)}% ({' '.join(f'{100 * x:.0f}' for x in v)})"
        print(f"| {o} | {cell(th)} | {cell(po)} | {cell(on) if on else '-'} |")


if __name__ == "__main__":
    main()
