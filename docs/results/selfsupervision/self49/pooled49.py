#!/usr/bin/python3
"""The pooled words classifier against theta c on the same runs (rule-s49-pooled-classifier.md).

usage: pooled49.py RUN_DIR SEED... [--pick W ONCE]
Reads RUN_DIR/motion-sS.json of runs made with --pooled-score. Prints, for every (weight, once)
of the pooled figures, the mean c and the paired gain over theta c with a 95 % t interval; with
--pick, the per-seed and per-object table of that setting.
"""
import json
import math
import statistics as st
import sys

T975 = {5: 2.571, 10: 2.228, 19: 2.093, 20: 2.086, 25: 2.060, 26: 2.056}


def interval(xs):
    n = len(xs)
    if n < 2:
        return float("nan")
    t = T975.get(n - 1, 1.96)
    return t * st.stdev(xs) / math.sqrt(n)


def main(argv):
    pick = None
    if "--pick" in argv:
        i = argv.index("--pick")
        pick = (float(argv[i + 1]), argv[i + 2] == "true")
        argv = argv[:i] + argv[i + 3:]
    run, seeds = argv[0], [int(s) for s in argv[1:]]
    rows = []
    for s in seeds:
        j = json.load(open(f"{run}/motion-s{s}.json"))
        g = j["ground_truth"]
        rows.append((s, g))
    names = [o["name"] for o in rows[0][1]["objects"]]
    theta = [100 * g["mot_accuracy"] for _, g in rows]
    argmax = [100 * g["argmax_accuracy"] for _, g in rows]
    colour = [100 * g["colour_accuracy"] for _, g in rows]
    n = len(rows)
    print(f"{n} seeds {seeds[0]}-{seeds[-1]}: theta c {st.mean(theta):.1f} +- {interval(theta):.1f}, "
          f"argmax {st.mean(argmax):.1f}, colour {st.mean(colour):.1f}; "
          f"theta c above argmax on {sum(a > b for a, b in zip(theta, argmax))} seeds")
    print("| weight | once | c | paired gain over theta c | higher / lower | above argmax (seeds) |")
    print("|---|---|---|---|---|---|")
    settings = [(p["weight"], p["once"]) for p in rows[0][1]["pooled"]]
    for w, once in settings:
        c = [100 * next(p["accuracy"] for p in g["pooled"] if p["weight"] == w and p["once"] == once)
             for _, g in rows]
        d = [a - b for a, b in zip(c, theta)]
        print(f"| {w} | {str(once).lower()} | {st.mean(c):.1f} | {st.mean(d):+.1f} +- {interval(d):.1f} | "
              f"{sum(x > 0 for x in d)} / {sum(x < 0 for x in d)} | {sum(a > b for a, b in zip(c, argmax))} |")
    if pick is None:
        return
    w, once = pick
    print(f"\nw {w}, once {str(once).lower()}: per seed (theta c -> pooled c; argmax; colour)")
    print("| seed | theta c | pooled c | argmax | colour | per object theta -> pooled |")
    print("|---|---|---|---|---|---|")
    per_t = {k: [] for k in names}
    per_p = {k: [] for k in names}
    for s, g in rows:
        p = next(p for p in g["pooled"] if p["weight"] == w and p["once"] == once)
        objs = []
        for k, o in enumerate(g["objects"]):
            per_t[o["name"]].append(100 * o["mot_accuracy"])
            per_p[o["name"]].append(100 * p["per_object"][k])
            objs.append(f"{100 * o['mot_accuracy']:.0f}->{100 * p['per_object'][k]:.0f}")
        print(f"| {s} | {100 * g['mot_accuracy']:.1f} | {100 * p['accuracy']:.1f} | "
              f"{100 * g['argmax_accuracy']:.1f} | {100 * g['colour_accuracy']:.1f} | {' '.join(objs)} |")
    print("\nper object, theta c -> pooled c (mean over seeds, paired gain +- 95 % t):")
    for k in names:
        d = [a - b for a, b in zip(per_p[k], per_t[k])]
        print(f"  {k:11s} {st.mean(per_t[k]):5.1f} -> {st.mean(per_p[k]):5.1f} ({st.mean(d):+.1f} +- {interval(d):.1f})")


if __name__ == "__main__":
    main(sys.argv[1:])
