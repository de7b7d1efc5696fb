#!/usr/bin/python3
"""Session 41's rule (rule-s41-claims-colour.md): two settings of `proprio selfsupervise` on the
same seeds, paired. usage: paired.py BASE_DIR OPTION_DIR SEED... (each DIR holds motion-sS.json
as scripts/experiment-selfsup writes them). Prints per seed c (mot_accuracy), argmax, coverage
(the issue's objects that name at least one class), the classes' objects and the wall time, then
the paired means with 95% t intervals, the counts higher / lower and the rule's four clauses.
Standard library only."""
import json
import math
import statistics
import sys

T95 = {1: 12.71, 2: 4.30, 3: 3.18, 4: 2.78, 5: 2.57, 6: 2.45, 7: 2.36, 8: 2.31, 9: 2.26,
       10: 2.23, 11: 2.20, 12: 2.18, 13: 2.16, 14: 2.14, 15: 2.13, 16: 2.12, 17: 2.11,
       18: 2.10, 19: 2.09, 20: 2.09, 29: 2.05, 39: 2.02}


def ci(v):
    n = len(v)
    m = sum(v) / n
    if n < 2:
        return m, 0.0
    sd = statistics.stdev(v)
    return m, T95.get(n - 1, 2.0) * sd / math.sqrt(n)


def row(path):
    j = json.load(open(path))
    g = j["ground_truth"]
    covered = sum(1 for o in g["objects"] if o.get("classes"))
    return {"c": 100 * g["mot_accuracy"], "argmax": 100 * g["argmax_accuracy"],
            "cover": covered, "objects": g["class_object"], "wall": j["seconds"],
            "per": {o["name"]: 100 * o["mot_accuracy"] for o in g["objects"]}}


if len(sys.argv) < 4:
    sys.exit(__doc__)
base, opt, seeds = sys.argv[1], sys.argv[2], sys.argv[3:]
rows = [(s, row(f"{base}/motion-s{s}.json"), row(f"{opt}/motion-s{s}.json")) for s in seeds]
print("| seed | c base | c option | argmax base | argmax option | coverage base | coverage option "
      "| classes' objects base | classes' objects option |")
print("|---|---|---|---|---|---|---|---|---|")
for s, a, b in rows:
    print(f"| {s} | {a['c']:.1f} | {b['c']:.1f} | {a['argmax']:.1f} | {b['argmax']:.1f} | "
          f"{a['cover']} | {b['cover']} | {', '.join(a['objects'])} | {', '.join(b['objects'])} |")
print()
for key, name in (("c", "c (Mixture of Topics)"), ("argmax", "argmax theta"),
                  ("cover", "coverage (objects)")):
    ma, ha = ci([a[key] for _, a, _ in rows])
    mb, hb = ci([b[key] for _, _, b in rows])
    d = [b[key] - a[key] for _, a, b in rows]
    md, hd = ci(d)
    print(f"{name}: base {ma:.2f} +- {ha:.2f}, option {mb:.2f} +- {hb:.2f}, paired "
          f"{md:+.2f} +- {hd:.2f} (interval {md - hd:+.2f} to {md + hd:+.2f}), higher on "
          f"{sum(1 for x in d if x > 0)}, lower on {sum(1 for x in d if x < 0)} of {len(d)}")
names = list(rows[0][1]["per"])
print("per object c (mean over the seeds), base -> option: " + ", ".join(
    f"{n} {sum(a['per'][n] for _, a, _ in rows) / len(rows):.1f} -> "
    f"{sum(b['per'][n] for _, _, b in rows) / len(rows):.1f}" for n in names))
wa = statistics.median(a["wall"] for _, a, _ in rows)
wb = statistics.median(b["wall"] for _, _, b in rows)
print(f"median wall: base {wa:.1f} s, option {wb:.1f} s ({100 * (wb / wa - 1):+.1f} %)")
dc = [b["cover"] - a["cover"] for _, a, b in rows]
dd = [b["c"] - a["c"] for _, a, b in rows]
mc, hc = ci(dc)
md, _ = ci(dd)
clauses = [mc > 0 and mc - hc > 0, md >= 0, sum(1 for x in dd if x < 0) <= len(dd) // 2,
           wb <= 1.15 * wa]
print("rule clauses: " + ", ".join(f"{i + 1} {'held' if ok else 'FAILED'}"
                                   for i, ok in enumerate(clauses)))
print("verdict: " + ("PASSED" if all(clauses) else "failed"))
