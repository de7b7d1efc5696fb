#!/usr/bin/python3
"""What a learned class needs (session 27): per class of `proprio learn` runs, its object, pushes,
views, purity and how many of its object's held-out views it takes; per named object the same
summed over the classes named after it.

usage: scripts/learn_classes.py RUN_DIR [RUN_DIR ...]   (directories holding learn.json)

The runs are read by scripts/learn_runs.py.

Per class (learn.json ground truth): the object it is named after (class_object: its pushes'
target), the object its turn chose, its learn pushes as intended>moved, its views, its purity
(the share of its views showing the object it is named after) and, when that object is a named
(scored) one, the held-out views of it (20) the Mixture of Topics gives this class. Per named
object: classes named after it, executed pushes that moved it as the intended object, views of
those classes (and their views showing it: views x purity), held-out MoT / argmax %. Last, over
all runs given, the named objects' held-out MoT against the views showing them (buckets), to
show how many views a class needs.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import learn_runs  # noqa: E402


def run_rows(run):
    r = learn_runs.load(run)
    j, g = r.json, r.truth
    classes = j["classes"]
    named = [o["name"] for o in g["objects"]]
    conf = g["mot_confusion"]
    cols = [c.split(" ")[0] for c in conf["columns"]]
    print(f"== {run}: MoT {100 * g['mot_accuracy']:.1f} %, argmax {100 * g['argmax_accuracy']:.1f} %")
    per_object = {n: {"classes": 0, "views": 0, "pure_views": 0.0, "pushes": 0} for n in named}
    for m, c in enumerate(classes):
        o = j["objects"][m]
        truth = g["class_object"][m]
        took = ""
        if truth in named and c in cols:
            took = f"{conf['counts'][named.index(truth)][cols.index(c)]:2d}/20"
        purity = g["class_purity"][m] if m < len(g["class_purity"]) else 0.0
        pushes = g["class_learn_pushes"][m]
        print(f"  {c:<9} {truth or '-':<10} chosen {g['class_chosen'][m] or '-':<10} views "
              f"{o['views']:3d} purity {100 * purity:4.0f}% held-out taken {took:>5}  "
              f"pushes {' '.join(pushes)}")
        if truth in per_object and o["views"] > 0:
            d = per_object[truth]
            d["classes"] += 1
            d["views"] += o["views"]
            d["pure_views"] += o["views"] * purity
    for p in r.pushes:
        t = p.get("truth") or p
        if p["executed"] and t.get("moved_intended") and t.get("intended") in per_object:
            per_object[t["intended"]]["pushes"] += 1
    out = []
    for o in g["objects"]:
        d = per_object[o["name"]]
        print(f"  {o['name']:<8} classes {d['classes']} pushes {d['pushes']:2d} views {d['views']:3d} "
              f"showing it {d['pure_views']:5.0f}  held out MoT {100 * o['mot_accuracy']:3.0f} / "
              f"argmax {100 * o['argmax_accuracy']:3.0f} %")
        out.append((o["name"], d, 100 * o["mot_accuracy"]))
    return out


def main(runs):
    allrows = []
    for r in runs:
        allrows += run_rows(r)
    buckets = [(0, 1), (1, 20), (20, 40), (40, 80), (80, 10000)]
    print("held-out MoT of a named object against the views showing it (views x purity, summed "
          "over its classes), all runs:")
    for lo, hi in buckets:
        v = [a for _, d, a in allrows if lo <= d["pure_views"] < hi]
        if v:
            print(f"  views [{lo}, {hi}): {len(v):2d} objects, held-out MoT mean "
                  f"{sum(v) / len(v):5.1f} %  ({' '.join(f'{x:.0f}' for x in v)})")


if __name__ == "__main__":
    main(sys.argv[1:])
