#!/usr/bin/python3
"""Paired comparison of two sets of `proprio learn` runs on the same seeds (session 26).

usage: scripts/learn_paired.py BASE_DIR OPTION_DIR SEED [SEED ...]   (MODE=quick by default)

BASE_DIR/OPTION_DIR hold scripts/experiment-learn's runs (MODE-sSEED/learn.json, read by
scripts/learn_runs.py). Prints per seed the held-out MoT by theta, argmax theta, pooled words,
per named object MoT / argmax %, the colour words alone when both sets scored it (session 39),
named objects given a class and the later learn pushes aimed at
another object than the turn chose (ground truth); then the means and the paired differences
(option - base) with 95 % t intervals (scripts/oracle_ladder_table.py's ci) and on how many seeds
the option is higher / lower, and the runs' median and longest wall time (MODE-sSEED.wall;
session 36); and the turns whose chosen blob was a moving distractor (ground truth
`class_chosen` neither a named object nor clutter) or an object an earlier turn had chosen
(repeats), summed over the seeds (session 37).
"""
import os
import statistics
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import learn_runs  # noqa: E402
from oracle_ladder_table import ci  # noqa: E402


def figures(run):
    r = learn_runs.load(run)
    j, g = r.json, r.truth
    w = j.get("held_out_words", {})
    chosen = dict(zip(j["classes"], g["class_chosen"]))
    later = [p for p in r.pushes if p["located"] != "chosen"]
    drift = sum(1 for p in later if p.get("intended") != chosen[p["class"]])
    truths = [o.get("truth", "") for o in j["objects"] if o["views"] > 0]
    named = sum(1 for o in g["objects"] if o["name"] in truths)
    per = " ".join(f"{o['name']} {100 * o['mot_accuracy']:.0f}/{100 * o['argmax_accuracy']:.0f}"
                   for o in g["objects"])
    table = r.table()
    distractor = repeat = 0
    seen = set()
    for c in g["class_chosen"]:
        if not c:
            continue
        if c not in table:
            distractor += 1
        elif c in seen:
            repeat += 1
        seen.add(c)
    return {"distractor": distractor, "repeat": repeat,
            "MoT": 100 * g["mot_accuracy"], "argmax": 100 * g["argmax_accuracy"],
            "pooled": 100 * w.get("pooled", 0), "named": named,
            "colour": 100 * w["colour"] if "colour" in w else None,
            "wall": r.wall(0.0),
            "drift": f"{drift}/{len(later)}", "per": per,
            "classes": ",".join(t or "-" for t in truths)}


def main(base, option, seeds):
    mode = os.environ.get("MODE", "quick")
    rows = []
    for s in seeds:
        b = figures(f"{base}/{mode}-s{s}")
        o = figures(f"{option}/{mode}-s{s}")
        rows.append((s, b, o))
        for name, f in (("base", b), ("option", o)):
            print(f"s{s} {name:<6} MoT {f['MoT']:5.1f} argmax {f['argmax']:5.1f} pooled "
                  f"{f['pooled']:5.1f} named {f['named']} drift {f['drift']:>5}  {f['per']}; "
                  f"{f['classes']}")
    keys = ["MoT", "argmax", "pooled", "named"]
    # The colour words alone (session 39), when both sets scored it.
    if all(r[1]["colour"] is not None and r[2]["colour"] is not None for r in rows):
        keys.insert(3, "colour")
    for key in keys:
        bv = [r[1][key] for r in rows]
        ov = [r[2][key] for r in rows]
        d = [o - b for b, o in zip(bv, ov)]
        m, h = ci(d)
        up = sum(1 for x in d if x > 0)
        down = sum(1 for x in d if x < 0)
        print(f"{key:<7} base {sum(bv) / len(bv):5.1f} option {sum(ov) / len(ov):5.1f} paired "
              f"(option - base) {' '.join(f'{x:+.1f}' for x in d)}: {m:+.1f} +- {h:.1f} "
              f"(higher on {up}, lower on {down} of {len(d)})")
    for name, i in (("base", 1), ("option", 2)):
        print(f"turns   {name:<6} on a distractor {sum(r[i]['distractor'] for r in rows)}, "
              f"repeats {sum(r[i]['repeat'] for r in rows)} ({len(rows)} runs)")
    for name, i in (("base", 1), ("option", 2)):
        walls = [r[i]["wall"] for r in rows]
        print(f"wall    {name:<6} median {statistics.median(walls):.1f} s, max {max(walls):.0f} s")


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2], sys.argv[3:])
