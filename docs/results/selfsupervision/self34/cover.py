#!/usr/bin/python3
"""Session 34: coverage first, then c, per seed, of `proprio selfsupervise` runs (issue 19).

usage: cover.py LABEL=DIR [LABEL=DIR ...] SEEDS   e.g. cover.py def=OUT/def rc=OUT/rc "1 7 8"

Each DIR holds motion-sS.json (scripts/experiment-selfsup). Per run: distinct objects learned
(named objects with views, i.e. a class named after them: ground_truth.objects[].views > 0),
rounds spent on an object already learned (a round whose class_object names an object an earlier
round's class already did; rounds with no class count as neither), c (held-out MoT accuracy),
argmax, purity, the rounds' objects, and how often the `recheck` event chose again. Then each
setting's means with 95% t intervals and, against the first setting, the paired differences.
Standard library only.
"""
import json
import math
import os
import sys

T95 = {1: 12.706, 2: 4.303, 3: 3.182, 4: 2.776, 5: 2.571, 6: 2.447, 7: 2.365}


def ci(v):
    n = len(v)
    m = sum(v) / n
    if n < 2:
        return m, None
    s = math.sqrt(sum((x - m) ** 2 for x in v) / (n - 1))
    return m, T95.get(n - 1, 2.0) * s / math.sqrt(n)


def run(path):
    j = json.load(open(path))
    g = j["ground_truth"]
    learned = [o["name"] for o in g["objects"] if o["views"] > 0]
    seen, wasted = set(), 0
    for k, obj in enumerate(g["class_object"]):
        if not obj or j["views_per_class"][k] == 0:
            continue
        if obj in seen:
            wasted += 1
        seen.add(obj)
    rechecks = again = grown = 0
    dec = j.get("decisions") or ""
    if dec and not os.path.isabs(dec):
        dec = os.path.join(os.path.dirname(path), dec)
    if dec and os.path.exists(dec):
        for line in open(dec):
            e = json.loads(line)
            if e.get("event") == "fault" and e.get("fault") == "grown":
                grown += 1
            if e.get("event") == "recheck":
                rechecks += 1
                again += "choosing again" in e.get("why", "")
    return {
        "distinct": len(learned),
        "wasted": wasted,
        "c": 100 * g["mot_accuracy"],
        "argmax": 100 * g["argmax_accuracy"],
        "purity": 100 * g["purity"],
        "objects": ",".join(x or "-" for x in g["class_object"]),
        "per": " ".join("%d" % round(100 * o["mot_accuracy"]) for o in g["objects"]),
        "recheck": "%d/%d" % (again, rechecks),
        "grown": grown,
    }


def main():
    args = sys.argv[1:]
    seeds = args[-1].split()
    sets = [a.split("=", 1) for a in args[:-1]]
    res = {}
    print("| seed | setting | distinct objects learned | rounds on a learned object | c | c per object (%s) | argmax | purity | class objects | rechecks (again/all) | `grown` |" % "calc bike bottle giraffe")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for s in seeds:
        for label, d in sets:
            p = os.path.join(d, "motion-s%s.json" % s)
            if not os.path.exists(p):
                continue
            r = run(p)
            res[(label, s)] = r
            print("| %s | %s | %d | %d | %.1f | %s | %.1f | %.1f | %s | %s | %d |" % (
                s, label, r["distinct"], r["wasted"], r["c"], r["per"], r["argmax"], r["purity"],
                r["objects"], r["recheck"], r["grown"]))
    print()
    base = sets[0][0]
    for label, _ in sets:
        have = [s for s in seeds if (label, s) in res]
        if not have:
            continue
        line = [label, "n=%d" % len(have)]
        for k in ("distinct", "wasted", "c", "argmax"):
            m, h = ci([res[(label, s)][k] for s in have])
            line.append("%s %.2f +- %s" % (k, m, "-" if h is None else "%.2f" % h))
        print("  ".join(line))
        if label != base:
            both = [s for s in have if (base, s) in res]
            for k in ("distinct", "wasted", "c", "argmax"):
                d = [res[(label, s)][k] - res[(base, s)][k] for s in both]
                if d:
                    m, h = ci(d)
                    print("   paired %s - %s %s: %+.2f +- %s (%s)" % (
                        label, base, k, m, "-" if h is None else "%.2f" % h,
                        " ".join("%+.1f" % x for x in d)))


main()
