#!/usr/bin/python3
"""Why pushes moved another object, from the simulator's contacts (`proprio evaluate push --json`
of session 19 or later: steps[].others[].parts / hit_by / resting_on, steps[].merged).

Each other object a push moved more than 5 mm gets one cause, the first that applies:
  transit   the arm touched it on the way to the start or back (touch = transit / return)
  jaws      the gripper's jaws touched it during the push (lowering, pushing, lifting)
  pusher    the pusher touched it (not the jaws)
  hand      the palm or another link touched it (not the jaws or the pusher)
  swept     no arm contact; the pushed object came into contact with it
  chain     no arm contact; only another (moved) object came into contact with it
  resting   no new contact; it was already touching an object the push moved
  none      no contact found (should not happen)
A table on which no other object moved but the intended one did not move either (the plan was
for a blob that was not on it) counts as no-move.
and, besides, `merged` when the other object held >= 10% of the pushed blob's features (the
path's cost ignored it). A table (executed, not only-intended) is counted under every cause of
its moved neighbours. Usage: others.py EVAL.json [...]"""
import collections
import json
import sys

CAUSES = ["transit", "jaws", "pusher", "hand", "swept", "chain", "resting", "none", "no-move"]


def cause(o, intended):
    if o.get("touch") in ("transit", "return"):
        return "transit"
    parts = o.get("parts", [])
    if o.get("touch") == "push":
        if "jaws" in parts:
            return "jaws"
        if "pusher" in parts:
            return "pusher"
        return "hand"
    hit = o.get("hit_by", [])
    if intended in hit:
        return "swept"
    if hit:
        return "chain"
    if o.get("resting_on"):
        return "resting"
    return "none"


for path in sys.argv[1:]:
    d = json.load(open(path))
    rows = [r for r in d["pushes"] if r["final_distance"] is not None]
    bad = [r for r in rows if not r["only_intended"]]
    by_table = collections.Counter()
    by_move = collections.Counter()
    big = collections.Counter()  # moved more than 2 cm
    merged = 0
    jaw_parts = collections.Counter()
    lines = []
    for r in bad:
        tags = set()
        descr = []
        for k, s in enumerate(r["steps"]):
            if not s["executed"]:
                continue
            for o in s.get("others", []):
                if o["moved"] <= 0.005:
                    continue
                c = cause(o, r["object"])
                tags.add(c)
                by_move[c] += 1
                if o["moved"] > 0.02:
                    big[c] += 1
                m = o["name"] in s.get("merged", [])
                merged += m
                if c in ("jaws", "pusher", "hand"):
                    jaw_parts["+".join(sorted(o.get("parts", [])))] += 1
                descr.append(f"step{k} {o['name']} {1000 * o['moved']:.0f}mm {c}"
                             f"{' merged' if m else ''}"
                             f" [{','.join(o.get('parts', []))}|{','.join(o.get('hit_by', []))}]")
        if not tags:  # no other object moved: the intended one did not move either
            tags.add("no-move")
            descr.append(r["outcome"])
        for t in tags:
            by_table[t] += 1
        lines.append(f"  seed {r['seed']} {r['object']}: " + "; ".join(descr))
    n = len(rows)
    print(f"{path}: executed {n}, only intended {n - len(bad)} ({100 * (n - len(bad)) / max(n, 1):.0f}%),"
          f" not only-intended {len(bad)}")
    print("\n".join(lines))
    print("  tables by cause: " + ", ".join(f"{c} {by_table[c]}" for c in CAUSES if by_table[c]))
    print("  moved neighbours by cause: " + ", ".join(f"{c} {by_move[c]}" for c in CAUSES if by_move[c])
          + f" (merged into the pushed blob: {merged})")
    print("  of them moved > 2 cm: " + ", ".join(f"{c} {big[c]}" for c in CAUSES if big[c]))
    print("  arm parts on arm-touched neighbours: " + ", ".join(f"{k} {v}" for k, v in jaw_parts.most_common()))
