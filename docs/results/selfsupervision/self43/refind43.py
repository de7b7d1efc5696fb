#!/usr/bin/python3
"""Session 43 (rule-s43-refind-colour.md): what each colour re-find did, by the ground truth.
usage: refind43.py RUNS_DIR SEED...  (RUNS_DIR/motion-sS.json and its decisions.jsonl beside it,
RUNS_DIR/motion-sS/decisions.jsonl). For every "refound" event by colour: its round, distance,
and the round's next executed learn push as the ground truth saw it ("aimed>moved": the object
under the pushed blob > the objects that moved, SelfSupervisionScore's class_learn_pushes), and
whether it was aimed at the round's chosen object and at the object its class is named after.
Standard library only; reads, never writes."""
import json, re, sys

runs, seeds = sys.argv[1], [int(s) for s in sys.argv[2:]]
tot = {"refound": 0, "refind": 0, "aimed_chosen": 0, "aimed_named": 0, "no_push": 0}
dists = []
for s in seeds:
    j = json.load(open(f"{runs}/motion-s{s}.json"))
    g = j["ground_truth"]
    dec = [json.loads(x) for x in open(f"{runs}/motion-s{s}/decisions.jsonl") if x.strip()]
    executed = {}  # round -> learn pushes executed so far
    for e in dec:
        r = e.get("round")
        if e["event"] == "push" and e.get("phase") == "learn" and e.get("executed"):
            executed[r] = executed.get(r, 0) + 1
        if e["event"] == "refind" and e["why"].startswith("colour"):
            tot["refind"] += 1
            print(f"seed {s} round {r + 1}: not re-found ({e['why']})")
        if e["event"] == "refound" and e["why"].startswith("colour"):
            tot["refound"] += 1
            d = float(re.search(r"are ([0-9.]+) \(Hellinger\)", e["why"]).group(1))
            dists.append(d)
            k = executed.get(r, 0)  # the next executed learn push's index in its round
            pushes = g["class_learn_pushes"][r] if r < len(g["class_learn_pushes"]) else []
            nxt = pushes[k] if k < len(pushes) else None
            chosen, named = g["class_chosen"][r], g["class_object"][r]
            aimed = nxt.split(">")[0] if nxt else None
            tot["aimed_chosen"] += aimed == chosen
            tot["aimed_named"] += aimed == named
            tot["no_push"] += nxt is None
            print(f"seed {s} round {r + 1}: re-found at {d:.3f}; next learn push {nxt} "
                  f"(chosen {chosen}, class named {named or '-'})")
print(f"\n{tot['refound']} re-finds by colour ({tot['refind']} lost objects not re-found); the "
      f"next learn push aimed at the round's chosen object {tot['aimed_chosen']}, at its class's "
      f"named object {tot['aimed_named']}, no push after {tot['no_push']}")
if dists:
    dists.sort()
    print("distances: " + " ".join(f"{d:.3f}" for d in dists))
