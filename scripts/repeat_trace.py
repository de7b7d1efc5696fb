#!/usr/bin/python3
"""Why a learn turn chose an object an earlier turn had chosen: issue 21, session 37.

usage: scripts/repeat_trace.py [-v] RUN [RUN ...]

RUN is a `proprio learn` run directory (learn.json, decisions.jsonl), read by
scripts/learn_runs.py. Standard library only; reads, never writes. Ground truth from learn.json: ground_truth.class_chosen[k] (the object under
turn k's chosen blob), class_object (the object each class is named after), class_blobs[k] (the
object under each blob of turn k's choice look, by the choice's blob index) and the pushes'
`intended` / `moved` (simulation).

A turn k "repeats" when an earlier turn chose the same object X. It is "named" when an earlier
class j is named after X (a second class of a learned object: the coverage loss), else
"unnamed" (the earlier turn chose X but its pushes went mostly to another object, after which
its class is named). Each named repeat gets one cause, the first that holds over X's named
classes j (in this order):
  drifted-last   j's last executed push with views was aimed at another object: where j was
                 left (its last region, its place) is that object's, not X's;
  moved-later    X moved after j's turn (a push of a later turn moved it: aimed at what) before
                 turn k's choice: where j left it is stale;
  split          X is two candidates at turn k's choice and j's known blob is the other one;
  named-neighbour X still where j left it, but j's known blob at turn k is another object's
                 (by its region, or else top-down / where it was left);
  not-found      X still where j left it, j is not among turn k's known objects.
Over the named repeats it also counts whether the choice had another candidate (one skipped
only as less new: the choice's own score preferred the repeat) or none (forced), and why the blobs
showing an object no class is named after yet were skipped (known: an earlier class's place or
recognition claimed it; less-new; no-features; ...).
-v prints every repeat.
"""
import json
import os
import sys
from collections import Counter

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import learn_runs  # noqa: E402

ORDER = ["drifted-last", "moved-later", "split", "named-neighbour", "not-found"]
ALTERNATIVES = Counter()  # named repeats: did the choice have a candidate skipped as less-new?
UNCLASSED = Counter()  # named repeats: skip reasons of blobs showing an object with no class yet


def trace(r, verbose):
    """Turn count and the repeats of run `r` (learn_runs.Run): (cause, why, turn, object)."""
    g = r.truth
    chosen, blobs, named = g["class_chosen"], g["class_blobs"], g["class_object"]
    pushes = r.pushes
    cls_index = r.class_indices()
    # Each turn's first choice, and the classes whose regions named a candidate just before it.
    chooses, regions_known = {}, {}
    for k, turn in r.turns().items():
        first = turn.choices[0]
        chooses[k] = first.event
        regions_known[k] = {kn["object"] for kn in first.candidates.get("known", [])}
    first_push = {}
    for p in pushes:
        c = cls_index.get(p["class"])
        if c is not None and c not in first_push:
            first_push[c] = p["index"]
    out = []
    for k, x in enumerate(chosen):
        if k == 0 or not x or x not in chosen[:k]:
            continue
        earlier = [i for i in range(k) if named[i] == x]
        if not earlier:
            out.append(("unnamed", "", k, x))
            continue
        e = chooses.get(k, {})
        known = {kn["object"]: kn["blob"] for kn in e.get("known", [])}
        reasons = {}
        before = first_push.get(k, len(pushes))
        for i in earlier:
            mine = [p for p in pushes if cls_index.get(p["class"]) == i and p["executed"]
                    and p.get("views", 0) > 0]
            last = mine[-1] if mine else None
            if last is not None and last.get("intended") != x:
                reasons.setdefault("drifted-last", f"class {i + 1}'s last push #{last['index']} "
                                   f"aimed at {last.get('intended') or '?'}")
                continue
            after = last["index"] if last else -1
            movers = [p for p in pushes if after < p["index"] < before and p["executed"]
                      and x in p.get("moved", [])]
            if movers:
                m = movers[0]
                reasons.setdefault("moved-later", f"by #{m['index']} ({m['class']}, aimed at "
                                   f"{m.get('intended') or '?'})" +
                                   (f" and {len(movers) - 1} more" if len(movers) > 1 else ""))
                continue
            b = known.get(i)
            src = "region" if i in regions_known.get(k, set()) else "top-down/left"
            under = blobs[k][b] if b is not None and b < len(blobs[k]) else None
            if b is None:
                reasons.setdefault("not-found", f"class {i + 1} not known")
            elif under == x:
                reasons.setdefault("split", f"class {i + 1} known as blob {b}, also {x}")
            else:
                reasons.setdefault("named-neighbour", f"class {i + 1} known as blob {b}: "
                                   f"{under or 'nothing'} ({src})")
        cause = min(reasons, key=ORDER.index) if reasons else "not-found"
        # What else the choice had: candidates skipped only as less new than the repeat, and the
        # reasons the blobs of objects no class is named after yet were skipped for.
        skipped = {s["blob"]: s["reason"] for s in e.get("skipped", []) if s["blob"] >= 0}
        ALTERNATIVES["with a less-new alternative" if "less-new" in skipped.values()
                     else "no alternative (forced)"] += 1
        for b, o in enumerate(blobs[k]):
            if o and o != x and o not in named[:k] and b in skipped:
                UNCLASSED[skipped[b]] += 1
        out.append((cause, reasons.get(cause, ""), k, x))
    if verbose:
        for cause, why, k, x in out:
            print(f"{r.path}: turn {k + 1} chose {x}: {cause}: {why}")
    return len(chosen), out


def main(argv):
    verbose = "-v" in argv
    runs = [a for a in argv if a != "-v"]
    if not runs:
        print(__doc__)
        return 2
    turns, causes, per_run = 0, Counter(), []
    for run in runs:
        r = learn_runs.load(run)
        n, out = trace(r, verbose)
        turns += n
        causes.update(c for c, *_ in out)
        named = sum(1 for c, *_ in out if c != "unnamed")
        missed = sum(1 for o in r.truth["objects"] if o["views"] == 0)
        head = 100 * r.json["headline"]["accuracy"]
        wall = r.wall(float("nan"))
        # Events that mention known-place (branch repeat37's --known-places; a skip reason).
        places = sum(1 for e in r.events if '"known-place"' in json.dumps(e))
        per_run.append((run, n, len(out), named, missed, f"{head:.1f}", f"{wall:.0f}", places))
    print("run turns repeats named-repeats named-objects-missed headline% wall-s "
          "choices-with-known-place")
    for r in per_run:
        print(*r)
    k = len(per_run)
    print("mean: repeats %.2f, named repeats %.2f, missed %.2f, headline %.1f %%" % (
        sum(r[2] for r in per_run) / k, sum(r[3] for r in per_run) / k,
        sum(r[4] for r in per_run) / k, sum(float(r[5]) for r in per_run) / k))
    total = sum(causes.values())
    print(f"{len(runs)} runs, {turns} turns, {total} repeats "
          f"({total - causes['unnamed']} named, {causes['unnamed']} unnamed)")
    for c in ORDER + ["unnamed"]:
        print(f"  {c:16s} {causes[c]}")
    print("named repeats:", ", ".join(f"{v} {k}" for k, v in sorted(ALTERNATIVES.items())))
    print("at named repeats, blobs of objects no class was named after yet, skipped as:",
          ", ".join(f"{k} {v}" for k, v in UNCLASSED.most_common()))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
