#!/usr/bin/python3
"""Session 41: the geometry of selfsupervise's learn pushes. usage: learn_push_geom.py RUNS_DIR
(RUNS_DIR/motion-sS.json and motion-sS/decisions.jsonl for seeds 11-30). For each executed learn
push, whether its plan's target lies nearer another blob of the look before it than the pushed
blob's centre did ("toward"), by what the push moved (ground truth: alone, with others, drift =
aimed at another object than the round chose). Standard library only."""
import json, math, sys, collections
# For each executed learn push: the pushed blob's nearest other blob at the start and at the
# plan's target (the look before it), and what moved (ground truth, class_learn_pushes order).
stats = collections.Counter()
gaps = []
for s in range(11, 31):
    d = sys.argv[1]
    j = json.load(open(f"{d}/motion-s{s}.json")); g = j["ground_truth"]
    look = None
    per_round = collections.defaultdict(list)
    for l in open(f"{d}/motion-s{s}/decisions.jsonl"):
        e = json.loads(l)
        if e.get("event") == "look" and e.get("blobs"):
            look = e
        if e.get("event") == "push" and e.get("phase") == "learn" and e.get("executed") and look:
            p = e["plan"]; b = p["blob"]; blobs = look["blobs"]
            if b >= len(blobs): continue
            c = blobs[b]["centre"]; t = p["target"]
            others = [o["centre"] for k, o in enumerate(blobs) if k != b]
            if not others: continue
            d0 = min(math.dist(c, o) for o in others); d1 = min(math.dist(t, o) for o in others)
            per_round[e["round"]].append((d0, d1))
    for r, pushes in per_round.items():
        truth = g["class_learn_pushes"][r] if r < len(g["class_learn_pushes"]) else []
        chosen = g["class_chosen"][r]
        for (d0, d1), tr in zip(pushes, truth):
            it, mv = tr.split(">"); mv = mv.split("+") if mv else []
            kind = ("drift" if it != chosen else "alone" if mv == [it] else "with-others" if it in mv else "other")
            closer = d1 < d0
            stats[(kind, "toward" if closer else "away")] += 1
            gaps.append((kind, d1))
for k in sorted(stats): print(k, stats[k])
for kind in ("alone", "with-others", "drift"):
    v = sorted(x for kk, x in gaps if kk == kind)
    if v: print(kind, "target's nearest other blob, median m: %.3f" % v[len(v)//2], "n", len(v))
