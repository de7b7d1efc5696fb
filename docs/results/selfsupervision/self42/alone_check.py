#!/usr/bin/python3
"""Session 42: how each round's (b) ended by the robot's own check against the ground truth.
usage: alone_check.py RUNS_DIR SEED... (RUNS_DIR/motion-sS.json and motion-sS/decisions.jsonl).
A round's (b) ends with the robot's event "singulated" (it judged the chosen object alone by the
feature hulls at --clearance) or a fault (cannot-clear, lost, not-singulated, grown); the ground
truth's class_gap is the chosen object's footprint gap to its nearest other object after (b)
(singulation: >= 0.10 m). Standard library only."""
import collections, json, sys

d, seeds = sys.argv[1], [int(s) for s in sys.argv[2:]]
ends = collections.Counter()
gaps = collections.defaultdict(list)
for s in seeds:
    g = json.load(open(f"{d}/motion-s{s}.json"))["ground_truth"]
    per = collections.defaultdict(list)
    for line in open(f"{d}/motion-s{s}/decisions.jsonl"):
        e = json.loads(line)
        if e.get("event") == "singulated":
            per[e["round"]].append("singulated")
        elif e.get("event") == "fault" and e["fault"] in ("cannot-clear", "lost", "not-singulated", "grown"):
            per[e["round"]].append(e["fault"])
    for r, gap in enumerate(g["class_gap"]):
        k = per[r][-1] if per[r] else "none"
        ends[(k, gap >= 0.10)] += 1
        gaps[k].append(gap)
print("how (b) ended (the robot) | truly alone (gap >= 0.10 m) | not | median gap, m")
for k in sorted(gaps):
    v = sorted(gaps[k])
    print(f"{k:14s} | {ends[(k, True)]:3d} | {ends[(k, False)]:3d} | {v[len(v) // 2]:.3f}")
said = sorted(x for x in gaps["singulated"] if x < 0.10)
if said:
    print("said alone, not alone: gaps " + " ".join(f"{x:.3f}" for x in said))
