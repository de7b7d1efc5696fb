#!/usr/bin/python3
"""Summary of a series (one OUT dir per seed, OUT/sN/motion-sN.json): means with 95% t intervals
over the seeds; learn pushes moving the intended / the round's chosen object alone (ground truth);
per object learn pushes and yaw range. usage: series.py DIR [DIR...] (each DIR a series: DIR/sN/motion-sN.json as scripts/experiment-selfsup
writes them one seed an OUT dir, or DIR/motion-sN.json as copied here; faults need the runs' decision logs)."""
import json, sys, math, glob, os
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "../../../../scripts"))
from oracle_ladder_table import ci  # mean and 95% t half-width over the seeds
for series in sys.argv[1:]:
    runs = sorted(glob.glob(os.path.join(series, "s*/motion-s*.json")) or glob.glob(os.path.join(series, "motion-s*.json")))
    rows = {}
    obj = {}
    faults = {}
    tot = [0, 0, 0]
    seeds = []
    for f in runs:
        d = json.load(open(f)); g = d["ground_truth"]
        seeds.append(os.path.basename(f)[8:-5])
        rung = {r["name"]: r["accuracy"] for r in g["oracle_ladder"]["rungs"]}
        n = a = ca = 0
        for r, lst in enumerate(g.get("class_learn_pushes", [])):
            ch = g["class_chosen"][r]
            for line in lst:
                i, m = line.split(">"); mv = m.split("+") if m else []
                n += 1; a += mv == [i]; ca += mv == [ch]
        tot[0] += n; tot[1] += a; tot[2] += ca
        vals = dict(c=g["mot_accuracy"], argmax=g["argmax_accuracy"], a_alone=rung["a_alone"],
                    purity=g["purity"], singulation=g["singulation"],
                    edge=g["pushes_per_cleared"], learn=d["pushes_learn"],
                    alone=a / max(n, 1), chosen_alone=ca / max(n, 1),
                    views=sum(d["views_per_class"]), above=float(g["mot_accuracy"] > g["argmax_accuracy"]))
        for k, v in vals.items(): rows.setdefault(k, []).append(v)
        for o in g["objects"]:
            obj.setdefault(o["name"], []).append((o["learn_pushes"], o["yaw_range_deg"], o["mot_accuracy"]))
        for fault, count in d.get("faults_by_kind", {}).items():
            faults[fault] = faults.get(fault, 0) + count
        if os.path.exists(f[:-5] + "/decisions.jsonl"):
            for j in open(f[:-5] + "/decisions.jsonl"):
                j = json.loads(j)
                if j["event"] == "fault": faults[j["fault"]] = faults.get(j["fault"], 0) + 1
    print(f"== {series}: seeds {' '.join(seeds)}")
    for k, v in rows.items():
        m, h = ci(v)
        per = " ".join(f"{x:.3f}" for x in v)
        print(f"{k:14s} {m:.3f} +- {h:.3f}   per seed: {per}")
    print(f"learn pushes moving the intended object alone: {tot[1]} of {tot[0]}; the round's chosen object alone: {tot[2]} of {tot[0]}")
    for name, v in obj.items():
        lp = ci([x[0] for x in v]); yr = ci([x[1] for x in v]); c = ci([x[2] for x in v])
        print(f"  {name:11s} learn pushes {lp[0]:.1f} +- {lp[1]:.1f}, yaw range {yr[0]:.0f} +- {yr[1]:.0f} deg, c {c[0]:.2f}")
    print("  faults (all seeds):", dict(sorted(faults.items())))
