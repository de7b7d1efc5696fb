#!/usr/bin/python3
"""Session 33: the oracle ladder's own-model rungs (selfsupervise --oracle-ladder
--own-model-rungs) beside the rungs they repeat, over several runs' JSON records.

usage: python3 own.py FILE...   (selfsupervise --json files, one a seed)

Per rung pair (x, x_own): per run, per object, mean with a 95% t interval over the runs, and the
paired difference x_own - x (points). x_own: the same training views through a vocabulary and an
LDA model of their own, classified by the pooled per-view words classifier at the run's weight;
its figures at the other weights (0, 0.25, 0.5, 0.75, 1) after.
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


def main():
    runs = []
    for f in sys.argv[1:]:
        g = json.load(open(f))["ground_truth"]
        runs.append((f, g, {r["name"]: r for r in g["oracle_ladder"]["rungs"]}))
    objects = [o["name"] for o in runs[0][1]["objects"]]
    print("runs: " + " ".join(f for f, _, _ in runs))
    print(f"{'rung':8s} {'mean +- 95% t':>16s}  per run  | per object (mean over runs): "
          + " ".join(objects))
    for base in ["a0", "a", "b", "c", "a_up"]:
        for name in [base, base + "_own"]:
            rs = [r.get(name) for _, _, r in runs]
            if any(r is None for r in rs):
                continue
            acc = [100 * r["accuracy"] for r in rs]
            m, h = ci(acc)
            po = [sum(100 * r["per_object"][i] for r in rs) / len(rs) for i in range(len(objects))]
            print(f"{name:8s} {m:7.1f} +- {h:5.1f}%  " + " ".join(f"{a:5.1f}" for a in acc)
                  + "  | " + " ".join(f"{p:5.1f}" for p in po)
                  + f"   views {sum(r['training_views'] for r in rs) / len(rs):.0f}"
                  + " classes " + " ".join(str(r["classes"]) for r in rs))
        rs = [(r.get(base), r.get(base + "_own")) for _, _, r in runs]
        if all(x and y for x, y in rs):
            d = [100 * (y["accuracy"] - x["accuracy"]) for x, y in rs]
            m, h = ci(d)
            print(f"  {base}_own - {base}: {m:+.1f} +- {h:.1f} points (" +
                  " ".join(f"{x:+.1f}" for x in d) + ")")
    print("per object, per run (a_up, a_up_own: also the views and classes):")
    for f, _, r in runs:
        for name in ["a_own", "c_own", "a_up_own"]:
            if name in r:
                print(f"  {f} {name}: " + " ".join(
                    f"{o} {100 * p:.0f}" for o, p in zip(objects, r[name]["per_object"])))
        for name in ["a", "c", "a_up"]:
            if name not in r:
                continue
            print(f"  {f} {name}: " + " ".join(
                f"{o} {100 * p:.0f}" for o, p in zip(objects, r[name]["per_object"])))
    print("own rungs at each weight of the word multinomials (mean over runs):")
    for base in ["a0_own", "a_own", "b_own", "c_own", "a_up_own"]:
        rs = [r.get(base) for _, _, r in runs]
        if any(x is None or not x.get("pooled") for x in rs):
            continue
        ws = [p["weight"] for p in rs[0]["pooled"]]
        print(f"  {base:7s} " + " ".join(
            f"w={w:g}: {sum(100 * x['pooled'][k]['accuracy'] for x in rs) / len(rs):5.1f}"
            for k, w in enumerate(ws)))


main()
