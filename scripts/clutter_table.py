"""Tables of `proprio experiment clutter --json FILE` (thesis 8.2, Fig 8-3, Tables 8.1-8.2).

usage: /usr/bin/python3 scripts/clutter_table.py FILE
Per number of topics T: the supervised and unsupervised Mixture of Topics' held-out accuracy,
mean over seeds x fractions with a 95% interval over the seeds (each seed's mean over the
fractions; mean +- t(0.975, n-1) sd / sqrt(n)), the worst and best cell, the band (per fraction
the mean over seeds: its min and max); held-out pushes: the leave-one-trial-out diagnostic (each trial's own views
classified by a supervised MoT fitted to the other trials') and the other seeds' push views
(session 22: classified by each seed's supervised MoT), mean over seeds x fractions; per
planned push, why it was not executed (its last outcome) and every failed attempt's cause; per
object the supervised accuracy at T >= 15 (mean over
seeds x fractions x T); the pushes per object; the issue's target (T >= 15: mean >= 90%, worst
>= 80%). Session 23: with --mot-classifier other than theta, the classifier beside theta (eq 7.3)
on the same models at T >= 15: per seed, the paired difference with its 95% interval over the
seeds, per object.
"""
import json
import statistics
import sys
from collections import defaultdict

T975 = {1: 12.71, 2: 4.30, 3: 3.18, 4: 2.78, 5: 2.57, 6: 2.45, 7: 2.36, 8: 2.31, 9: 2.26}

d = json.load(open(sys.argv[1]))
o = d["options"]
objects = o["objects"]
cells = d["cells"]


def interval(values):
    if len(values) < 2:
        return ""
    m = statistics.mean(values)
    h = T975.get(len(values) - 1, 2.0) * statistics.stdev(values) / len(values) ** 0.5
    return f" +- {100 * h:.1f}"


def row(key, t):
    cs = [c for c in cells if c["topics"] == t]
    per_seed = defaultdict(list)
    per_fraction = defaultdict(list)
    for c in cs:
        per_seed[c["seed"]].append(c[key])
        per_fraction[c["fraction"]].append(c[key])
    seeds = [statistics.mean(v) for v in per_seed.values()]
    bands = [statistics.mean(v) for v in per_fraction.values()]
    vals = [c[key] for c in cs]
    return (f"{100 * statistics.mean(vals):.1f}{interval(seeds)} | {100 * min(vals):.1f} | "
            f"{100 * max(vals):.1f} | {100 * min(bands):.1f}-{100 * max(bands):.1f}")


def cross(t, key="cross_trial"):
    vals = [c[key] for c in cells if c["topics"] == t and c.get(key) is not None]
    if not vals:
        return "-"
    per_seed = defaultdict(list)
    for c in cells:
        if c["topics"] == t and c.get(key) is not None:
            per_seed[c["seed"]].append(c[key])
    seeds = [statistics.mean(v) for v in per_seed.values()]
    return f"{100 * statistics.mean(vals):.1f}{interval(seeds)}"


print("| T | supervised mean (95% over seeds) | worst | best | band | "
      "unsupervised mean | worst | best | band | pushes: other trial | pushes: other seeds |")
print("|---|---|---|---|---|---|---|---|---|---|---|")
for t in o["topics"]:
    print(f"| {t} | {row('supervised', t)} | {row('unsupervised', t)} | {cross(t)} | "
          f"{cross(t, 'cross_seed')} |")

# Why planned pushes were not executed (final outcome), and the failed attempts by cause.
print()
causes = ["not-planned", "robot-refused", "object-not-seen", "off-table"]
print("| object | planned | executed | " + " | ".join(f"not: {c}" for c in causes) +
      " | attempts made | failed attempts by cause |")
print("|---|---|---|" + "---|" * len(causes) + "---|---|")
for name in objects:
    ps = [p for p in d["pushes"] if p["object"] == name]
    out = defaultdict(int)
    failed = defaultdict(int)
    for p in ps:
        if not p["executed"]:
            out[p["outcome"]] += 1
        for f in p.get("failed", []):
            failed[f] += 1
    print(f"| {name} | {len(ps)} | {sum(p['executed'] for p in ps)} | " +
          " | ".join(str(out[c]) for c in causes) +
          f" | {sum(p.get('attempts', 1) for p in ps)} | " +
          ", ".join(f"{k} {v}" for k, v in sorted(failed.items())) + " |")

high = [c for c in cells if c["topics"] >= 15]
if high:
    print()
    for key in ("supervised", "unsupervised"):
        vals = [c[key] for c in high]
        print(f"T >= 15, {key}: mean {100 * statistics.mean(vals):.1f}%, worst "
              f"{100 * min(vals):.1f}% over {len(vals)} cells (target: mean >= 90%, worst >= 80%)")
    print()
    print("| object | pushes executed | moved it | training views (fraction 0.7) | "
          "renders, T >= 15 | per seed | other seeds' pushes, T >= 15 | per seed |")
    print("|---|---|---|---|---|---|---|---|")
    for i, name in enumerate(objects):
        ps = [p for p in d["pushes"] if p["object"] == name]
        views = [c["views_per_object"][i] for c in cells
                 if abs(c["fraction"] - 0.7) < 1e-9 and c["topics"] == o["topics"][0]]
        per_seed = defaultdict(list)
        for c in high:
            per_seed[c["seed"]].append(c["supervised_per_object"][i])
        seeds = [statistics.mean(v) for v in per_seed.values()]
        acc = statistics.mean(c["supervised_per_object"][i] for c in high)
        xs = defaultdict(list)
        for c in high:
            if c.get("cross_seed_per_object"):
                xs[c["seed"]].append(c["cross_seed_per_object"][i])
        xseeds = [statistics.mean(v) for v in xs.values()]
        xcol = (f"{100 * statistics.mean(xseeds):.1f}{interval(xseeds)} | "
                f"{' '.join(f'{100 * s:.0f}' for s in xseeds)}") if xseeds else "- | -"
        print(f"| {name} | {sum(p['executed'] for p in ps)} / {len(ps)} | "
              f"{sum(p['moved_intended'] for p in ps)} | {'/'.join(str(v) for v in views)} | "
              f"{100 * acc:.1f}{interval(seeds)} | "
              f"{' '.join(f'{100 * s:.0f}' for s in seeds)} | {xcol} |")

for which in ("best", "worst"):
    if which not in d:
        continue
    b = d[which]
    m = b["supervised"]
    print()
    print(f"{which}: fraction {b['fraction']}, T {b['topics']}, supervised, summed over the "
          f"seeds: {100 * m['accuracy']:.1f}% (rows: true object, % of its renders)")
    print()
    print("| | " + " | ".join(m["columns"]) + " |")
    print("|---|" + "---|" * len(m["columns"]))
    for r, counts in zip(m["rows"], m["counts"]):
        n = sum(counts) + m["unclassified"][m["rows"].index(r)]
        print(f"| {r} | " + " | ".join(f"{100 * x / n:.0f}" if n else "-" for x in counts) + " |")


# Session 23: the classifier (--mot-classifier) against theta on the same models, T >= 15.
paired = [c for c in cells if c["topics"] >= 15 and c.get("theta")]
if paired:
    name = o.get("mot_classifier", "theta")
    if name == "pooled":
        name += f" (w {o.get('mot_word_weight')})"
    print()
    print(f"T >= 15: supervised MoT by {name} against theta (eq 7.3), the same vocabulary, LDA and "
          "MoT (per seed: mean over fractions x T; difference: mean +- 95% interval over seeds)")
    print()
    print("| score | classifier | theta | difference | classifier per seed | theta per seed |")
    print("|---|---|---|---|---|---|")
    for label, key in (("renders", "supervised"), ("pushes: other trial", "cross_trial"),
                       ("pushes: other seeds", "cross_seed")):
        a = defaultdict(list)
        b = defaultdict(list)
        for c in paired:
            if c.get(key) is None or c["theta"].get(key) is None:
                continue
            a[c["seed"]].append(c[key])
            b[c["seed"]].append(c["theta"][key])
        if not a:
            continue
        sa = [statistics.mean(a[k]) for k in sorted(a)]
        sb = [statistics.mean(b[k]) for k in sorted(a)]
        diff = [x - y for x, y in zip(sa, sb)]
        print(f"| {label} | {100 * statistics.mean(sa):.1f}{interval(sa)} | "
              f"{100 * statistics.mean(sb):.1f}{interval(sb)} | "
              f"{100 * statistics.mean(diff):+.1f}{interval(diff)} | "
              f"{' '.join(f'{100 * x:.1f}' for x in sa)} | {' '.join(f'{100 * x:.1f}' for x in sb)} |")
    vals = [c["supervised"] for c in paired]
    tvals = [c["theta"]["supervised"] for c in paired]
    print()
    print(f"renders, {len(vals)} cells: classifier mean {100 * statistics.mean(vals):.1f}%, worst "
          f"{100 * min(vals):.1f}%; theta mean {100 * statistics.mean(tvals):.1f}%, worst "
          f"{100 * min(tvals):.1f}% (target: mean >= 90%, worst >= 80%)")
    print()
    print("| object | renders: classifier | theta | per seed (classifier / theta) | "
          "other seeds' pushes: classifier | theta |")
    print("|---|---|---|---|---|---|")
    for i, obj in enumerate(objects):
        a = defaultdict(list)
        b = defaultdict(list)
        xa = defaultdict(list)
        xb = defaultdict(list)
        for c in paired:
            a[c["seed"]].append(c["supervised_per_object"][i])
            b[c["seed"]].append(c["theta"]["supervised_per_object"][i])
            if c.get("cross_seed_per_object") and c["theta"].get("cross_seed_per_object"):
                xa[c["seed"]].append(c["cross_seed_per_object"][i])
                xb[c["seed"]].append(c["theta"]["cross_seed_per_object"][i])
        sa = [statistics.mean(a[k]) for k in sorted(a)]
        sb = [statistics.mean(b[k]) for k in sorted(a)]
        per = " ".join(f"{100 * x:.0f}/{100 * y:.0f}" for x, y in zip(sa, sb))
        if xa:
            xsa = [statistics.mean(xa[k]) for k in sorted(xa)]
            xsb = [statistics.mean(xb[k]) for k in sorted(xa)]
            xcol = (f"{100 * statistics.mean(xsa):.1f}{interval(xsa)} | "
                    f"{100 * statistics.mean(xsb):.1f}{interval(xsb)}")
        else:
            xcol = "- | -"
        print(f"| {obj} | {100 * statistics.mean(sa):.1f}{interval(sa)} | "
              f"{100 * statistics.mean(sb):.1f}{interval(sb)} | {per} | {xcol} |")
