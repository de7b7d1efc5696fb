#!/usr/bin/python3
"""Session 41's second rule (rule-s41-views-both.md): `proprio selfsupervise --views both`
against motion views on the same seeds. usage: views_both.py MOTION_DIR BOTH_DIR SEED...
(MOTION_DIR/motion-sS.json and BOTH_DIR/both-sS.json as scripts/experiment-selfsup writes them).
Checks that each seed made the same pushes (the same classes' objects; each class's views at
least as many as the motion run's and at most twice), prints per seed c, argmax and views, the
paired c gain with its 95% t interval and the rule's clauses. Standard library only."""
import json
import math
import statistics
import sys

if len(sys.argv) < 4:
    sys.exit(__doc__)
mdir, bdir, seeds = sys.argv[1], sys.argv[2], sys.argv[3:]
rows = []
for s in seeds:
    m = json.load(open(f"{mdir}/motion-s{s}.json"))
    b = json.load(open(f"{bdir}/both-s{s}.json"))
    gm, gb = m["ground_truth"], b["ground_truth"]
    vm, vb = m["views_per_class"], b["views_per_class"]
    same = (gm["class_object"] == gb["class_object"] and len(vm) == len(vb)
            and all(x <= y <= 2 * x for x, y in zip(vm, vb)))
    rows.append((s, 100 * gm["mot_accuracy"], 100 * gb["mot_accuracy"],
                 100 * gm["argmax_accuracy"], 100 * gb["argmax_accuracy"], sum(vm), sum(vb),
                 same, m["seconds"], b["seconds"],
                 {o["name"]: 100 * o["mot_accuracy"] for o in gm["objects"]},
                 {o["name"]: 100 * o["mot_accuracy"] for o in gb["objects"]}))
print("| seed | c motion | c both | argmax motion | argmax both | views motion | views both | same pushes |")
print("|---|---|---|---|---|---|---|---|")
for r in rows:
    print(f"| {r[0]} | {r[1]:.1f} | {r[2]:.1f} | {r[3]:.1f} | {r[4]:.1f} | {r[5]} | {r[6]} | "
          f"{'yes' if r[7] else 'NO'} |")
n = len(rows)
t = {19: 2.09, 2: 4.30, 4: 2.78}.get(n - 1, 2.0)


def ci(v):
    mean = sum(v) / len(v)
    return mean, (t * statistics.stdev(v) / math.sqrt(len(v)) if len(v) > 1 else 0.0)


for i, name in ((1, "c motion"), (2, "c both"), (3, "argmax motion"), (4, "argmax both")):
    mean, h = ci([r[i] for r in rows])
    print(f"{name}: {mean:.2f} +- {h:.2f}")
d = [r[2] - r[1] for r in rows]
md, hd = ci(d)
da = [r[4] - r[3] for r in rows]
ma, ha = ci(da)
print(f"paired c (both - motion): {md:+.2f} +- {hd:.2f} (interval {md - hd:+.2f} to {md + hd:+.2f}), "
      f"higher on {sum(1 for x in d if x > 0)}, lower on {sum(1 for x in d if x < 0)} of {n}")
print(f"paired argmax: {ma:+.2f} +- {ha:.2f}, higher on {sum(1 for x in da if x > 0)}, "
      f"lower on {sum(1 for x in da if x < 0)}")
names = list(rows[0][10])
print("per object c, motion -> both: " + ", ".join(
    f"{k} {sum(r[10][k] for r in rows) / n:.1f} -> {sum(r[11][k] for r in rows) / n:.1f}"
    for k in names))
print(f"median run seconds: motion {statistics.median(r[8] for r in rows):.1f}, "
      f"both {statistics.median(r[9] for r in rows):.1f} (not judged: other machine load)")
clauses = [all(r[7] for r in rows), md > 0 and md - hd > 0, sum(1 for x in d if x < 0) <= 5]
print("rule clauses: " + ", ".join(f"{i + 1} {'held' if ok else 'FAILED'}"
                                   for i, ok in enumerate(clauses)))
print("verdict: " + ("PASSED" if all(clauses) else "failed"))
