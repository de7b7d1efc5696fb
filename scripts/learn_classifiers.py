#!/usr/bin/python3
"""Learn's held-out classifiers compared on the same runs (session 39).

usage: scripts/learn_classifiers.py DIR SEED [SEED ...]   (MODE=quick by default; DIR may be
       given several times as DIR1:DIR2:... when the seeds' runs are split between directories)

Each run (scripts/experiment-learn's MODE-sSEED, read by scripts/learn_runs.py) scores the same
held-out views by every classifier on the same training views, so each pair is free of the
pushes' noise. Prints per seed the pooled words classifier (learn.json held_out_words.pooled),
the colour words alone (held_out_words.colour), the Mixture of Topics and argmax theta, then the
means, the paired difference colour - pooled with its 95 % t interval and on how many seeds it
is higher / lower, and per named object the two classifiers' means over the seeds.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import learn_runs  # noqa: E402
from oracle_ladder_table import ci  # noqa: E402


def find(dirs, mode, seed):
    for d in dirs:
        path = f"{d}/{mode}-s{seed}"
        if learn_runs.exists(path):
            return path
    raise SystemExit(f"no run of seed {seed} in {':'.join(dirs)}")


def main(dirs, seeds):
    mode = os.environ.get("MODE", "quick")
    rows = []
    per = {}
    for s in seeds:
        r = learn_runs.load(find(dirs, mode, s))
        w = r.json["held_out_words"]
        g = r.truth
        if "colour" not in w:
            raise SystemExit(f"seed {s}: no colour figure (a run without colour words?)")
        row = {"pooled": 100 * w["pooled"], "colour": 100 * w["colour"],
               "MoT": 100 * g["mot_accuracy"], "argmax": 100 * g["argmax_accuracy"]}
        rows.append(row)
        for o in w["objects"]:
            per.setdefault(o["name"], []).append((100 * o["pooled"], 100 * o["colour"]))
        print(f"s{s} pooled {row['pooled']:5.1f} colour {row['colour']:5.1f} "
              f"MoT {row['MoT']:5.1f} argmax {row['argmax']:5.1f}")
    for key in ("pooled", "colour", "MoT", "argmax"):
        v = [r[key] for r in rows]
        m, h = ci(v)
        print(f"{key:<7} mean {m:5.1f} +- {h:.1f}")
    d = [r["colour"] - r["pooled"] for r in rows]
    m, h = ci(d)
    print(f"colour - pooled: {m:+.1f} +- {h:.1f} (higher on {sum(x > 0 for x in d)}, lower on "
          f"{sum(x < 0 for x in d)} of {len(d)})")
    for name, pairs in per.items():
        p = sum(x for x, _ in pairs) / len(pairs)
        c = sum(y for _, y in pairs) / len(pairs)
        print(f"  {name:<10} pooled {p:5.1f} colour {c:5.1f} ({c - p:+.1f})")


if __name__ == "__main__":
    main(sys.argv[1].split(":"), sys.argv[2:])
