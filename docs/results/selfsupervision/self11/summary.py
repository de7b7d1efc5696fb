#!/usr/bin/python3
"""Means with 95% t intervals over selfsupervise run JSONs (one a seed): c, argmax, the ladder's
a0 and a, singulation, pushes per object moved to the edge, pushes moving only the intended
object, purity, and per object c (session 20, issue 19).

usage: summary.py RUN.json...
"""
import json
import math
import sys


def ci(v):
    n = len(v)
    m = sum(v) / n
    if n < 2:
        return m, 0.0
    sd = math.sqrt(sum((x - m) ** 2 for x in v) / (n - 1))
    t = {2: 12.71, 3: 4.30, 4: 3.18, 5: 2.78, 6: 2.57, 7: 2.45}.get(n, 2.0)
    return m, t * sd / math.sqrt(n)


def rung(g, name):
    for r in g.get("oracle_ladder", {}).get("rungs", []):
        if r["name"] == name:
            return r["accuracy"]
    return float("nan")


runs = [json.load(open(f))["ground_truth"] for f in sys.argv[1:]]
rows = [("c (MoT, the robot's own)", lambda g: g["mot_accuracy"], 100),
        ("argmax theta", lambda g: g["argmax_accuracy"], 100),
        ("a0 (ladder)", lambda g: rung(g, "a0"), 100),
        ("a (ladder)", lambda g: rung(g, "a"), 100),
        ("singulation", lambda g: g["singulation"], 100),
        ("pushes per object moved to the edge", lambda g: g["pushes_per_cleared"], 1),
        ("pushes moving only the intended object", lambda g: g["only_intended"], 100),
        ("training-view purity", lambda g: g["purity"], 100)]
for name, f, k in rows:
    v = [k * f(g) for g in runs]
    m, h = ci(v)
    print(f"{name:40s} {m:7.2f} +- {h:6.2f}   per seed: " + " ".join(f"{x:.1f}" for x in v))
above = sum(1 for g in runs if g["mot_accuracy"] > g["argmax_accuracy"])
print(f"c above argmax on {above} of {len(runs)} seeds")
names = [o["name"] for o in runs[0]["objects"]]
for i, name in enumerate(names):
    c = ci([100 * g["objects"][i]["mot_accuracy"] for g in runs])
    p = ci([g["objects"][i].get("learn_pushes", 0) for g in runs])
    y = ci([g["objects"][i].get("yaw_range_deg", 0) for g in runs])
    print(f"  {name:11s} c {c[0]:5.1f} +- {c[1]:5.1f}%  learn pushes {p[0]:4.1f} +- {p[1]:4.1f}"
          f"  yaw seen {y[0]:4.0f} +- {y[1]:4.0f} deg")
