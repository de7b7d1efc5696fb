#!/usr/bin/python3
"""Are (d)'s claims right? (issue 19; sessions 34-36: one script for all three.) For each
round's last choice look of `proprio selfsupervise` runs, each learned class's claimed blob
against the ground truth: the object under that blob (ground_truth.class_blobs[round][blob])
and the class's object.

usage: selfsup_claims.py [--field other_claimed_by] [--against chosen] RUN.json [RUN.json ...]
(decisions.jsonl as the JSON names it, or RUN/decisions.jsonl beside it).
--field: the scores' field read (claimed_by, the claims in use, by default; other_claimed_by,
session 35: the claims of another signal on the same looks, `--other-claims-by` since session 36).
--against: the class's object a claim must be on: "named" (the default, sessions 34 and 35:
ground_truth.class_object, the object the class's pushes moved most) or "chosen" (session 36: the
object under the blob its own round chose at its last choice look, i.e. what the class's first
look showed; it differs from "named" when the round drifted onto another object) or "looks"
(session 36: any object making at least 20% of the class's tracked blob in some look of its
round, ground_truth.class_learn_blobs: right when the claim is on an object its looks held).
A claim is "right" when the blob's object is that object; "at random": the right claims expected
if each class claimed a blob of its look drawn at random. Standard library only.
"""
import json
import os
import sys

field = "claimed_by"
against = "named"
args = sys.argv[1:]
while args[:1] in (["--field"], ["--against"]):
    if args[0] == "--field":
        field = args[1]
    else:
        against = args[1]
        if against not in ("named", "chosen", "looks"):
            sys.exit("selfsup_claims.py: --against named|chosen|looks")
    args = args[2:]
if not args:
    sys.exit(__doc__)
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
        if e.get("event") == "choose" and e.get("blob") is not None:
            last.setdefault(e["round"], {})["chosen"] = e["blob"]
            if e.get("scores"):
                last[e["round"]]["scored"] = e
    # The object each class's round chose (its last choice), by the ground truth.
    chosen = {}
    for r, d in last.items():
        blobs = g["class_blobs"][r] if r < len(g["class_blobs"]) else []
        b = d.get("chosen", -1)
        chosen[r] = blobs[b] if 0 <= b < len(blobs) else None
    # The objects each class's looks held (>= 20% of its tracked blob in some look).
    held = {}
    for r, looks in enumerate(g.get("class_learn_blobs", [])):
        objs = set()
        for blob in looks or []:
            for part in (blob or "").split("+"):
                name, _, share = part.partition(":")
                if name and share and float(share) >= 0.2:
                    objs.add(name)
        held[r] = objs
    out = []
    for r, d in sorted(last.items()):
        e = d.get("scored")
        if e is None:
            continue
        blobs = g["class_blobs"][r]
        for s in e["scores"]:
            c = s.get(field, -1)
            if c is None or c < 0 or s["blob"] >= len(blobs):
                continue
            if against == "looks":
                objs = held.get(c, set())
                obj = "+".join(sorted(objs)) or None
                ok = blobs[s["blob"]] in objs
                chance += sum(b in objs for b in blobs) / len(blobs)
            else:
                obj = g["class_object"][c] if against == "named" else chosen.get(c)
                ok = obj is not None and blobs[s["blob"]] == obj
                chance += sum(b == obj for b in blobs) / len(blobs)
            right += ok
            wrong += not ok
            out.append("r%d:class%d(%s)->%s%s" % (r + 1, c + 1, obj, blobs[s["blob"]] or "-",
                                                 "" if ok else "(X)"))
    print(os.path.basename(os.path.dirname(path)) + "/" + os.path.basename(path), " ".join(out))
print(field + ": claims right %d, wrong %d; at random %.1f right expected" % (right, wrong, chance))
