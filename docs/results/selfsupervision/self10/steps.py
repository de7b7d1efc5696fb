#!/usr/bin/python3
"""Which step of thesis 7.2 fails, per run (selfsupervise's JSON RUN.json and its decision log
RUN/decisions.jsonl): per round the chosen object, its ground-truth gap after (b) (singulated:
>= 10 cm), the clearing pushes (and free-space pushes of the chosen object), the learn pushes
executed / refused / not planned, those moving the intended object alone and the round's chosen
object alone; per object its learn pushes and the yaw range seen.
usage: steps.py RUN [RUN ...]   (RUN without .json)"""
import json, sys, os
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "../../../../scripts"))
from oracle_ladder_table import ci  # mean and 95% t half-width over the runs

tot = {}
def add(k, v): tot.setdefault(k, []).append(v)
for run in sys.argv[1:]:
    d = json.load(open(run + ".json")); g = d["ground_truth"]
    lp_ = os.path.join(run, "decisions.jsonl")  # not kept in the repository: counts 0 without it
    log = [json.loads(l) for l in open(lp_)] if os.path.exists(lp_) else []
    rounds = len(g["class_chosen"])
    pr = {r: dict(clear=0, free=0, learn_ok=0, learn_refused=0, not_planned=0, lost=0, crowded=0)
          for r in range(rounds)}
    free_next = False
    for j in log:
        r = j.get("round")
        if r is None or r not in pr: continue
        if j["event"] == "plan" and str(j.get("then", "")).startswith("free space"):
            free_next = j.get("plan", {}).get("outcome") == "planned"
        elif j["event"] == "push":
            if j["phase"] == "clear" and j["executed"]:
                pr[r]["clear"] += 1
                if free_next: pr[r]["free"] += 1
            if j["phase"] == "learn":
                pr[r]["learn_ok" if j["executed"] else "learn_refused"] += 1
            free_next = False
        elif j["event"] == "fault" and j["fault"] in ("not-planned", "lost", "crowded"):
            pr[r][j["fault"].replace("-", "_")] += 1
    print(f"== {run}: c {g['mot_accuracy']:.3f}, singulation {g['singulation']:.2f}, "
          f"learn pushes {d['pushes_learn']}, clear {d['pushes_clear']}, faults {d['faults']}")
    alone = chosen_alone = n = 0
    for r in range(rounds):
        ch = g["class_chosen"][r]; gap = g["class_gap"][r]
        lp = g["class_learn_pushes"][r]
        a = sum(1 for x in lp if x.split(">")[1] == x.split(">")[0])
        ca = sum(1 for x in lp if x.split(">")[1] == ch)
        alone += a; chosen_alone += ca; n += len(lp)
        p = pr[r]
        print(f"  round {r}: chose {ch:10s} gap {gap:6.3f} {'SING' if gap >= 0.1 else '    '} "
              f"clear {p['clear']:2d} (free {p['free']}) learn {p['learn_ok']:2d} executed, "
              f"{p['learn_refused']} refused, {p['not_planned']} not planned, {p['lost']} lost; "
              f"alone {a}, chosen alone {ca}; class named {g['class_object'][r]}, "
              f"purity {g['class_purity'][r]:.2f}")
    for o in g["objects"]:
        print(f"  {o['name']:10s} learn pushes {o['learn_pushes']:2d}, yaw seen {o['yaw_range_deg']:5.0f} deg, "
              f"turn/push {o['turn_deg']:4.0f} deg, c {o['mot_accuracy']:.2f}")
        add("yaw " + o["name"], o["yaw_range_deg"]); add("lp " + o["name"], o["learn_pushes"])
        add("c " + o["name"], o["mot_accuracy"])
    add("c", g["mot_accuracy"]); add("argmax", g["argmax_accuracy"]); add("sing", g["singulation"])
    add("alone", alone / max(n, 1)); add("learn", d["pushes_learn"]); add("purity", g["purity"])
    add("ppc", g["pushes_per_cleared"])
    lad = {x["name"]: x["accuracy"] for x in g.get("oracle_ladder", {}).get("rungs", [])}
    for k in ("a0", "a", "a_alone", "b"):
        if k in lad: add(k, lad[k])
    print(f"  learn pushes moving the intended object alone {alone} of {n}, the chosen alone {chosen_alone}")
if len(sys.argv) > 2:
    print("== means, 95% t intervals over the runs")
    for k, v in tot.items():
        m, h = ci(v)
        print(f"  {k:18s} {m:8.3f} +- {h:.3f}   ({' '.join(f'{x:.3g}' for x in v)})")
