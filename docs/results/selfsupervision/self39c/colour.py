"""Session 39: c by theta (the MoT) and by the colour words alone on the same selfsupervise runs.

usage: /usr/bin/python3 colour.py DIR SEEDS [PREFIX]   (DIR holds PREFIX-sS.json of COLOUR=1
runs, PREFIX "motion" by default: an experiment-selfsup OUT; here: self39c SEEDS col)
Prints a markdown row per seed: the classes' objects, c, argmax, colour, colour - c, the
coverage ceiling (held-out views of objects some class of the model is named after: no
classifier scores above it), and per object c / colour; then the paired mean with a 95% t interval.
"""
import json
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "..",
                                "scripts"))
from oracle_ladder_table import ci  # noqa: E402


d, seeds = sys.argv[1], sys.argv[2].split()
prefix = sys.argv[3] if len(sys.argv) > 3 else "motion"
print("| seed | classes' objects | c (MoT) | argmax | colour | colour - c | ceiling |"
      " c per object | colour per object |")
print("|---|---|---|---|---|---|---|---|---|")
diffs = []
for s in seeds:
    j = json.load(open(f"{d}/{prefix}-s{s}.json"))
    g = j["ground_truth"]
    # Objects a class of the model (not a class dropped for want of views) is named after.
    named = {g["class_object"][j["classes"].index(c)] for c in j["model_classes"]}
    held = sum(o["held_out"] for o in g["objects"])
    ceiling = sum(o["held_out"] for o in g["objects"] if o["name"] in named) / held
    c, col = g["mot_accuracy"], g["colour_accuracy"]
    diffs.append(100 * (col - c))
    per = lambda k: " ".join(f"{100 * o[k]:.0f}" for o in g["objects"])
    print(f"| {s} | {', '.join(g['class_object'])} | {100 * c:.1f} | "
          f"{100 * g['argmax_accuracy']:.1f} | {100 * col:.1f} | {100 * (col - c):+.1f} | "
          f"{100 * ceiling:.0f} | {per('mot_accuracy')} | {per('colour_accuracy')} |")
m, h = ci(diffs)
print(f"\ncolour - c: {m:+.1f} +- {h:.1f} points (95% t), higher on "
      f"{sum(1 for x in diffs if x > 0)} of {len(diffs)} seeds, lower on "
      f"{sum(1 for x in diffs if x < 0)}")
print("objects:", ", ".join(o["name"] for o in g["objects"]))
