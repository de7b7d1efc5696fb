"""The table, JSON and SVG plot of scripts/experiment-mot-topics (thesis Fig 7-9).

usage: python3 scripts/mot_topics_table.py OUT_DIR T...
Mean class accuracy per method and T: argmax theta (topics named by the labelled training views,
merged), supervised MoT, online-supervised MoT (half the views, then the other half by the 50:50
rule; with T*/online-r*.json (REPEATS > 1) the mean over the rule's draws, each draw listed in
the JSON's "online_runs" and the table giving mean +- t(0.975, n-1) sd / sqrt(n)), unsupervised MoT (k-means over theta with C given; each learned object named after the
majority class of its training views); when T*/mix.json exist (COMPONENTS > 1), the supervised
MoT with a mixture of Dirichlets per object as a fifth curve.
"""
import os
import collections
import csv
import glob
import json
import math
import statistics
import sys

out, topics = sys.argv[1], [int(t) for t in sys.argv[2:]]


def mca_of_csv(path, naming):
    right, total = collections.Counter(), collections.Counter()
    for row in csv.DictReader(open(path)):
        if not row["class"]:
            continue
        total[row["truth"]] += 1
        right[row["truth"]] += naming.get(row["class"], "") == row["truth"]
    return sum(right[c] / total[c] for c in total) / len(total), right, total


rows = []
for t in topics:
    d = f"{out}/T{t}"
    argmax = json.load(open(f"{d}/argmax.json"))["mapped"]["classes"]
    sup = json.load(open(f"{d}/sup.json"))["confusion"]
    # The 50:50 rule's draws: online.json (seed SEED), online-r2.json (SEED + 1), ...
    draws = [f"{d}/online.json"] + sorted(glob.glob(f"{d}/online-r*.json"),
                                          key=lambda f: int(f.rsplit("-r", 1)[1][:-5]))
    online_runs = [json.load(open(f))["confusion"]["mean_class_accuracy"] for f in draws]
    votes = collections.defaultdict(collections.Counter)
    for row in csv.DictReader(open(f"{d}/unsup-train.csv")):
        if row["class"]:
            votes[row["class"]][row["truth"]] += 1
    naming = {o: v.most_common(1)[0][0] for o, v in votes.items()}
    unsup, _, _ = mca_of_csv(f"{d}/unsup.csv", naming)
    rows.append({"topics": t, "argmax": argmax["mean_class_accuracy"],
                 "supervised": sup["mean_class_accuracy"],
                 "online": statistics.mean(online_runs), "online_runs": online_runs,
                 "unsupervised": unsup,
                 "argmax_confusion": argmax, "supervised_confusion": sup})
    if os.path.exists(f"{d}/mix.json"):
        mix = json.load(open(f"{d}/mix.json"))["confusion"]
        rows[-1].update({"mixture": mix["mean_class_accuracy"], "mixture_confusion": mix})
classes = len(rows[0]["supervised_confusion"]["rows"])
json.dump({"format": "proprio.experiment.mot_topics", "chance": 1 / classes, "rows": rows},
          open(f"{out}/fig7-9.json", "w"), indent=1)

methods = [("supervised", "supervised MoT", "#1f77b4"), ("online", "online-supervised MoT", "#2ca02c"),
           ("unsupervised", "unsupervised MoT", "#d62728"), ("argmax", "argmax theta", "#7f7f7f")]
if all("mixture" in r for r in rows):
    methods.insert(1, ("mixture", "supervised MoT, mixture", "#9467bd"))
print("T   " + "  ".join(f"{m[1]:>22}" for m in methods))
for r in rows:
    print(f"{r['topics']:<3} " + "  ".join(f"{100 * r[m[0]]:21.1f}%" for m in methods))
T975 = {1: 12.71, 2: 4.30, 3: 3.18, 4: 2.78, 5: 2.57, 6: 2.45, 7: 2.36, 8: 2.31, 9: 2.26}
if any(len(r["online_runs"]) > 1 for r in rows):
    print("\nonline-supervised MoT over the 50:50 rule's draws (mean +- t(0.975, n-1) sd / sqrt(n); "
          "supervised - online):")
    for r in rows:
        v = [100 * a for a in r["online_runs"]]
        if len(v) < 2:
            continue
        m, s = statistics.mean(v), statistics.stdev(v)
        h = T975.get(len(v) - 1, 2.0) * s / math.sqrt(len(v))
        print(f"T = {r['topics']:<3} {len(v)} draws: {m:.1f} +- {h:.1f} (sd {s:.1f}; "
              f"{min(v):.1f}-{max(v):.1f}); supervised {100 * r['supervised']:.1f}, "
              f"difference {100 * r['supervised'] - m:+.1f} +- {h:.1f}")
best = max(rows, key=lambda r: r["supervised"])
print(f"chance {100 / classes:.1f}%; best supervised MoT {100 * best['supervised']:.1f}% at "
      f"T = {best['topics']}")
for name in [m[0] for m in methods if m[0] in ("supervised", "mixture", "argmax")]:
    r = max(rows, key=lambda r: r[name])
    c = r[f"{name}_confusion"]
    print(f"\n{name} at T = {r['topics']} (rows: truth)")
    print("              " + " ".join(f"{x[:6]:>6}" for x in c["columns"]))
    for label, counts in zip(c["rows"], c["counts"]):
        print(f"{label[:12]:>12}  " + " ".join(f"{n:6d}" for n in counts))

# The plot: accuracy (%) against T, one polyline per method, chance dashed.
w, h, left, bottom, top, right = 640, 400, 60, 50, 20, 190
tmax = max(topics)
x = lambda t: left + (w - left - right) * (t - min(topics)) / max(1, tmax - min(topics))
y = lambda a: top + (h - top - bottom) * (1 - a)
svg = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" font-family="sans-serif" '
       'font-size="12">', f'<rect width="{w}" height="{h}" fill="white"/>']
for a in (0, 0.2, 0.4, 0.6, 0.8, 1.0):
    svg.append(f'<line x1="{left}" x2="{w - right}" y1="{y(a)}" y2="{y(a)}" stroke="#ddd"/>')
    svg.append(f'<text x="{left - 8}" y="{y(a) + 4}" text-anchor="end">{int(100 * a)}%</text>')
for t in topics:
    svg.append(f'<text x="{x(t)}" y="{h - bottom + 18}" text-anchor="middle">{t}</text>')
svg.append(f'<text x="{(left + w - right) / 2}" y="{h - 10}" text-anchor="middle">topics T</text>')
svg.append(f'<line x1="{left}" x2="{w - right}" y1="{y(1 / classes)}" y2="{y(1 / classes)}" '
           'stroke="black" stroke-dasharray="4 4"/>')
for i, (key, label, colour) in enumerate(methods):
    pts = " ".join(f"{x(r['topics']):.1f},{y(r[key]):.1f}" for r in rows)
    svg.append(f'<polyline points="{pts}" fill="none" stroke="{colour}" stroke-width="2"/>')
    svg.append(f'<text x="{w - right + 10}" y="{top + 20 + 18 * i}" fill="{colour}">{label}</text>')
svg.append(f'<text x="{w - right + 10}" y="{top + 20 + 18 * len(methods)}">- - chance</text>')
svg.append("</svg>")
open(f"{out}/fig7-9.svg", "w").write("\n".join(svg) + "\n")
