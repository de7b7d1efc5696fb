#!/usr/bin/python3
"""The robot's singulation check against the ground truth, per round: the last look of (b) of
each round (decision log RUN/decisions.jsonl, event "look", phase "clear") gives the feature
hulls' verdict ("why" begins "feature hulls: 0 too near"; in older logs "too_near" == 0) and,
whenever the camera measured depth, the depth check's verdict ("why" ends in ": alone") and gap; the ground
truth is the round's gap after (b) (RUN.json, ground_truth.class_gap; alone: >= 10 cm).
With --at T the depth check's verdict is recomputed at clearance T from its logged gap (alone:
not merged and gap >= T; no gap logged and "none other": alone).
usage: check.py [--at T] RUN [RUN ...]   (RUN without .json)"""
import json, os, sys

args = sys.argv[1:]
at = None
if args and args[0] == "--at":
    at = float(args[1]); args = args[2:]

tab = {"hulls": [[0, 0], [0, 0]], "depth": [[0, 0], [0, 0]]}  # [said alone][truly alone]
for run in args:
    d = json.load(open(run + ".json")); g = d["ground_truth"]
    log = [json.loads(l) for l in open(os.path.join(run, "decisions.jsonl"))]
    last = {}
    for j in log:
        if j["event"] == "look" and j.get("phase") == "clear":
            last[j["round"]] = j
    print(f"== {run}: singulation {g['singulation']:.2f}, c {g['mot_accuracy']:.3f}")
    for r, gap in enumerate(g["class_gap"]):
        j = last.get(r)
        if j is None:
            print(f"  round {r}: no look of (b)"); continue
        truly = gap >= 0.1
        why = j.get("why", "")
        # the feature hulls' verdict: in "why" ("feature hulls: N too near; depth: ..."), in
        # older logs too_near (then the check that decided)
        said = (why.startswith("feature hulls: 0 too near") if why.startswith("feature hulls")
                else j.get("too_near", 1) == 0)
        depth = why.endswith(": alone") if why else None
        if at is not None and depth is not None and "depth:" in why:
            dg_ = j.get("gap", float("inf") if "none other" in why else None)
            depth = dg_ is not None and "lies on two footprints" not in why and dg_ >= at
        tab["hulls"][int(said)][int(truly)] += 1
        if depth is not None: tab["depth"][int(depth)][int(truly)] += 1
        dg = j.get("gap")
        print(f"  round {r}: truth gap {gap:6.3f} {'ALONE' if truly else 'near '}; hulls "
              f"{'alone' if said else 'not  '}; depth {'-' if depth is None else ('alone' if depth else 'not  ')} "
              f"(gap {'-' if dg is None else f'{dg:.3f}'}) {why}")
for k, t in tab.items():
    n = sum(map(sum, t))
    if n == 0: continue
    right = t[1][1] + t[0][0]
    print(f"{k:8s} check: said alone & truly alone {t[1][1]}, said alone & not {t[1][0]}, "
          f"said not & truly alone {t[0][1]}, said not & not {t[0][0]}; right {right} of {n}")
