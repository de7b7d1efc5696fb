#!/usr/bin/env python3
"""Summary of a selfsupervise series: per-seed figures with 95% t intervals, per object learn
pushes, yaw range, turn per push; rounds whose pushed-most object is the chosen one."""
import json, math, sys, collections
out, seeds = sys.argv[1], sys.argv[2].split()
def ci(v):
    n = len(v); m = sum(v) / n
    if n < 2: return m, 0.0
    sd = math.sqrt(sum((x - m) ** 2 for x in v) / (n - 1))
    t = {2: 12.71, 3: 4.30, 4: 3.18, 5: 2.78, 6: 2.57}.get(n, 2.0)
    return m, t * sd / math.sqrt(n)
rows = {s: json.load(open(f"{out}/motion-s{s}.json")) for s in seeds}
def rung(g, name):
    for r in g.get("oracle_ladder", {}).get("rungs", []):
        if r["name"] == name: return r["accuracy"]
    return float("nan")
def line(name, vals, pct=True):
    m, h = ci(vals); k = 100 if pct else 1
    print(f"{name:40s} {k*m:6.1f} +- {k*h:5.1f}   per seed: " + " ".join(f"{k*v:.1f}" for v in vals))
gs = [rows[s]["ground_truth"] for s in seeds]
line("c (MoT)", [g["mot_accuracy"] for g in gs])
line("argmax", [g["argmax_accuracy"] for g in gs])
line("a_alone", [rung(g, "a_alone") for g in gs])
line("singulation", [g["singulation"] for g in gs])
line("pushes per object moved to edge", [g["pushes_per_cleared"] for g in gs], False)
line("off table", [g["off_table"] for g in gs], False)
line("learn pushes executed", [rows[s]["pushes_learn"] for s in seeds], False)
line("clear pushes executed", [rows[s]["pushes_clear"] for s in seeds], False)
match = [sum(1 for a, b in zip(g["class_chosen"], g["class_object"]) if a == b) for g in gs]
print("rounds whose pushed-most object is the chosen one:", sum(match), "of", sum(len(g["class_chosen"]) for g in gs), match)
print("distinct pushed most:", [len(set(x for x in g["class_object"] if x)) for g in gs])
above = sum(1 for g in gs if g["mot_accuracy"] > g["argmax_accuracy"]); print("above argmax on", above, "of", len(gs))
faults = collections.Counter()
refound = 0
for s in seeds:
    for l in open(f"{out}/motion-s{s}/decisions.jsonl"):
        j = json.loads(l)
        if j["event"] == "fault": faults[j["fault"]] += 1
        if j["event"] == "refound" and j.get("why", "").startswith("looks"): refound += 1
print("faults (all runs):", dict(faults), "refound by looks:", refound)
objs = collections.defaultdict(list)
for g in gs:
    for o in g["objects"]: objs[o["name"]].append(o)
print(f"{'object':11s} {'learn pushes (per seed)':28s} {'mean +- ci':12s} {'seeds w/o':9s} {'yaw range':14s} {'turn/push':12s} {'c':10s}")
for n, os in objs.items():
    lp = [o["learn_pushes"] for o in os]; m, h = ci(lp)
    yr = [o["yaw_range_deg"] for o in os]; ym, yh = ci(yr)
    tp = [o.get("turn_deg", 0) for o in os if o["learn_pushes"] > 0]; tm, th = ci(tp) if tp else (0, 0)
    cm, ch = ci([o["mot_accuracy"] for o in os])
    print(f"{n:11s} {' '.join(str(x) for x in lp):28s} {m:4.1f} +- {h:4.1f} {sum(1 for x in lp if x == 0):5d}    {ym:4.0f} +- {yh:4.0f}d  {tm:4.1f} +- {th:4.1f}d {100*cm:4.0f} +- {100*ch:3.0f}%")
