#!/usr/bin/python3
"""Session 34 (session 35: --field): are (d)'s claims right? For each round's last choice look of selfsupervise runs,
each learned class's claimed blob against the ground truth: the object under that blob
(ground_truth.class_blobs[round][blob]) and the object the class learned (class_object).

usage: claims.py [--field other_claimed_by] RUN.json [RUN.json ...]   (decisions.jsonl as the
JSON names it). --field: the scores' field read (claimed_by, the claims in use, by default;
other_claimed_by, session 35: the claims of the signal not in use, on the same looks).
Standard library only; a claim is "right" when the blob's object is the class's object; "at
random": the right claims expected if each class claimed a blob of its look drawn at random.
"""
import json
import os
import sys

field = "claimed_by"
args = sys.argv[1:]
if args[:1] == ["--field"]:
    field, args = args[1], args[2:]
right = wrong = 0
chance = 0.0  # expected right claims were each a blob drawn at random from its look
for path in args:
    j = json.load(open(path))
    g = j["ground_truth"]
    dec = j["decisions"]
    if not os.path.exists(dec):
        dec = os.path.join(os.path.splitext(path)[0], "decisions.jsonl")
    last = {}
    for line in open(dec):
        e = json.loads(line)
        if e.get("event") == "choose" and e.get("scores"):
            last[e["round"]] = e
    out = []
    for r, e in sorted(last.items()):
        blobs = g["class_blobs"][r]
        for s in e["scores"]:
            c = s.get(field, -1)
            if c is None or c < 0 or s["blob"] >= len(blobs):
                continue
            ok = blobs[s["blob"]] == g["class_object"][c]
            chance += sum(b == g["class_object"][c] for b in blobs) / len(blobs)
            right += ok
            wrong += not ok
            out.append("r%d:class%d(%s)->%s%s" % (r + 1, c + 1, g["class_object"][c],
                                                 blobs[s["blob"]] or "-", "" if ok else "(X)"))
    print(os.path.basename(os.path.dirname(path)) + "/" + os.path.basename(path), " ".join(out))
print(field + ": claims right %d, wrong %d; at random %.1f right expected" % (right, wrong, chance))
