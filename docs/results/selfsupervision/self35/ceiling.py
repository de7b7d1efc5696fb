#!/usr/bin/python3
"""Session 35: of the claims claims.py counts (seeds 1, 7, 8 of each DIR/motion-sS.json), how many
classes had their object among the look's blobs at all, and the right claims of the classes whose
views are at least 75% pure (ground_truth.class_purity). usage: ceiling.py DIR [DIR ...]
"""
import json, os, sys
for lab in sys.argv[1:]:
    tot = present = right = 0; right_pure = tot_pure = 0
    for s in (1, 7, 8):
        p = f"{lab}/motion-s{s}.json"
        j = json.load(open(p)); g = j["ground_truth"]
        dec = j["decisions"]
        if not os.path.exists(dec): dec = os.path.join(os.path.splitext(p)[0], "decisions.jsonl")
        last = {}
        for line in open(dec):
            e = json.loads(line)
            if e.get("event") == "choose" and e.get("scores"): last[e["round"]] = e
        for r, e in last.items():
            blobs = g["class_blobs"][r]
            for sc in e["scores"]:
                c = sc.get("claimed_by", -1)
                if c is None or c < 0 or sc["blob"] >= len(blobs): continue
                tot += 1; obj = g["class_object"][c]
                present += obj in blobs; ok = blobs[sc["blob"]] == obj; right += ok
                if g["class_purity"][c] >= 0.75: tot_pure += 1; right_pure += ok
    print(lab, f"claims {tot}, class's object among the look's blobs {present}, right {right}; classes >=75% pure: {right_pure} of {tot_pure}")
