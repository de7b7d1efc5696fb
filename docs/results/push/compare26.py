#!/usr/bin/python3
"""Session 26: per table, what a candidate changes against a baseline (`proprio evaluate push
--json` files of the same seeds). Each table whose outcome, only-intended flag or final distance
(by more than 2 mm) differs is listed with both sides' pushes and, for a table that moved another
object, the cause of each moved neighbour (others.py's classes); then counts and per object.
Usage: compare26.py BASE.json CANDIDATE.json  (run from the repository root; stdlib only)."""
import json
import sys
from collections import defaultdict

sys.path.insert(0, 'docs/results/push')
from summarise import median  # noqa: E402


def cause(o, intended):
    if o.get("touch") in ("transit", "return"):
        return "transit"
    parts = o.get("parts", [])
    if o.get("touch") == "push":
        return "jaws" if "jaws" in parts else "pusher" if "pusher" in parts else "hand"
    hit = o.get("hit_by", [])
    return "swept" if intended in hit else "chain" if hit else "resting" if o.get("resting_on") else "none"


def moved(r):
    out = []
    for k, s in enumerate(r.get("steps", [])):
        if not s["executed"]:
            continue
        for o in s.get("others", []):
            if o["moved"] > 0.005:
                out.append(f"step{k} {o['name']} {1000 * o['moved']:.0f}mm {cause(o, r['object'])}")
    return out


def desc(r):
    if r['final_distance'] is None:
        return f"{r['outcome']}: {r['message'][:150]}"
    steps = r.get('steps', [])
    plans = ','.join(s.get('plan', '?') for s in steps)
    return (f"{1000 * r['final_distance']:.0f} mm, {r.get('pushes', 1)} push(es) [{plans}], "
            f"only {'yes' if r['only_intended'] else 'no'}"
            + (f" ({'; '.join(moved(r))})" if not r['only_intended'] else ""))


A = {r['seed']: r for r in json.load(open(sys.argv[1]))['pushes']}
B = {r['seed']: r for r in json.load(open(sys.argv[2]))['pushes']}
counts = defaultdict(int)
for s in sorted(set(A) & set(B)):
    a, b = A[s], B[s]
    ea, eb = a['final_distance'] is not None, b['final_distance'] is not None
    if ea and not eb:
        k = 'executed -> not executed' + (' (was only intended)' if a['only_intended'] else ' (was not only intended)')
    elif eb and not ea:
        k = 'not executed -> executed'
    elif not ea:
        continue
    elif a['only_intended'] != b['only_intended']:
        k = 'only intended gained' if b['only_intended'] else 'only intended lost'
    elif abs(b['final_distance'] - a['final_distance']) > 0.002:
        k = 'closer by > 2 mm' if b['final_distance'] < a['final_distance'] else 'farther by > 2 mm'
    else:
        counts['same (within 2 mm, same flags)'] += 1
        continue
    counts[k] += 1
    print(f"{s:4d} {a['object']:13s} {k}\n      base: {desc(a)}\n      cand: {desc(b)}")
print("counts: " + ", ".join(f"{k} {v}" for k, v in sorted(counts.items())))
both = [s for s in A if s in B and A[s]['final_distance'] is not None and B[s]['final_distance'] is not None]
print(f"tables both executed {len(both)}: median base {1000 * median([A[s]['final_distance'] for s in both]):.0f} mm, "
      f"cand {1000 * median([B[s]['final_distance'] for s in both]):.0f} mm")
