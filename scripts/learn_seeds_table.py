#!/usr/bin/python3
"""Per-seed and per-object table of several sets of `proprio learn` runs (session 36).

usage: scripts/learn_seeds_table.py ROOT MODE SET[,SET...] SEED [SEED ...]

ROOT/SET holds scripts/experiment-learn's runs (MODE-sSEED/learn.json and MODE-sSEED.wall, read by
scripts/learn_runs.py).
Prints a Markdown table of the pooled held-out headline per seed (named objects given views in
brackets), then per set: the seeds' mean, per named object, the named objects with no view
(missed), executed pushes, views and the median wall time. Seeds without a run print "-".
"""
import os
import statistics
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import learn_runs  # noqa: E402

NAMES = ["book", "bottle", "cd", "giraffe"]


def figures(run):
    if not learn_runs.exists(run):
        return None
    r = learn_runs.load(run)
    j = r.json
    w = j["held_out_words"]
    truths = [o.get("truth", "") for o in j["objects"] if o["views"] > 0]
    per = {o["name"]: 100 * o["pooled"] for o in w["objects"]}
    return {"pooled": 100 * w["pooled"], "per": per,
            "named": sum(1 for n in per if n in truths),
            "pushes": sum(1 for p in r.pushes if p.get("executed")),
            "views": sum(o["views"] for o in j["objects"]),
            "wall": r.wall()}


def main(root, mode, sets, seeds):
    runs = {s: {seed: figures(f"{root}/{s}/{mode}-s{seed}") for seed in seeds} for s in sets}
    print("| seed | " + " | ".join(sets) + " |")
    print("|---" * (len(sets) + 1) + "|")
    for seed in seeds:
        cells = ["-" if runs[s][seed] is None else
                 f"{runs[s][seed]['pooled']:.1f} ({runs[s][seed]['named']})" for s in sets]
        print(f"| {seed} | " + " | ".join(cells) + " |")
    print()
    print("| setting | seeds | pooled mean | " + " | ".join(NAMES) +
          " | missed | executed pushes | views | median wall s |")
    print("|---" * 11 + "|")
    for s in sets:
        fs = [f for f in runs[s].values() if f]
        if not fs:
            continue
        per = " | ".join(f"{statistics.mean(f['per'][n] for f in fs):.1f}" for n in NAMES)
        print(f"| {s} | {len(fs)} | {statistics.mean(f['pooled'] for f in fs):.1f} | {per} | "
              f"{sum(4 - f['named'] for f in fs)} | {sum(f['pushes'] for f in fs)} | "
              f"{sum(f['views'] for f in fs)} | {statistics.median(f['wall'] for f in fs):.0f} |")


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2], sys.argv[3].split(","), sys.argv[4:])
