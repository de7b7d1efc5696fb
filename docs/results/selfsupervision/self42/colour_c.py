#!/usr/bin/python3
"""Session 42's rule (rule-s42-colour-c.md): c by the colour words against the Mixture of Topics
on the same runs (CCOL: COLOUR=1), the defaults' runs (BASE) beside. usage: colour_c.py CCOL BASE
SEED... (CCOL/motion-sS.json, BASE/motion-sS.json). Standard library only."""
import json, math, sys

ccol, base, seeds = sys.argv[1], sys.argv[2], [int(s) for s in sys.argv[3:]]
T = {19: 2.093, 2: 4.303, 4: 2.776}


def ci(v):
    n = len(v); m = sum(v) / n
    if n < 2: return m, 0.0
    sd = math.sqrt(sum((x - m) ** 2 for x in v) / (n - 1))
    return m, T.get(n - 1, 2.0) * sd / math.sqrt(n)


def pushes(j):  # what the robot did: the ground truth's pushes and the classes' objects
    g = j["ground_truth"]
    return (g["class_learn_pushes"], g["class_chosen"], j["pushes_clear"], j["pushes_learn"])


names = ["calculator", "bike", "bottle", "giraffe"]
print("| seed | classes' objects | c (MoT) | colour | colour - c | ceiling | c, defaults (no colour words) | same pushes | c per object (calc, bike, bottle, giraffe) | colour per object |")
print("|---|---|---|---|---|---|---|---|---|---|")
gains, cs, cols, bases, same, per_c, per_col = [], [], [], [], 0, {n: [] for n in names}, {n: [] for n in names}
lower = 0
for s in seeds:
    a = json.load(open(f"{ccol}/motion-s{s}.json")); b = json.load(open(f"{base}/motion-s{s}.json"))
    g = a["ground_truth"]; c = 100 * g["mot_accuracy"]; col = 100 * g["colour_accuracy"]
    objs = {o["name"]: o for o in g["objects"]}
    ceiling = 100 * sum(1 for o in g["objects"] if o["classes"]) / len(g["objects"])
    sp = pushes(a) == pushes(b); same += sp
    gains.append(col - c); cs.append(c); cols.append(col); bases.append(100 * b["ground_truth"]["mot_accuracy"])
    lower += col < c
    for n in names:
        per_c[n].append(100 * objs[n]["mot_accuracy"]); per_col[n].append(100 * objs[n]["colour_accuracy"])
    print(f"| {s} | {', '.join(g['class_object'])} | {c:.2f} | {col:.2f} | {col - c:+.2f} | {ceiling:.0f} | "
          f"{bases[-1]:.2f} | {'yes' if sp else 'no'} | "
          + " ".join(f"{100 * objs[n]['mot_accuracy']:.0f}" for n in names) + " | "
          + " ".join(f"{100 * objs[n]['colour_accuracy']:.0f}" for n in names) + " |")
n = len(seeds)
for label, v in [("c (MoT, colour words)", cs), ("colour", cols), ("c, defaults", bases)]:
    m, h = ci(v); print(f"{label}: {m:.2f} +- {h:.2f}")
m, h = ci(gains)
print(f"paired colour - c: {m:+.2f} +- {h:.2f} (interval {m - h:+.2f} to {m + h:+.2f}), higher on "
      f"{sum(1 for x in gains if x > 0)}, lower on {lower} of {n}")
d = [x - y for x, y in zip(cs, bases)]; md, hd = ci(d)
print(f"c with colour words in the LDA - c of the defaults: {md:+.2f} +- {hd:.2f}; same pushes on {same} of {n} seeds")
print("per object, c -> colour (mean over seeds): " + ", ".join(
    f"{k} {sum(per_c[k]) / n:.1f} -> {sum(per_col[k]) / n:.1f}" for k in names))
ok1 = m >= 5 and m - h > 0; ok2 = lower <= 4
print(f"rule clauses: 1 {'held' if ok1 else 'FAILED'}, 2 {'held' if ok2 else 'FAILED'}; verdict: {'passed' if ok1 and ok2 else 'failed'}")
