#!/usr/bin/python3
"""Session 45: why a run learned fewer than its C objects, round by round, by the ground truth.
For each round: the object under the blob it chose (class_chosen), the object its pushes moved
most (round_object), its views and stop reason, and one of: ok-new (a new object chosen and
pushed), chose-learned (the chosen object already had a class), drift-to-new / drift-to-learned
(another object than the chosen one was pushed most), no-views; beside it, the last choice
look's claims (object under each blob : claiming class : distance to its nearest class). Rounds
are listed for runs with fewer than C objects with a class; totals at the end, and the later
rounds' outcomes by whether the round chose once or again (after losing its object in (b)).
usage: cover45.py RUN.json ...  (RUN/decisions.jsonl beside each). Standard library only."""
import collections
import json
import sys

cause = collections.Counter()
by_choices = collections.Counter()
for path in sys.argv[1:]:
    d = json.load(open(path))
    g = d["ground_truth"]
    ev = [json.loads(x) for x in open(path[:-len(".json")] + "/decisions.jsonl")]
    chosen, ro = g["class_chosen"], g["round_object"]
    learned, lines = set(), []
    for r in range(len(ro)):
        chooses = [e for e in ev if e["event"] == "choose" and e.get("round") == r]
        if chosen[r] in learned:
            why = "chose-learned"
        elif not ro[r]:
            why = "no-views"
        elif ro[r] != chosen[r]:
            why = "drift-to-learned" if ro[r] in learned else "drift-to-new"
        else:
            why = "ok-new"
        claim = ""
        if chooses and chooses[-1].get("scores"):
            blobs = g["class_blobs"][r]
            claim = " ".join(
                f"{blobs[x['blob']] if x['blob'] < len(blobs) else '?'}:{x.get('claimed_by')}:"
                f"{x.get('nearest', 0):.2f}" for x in chooses[-1]["scores"])
        cause[why] += 1
        if r > 0:
            by_choices[("chose again" if len(chooses) > 1 else "chose once", why.split("-to")[0])] += 1
        lines.append(f"  r{r} chose {chosen[r]} pushed-most {ro[r]} views {d['views_per_class'][r]}"
                     f" stop '{d['stop_reasons'][r]}' -> {why} | {claim}")
        if ro[r]:
            learned.add(ro[r])
    n = len(set(x for x in g["class_object"] if x))
    print(f"{path}: objects with a class {n}")
    if n < len(g["objects"]):
        print("\n".join(lines))
print("rounds:", dict(cause))
print("later rounds by choices:", {" / ".join(k): v for k, v in sorted(by_choices.items())})
