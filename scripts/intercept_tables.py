#!/usr/bin/python3
"""Markdown tables of docs/results/interception.md from the JSON of `proprio intercept [sweep]`.

Usage: scripts/intercept_tables.py DIR
DIR holds sweep/sweep.json and the runs' JSON named {learned,cv}-{both,energy,precision}-{n0,n15,n15r}.json
(the commands of the page's "Rerun" section). Prints the sweep table, the three priors' table and
Fig 3-11's interception choices.
"""

import json
import os
import sys


def summary(doc):
    """The summary object of a proprio.intercept document (its "summary", else the top level)."""
    return doc.get("summary", doc)


def fmt(x):
    """One decimal from 10 up, else two, as the page's tables."""
    if x == 0:
        return "0"
    return f"{x:.1f}" if abs(x) >= 10 else f"{x:.2f}"


def sweep_table(sweep):
    print("| model | noise (cm) | pixel std | loop | executed | mean miss (mm) | median (mm) |"
          " predicted std (mm) | miss / std | interception after plan (s) | plan ms mean / max |"
          " re-aims |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for r in sweep["rows"]:
        ratio = r["miss_over_predicted_sigma"]
        ratio_s = "-" if r["mean_predicted_sigma_mm"] < 0.005 else fmt(ratio)
        print(f"| {r['transition']} | {r['noise_cm']:g} | {r['sigma_px']:.2f} |"
              f" {'re-plan' if r['replan'] else 'open'} | {r['executed']}/{r['trials']} |"
              f" {fmt(r['mean_miss_mm'])} | {fmt(r['median_miss_mm'])} |"
              f" {fmt(r['mean_predicted_sigma_mm'])} | {ratio_s} |"
              f" {r['mean_intercept_time_s']:.3f} | {r['mean_plan_ms']:.2f} / {r['max_plan_ms']:.2f} |"
              f" {r['mean_reaims']:.1f} |")


def priors_table(d):
    print("| model | noise | loop | both | energy only | precision only |")
    print("|---|---|---|---|---|---|")
    for model, name in (("learned", "learned"), ("cv", "constant-velocity")):
        for run, noise, loop in (("n0", "0", "open"), ("n15", "1.5 cm", "open"),
                                 ("n15r", "1.5 cm", "re-plan")):
            cells = []
            for prior in ("both", "energy", "precision"):
                path = os.path.join(d, f"{model}-{prior}-{run}.json")
                if not os.path.exists(path):
                    cells.append("?")
                    continue
                s = summary(json.load(open(path)))
                cell = f"{fmt(s['mean_miss_mm'])} mm"
                if s["executed"] != s["trials"]:
                    cell += f" ({s['executed']}/{s['trials']})"
                cells.append(cell)
            print(f"| {name} | {noise} | {loop} | " + " | ".join(cells) + " |")


def choices(sweep):
    rows = {}
    for c in sweep["interception_choices"]:
        rows.setdefault((c["transition"], c["prior"]), {})[c["noise_cm"]] = c
    levels = sorted({c["noise_cm"] for c in sweep["interception_choices"]})
    print("| model | prior | " + " | ".join(f"{n:g} cm" for n in levels) + " |")
    print("|---|---|" + "---|" * len(levels))
    for (t, p), by in rows.items():
        cells = []
        for n in sorted(by):
            c = by[n]
            cells.append(f"{c['mean_intercept_time_s']:.2f} +- {c['std_intercept_time_s']:.2f}"
                         f" ({c['draws']})")
        print(f"| {t} | {p} | " + " | ".join(cells) + " |")


def main():
    d = sys.argv[1]
    sweep_path = os.path.join(d, "sweep", "sweep.json")
    if os.path.exists(sweep_path):
        sweep = json.load(open(sweep_path))
        sweep_table(sweep)
        print()
        choices(sweep)
        print()
    priors_table(d)


if __name__ == "__main__":
    main()
