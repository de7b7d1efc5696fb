"""Session 25: defaults against --repeat-tries 1 on the same seeds, and session 24's rule.

usage: python3 paired.py DEF REP [SEEDS] [LABEL]   (DEF/motion-sN.json or DEF-sN.json; SEEDS default
"2 3 4 5 6"; LABEL the option's name, default "--repeat-tries 1"; session 26 also "--repeat-later")
Prints per seed c, argmax, classes by ground-truth name, per-object c; means with 95% t
intervals; the paired difference (option minus defaults) and the rule's verdict; and where c
is lost (objects never learned, learned once, learned twice or more).
"""
import json
import os
import sys

# The mean and 95 % t half-width over seeds: the oracle ladder table's (one definition).
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "..", "scripts"))
from oracle_ladder_table import ci  # noqa: E402


def path(d, s):  # a run directory's motion-sN.json, or the committed copy d-sN.json
    p = f"{d}/motion-s{s}.json"
    return p if os.path.exists(p) else f"{d}-s{s}.json"


def load(d, s):
    return json.load(open(path(d, s)))


def main():
    a, b = sys.argv[1], sys.argv[2]
    seeds = (sys.argv[3] if len(sys.argv) > 3 else "2 3 4 5 6").split()
    seeds = [s for s in seeds if all(os.path.exists(path(d, s)) for d in (a, b))]
    option = sys.argv[4] if len(sys.argv) > 4 else "--repeat-tries 1"
    runs = {"defaults": [load(a, s) for s in seeds], option: [load(b, s) for s in seeds]}
    print(f"seeds {' '.join(seeds)}")
    for name, rows in runs.items():
        print(f"\n## {name}")
        print("| seed | c | argmax | classes (ground truth) | c per object: "
              + " / ".join(o["name"] for o in rows[0]["ground_truth"]["objects"]) + " | learn / clear pushes |")
        print("|---|---|---|---|---|---|")
        for s, r in zip(seeds, rows):
            g = r["ground_truth"]
            per = " / ".join(f"{100 * o['mot_accuracy']:.0f}" for o in g["objects"])
            print(f"| {s} | {100 * g['mot_accuracy']:.1f}% | {100 * g['argmax_accuracy']:.1f}% | "
                  f"{', '.join(g['class_object'])} | {per}% | {r['pushes_learn']} / {r['pushes_clear']} |")
        for key, label in [("mot_accuracy", "c"), ("argmax_accuracy", "argmax"), ("singulation", "singulation"),
                           ("purity", "purity")]:
            m, h = ci([100 * r["ground_truth"][key] for r in rows])
            print(f"{label}: {m:.1f} +- {h:.1f}")
        objs = {}
        for r in rows:
            for o in r["ground_truth"]["objects"]:
                objs.setdefault(o["name"], []).append(100 * o["mot_accuracy"])
        print("per object c, mean +- t: " + "; ".join(f"{k} {ci(v)[0]:.1f} +- {ci(v)[1]:.1f}" for k, v in objs.items()))
        distinct = [len(set(r["ground_truth"]["class_object"])) for r in rows]
        print(f"distinct objects learned per seed: {distinct}")
    d = [100 * (y["ground_truth"]["mot_accuracy"] - x["ground_truth"]["mot_accuracy"])
         for x, y in zip(runs["defaults"], runs[option])]
    m, h = ci(d)
    print(f"\npaired difference (option - defaults), points: {m:+.1f} +- {h:.1f}; per seed "
          + " ".join(f"{x:+.1f}" for x in d))
    ok = len(d) >= 5 and m - h > 0 and min(d) >= -10
    print(f"rule (mean > 0, interval above 0, no seed below -10 points, 5 seeds): "
          f"{'passes' if ok else 'fails'} (interval low {m - h:+.1f}, worst seed {min(d):+.1f})")
    for name, rows in runs.items():
        loss = {}
        for r in rows:
            g = r["ground_truth"]
            n = len(g["objects"])
            for o in g["objects"]:
                k = len(o["classes"])
                cat = "never learned" if k == 0 else ("learned twice+" if k > 1 else "learned once")
                loss.setdefault(cat, [0, 0.0])
                loss[cat][0] += 1
                loss[cat][1] += 100 * (1 - o["mot_accuracy"]) / n
        print(f"\nloss of c, {name} (objects over all seeds; points of c per seed):")
        for cat, (k, pts) in sorted(loss.items()):
            print(f"  {cat:15s} {k:3d} objects  {pts / len(rows):5.1f} points")
        # How each class that learned an object again came about (ground truth, for scoring):
        # its round chose a learned object; its first learn push already pushed a learned one; or
        # it drifted onto a learned one mid-round (the push's intended object changed).
        how, drift_rounds, rounds, drift_pushes, pushes = {}, 0, 0, 0, 0
        for r in rows:
            g = r["ground_truth"]
            seen = {}
            for k, obj in enumerate(g["class_object"]):
                lp = [x.split(">")[0] for x in g["class_learn_pushes"][k]]
                chosen = g["class_chosen"][k]
                if lp:
                    rounds += 1
                    drift_rounds += any(x != chosen for x in lp)
                    pushes += len(lp)
                    drift_pushes += sum(x != chosen for x in lp)
                if obj in seen:
                    cause = (("chose an object a drifting round learned" if seen[obj] else
                              "chose a learned object") if chosen == obj else
                             "first push on a learned object" if lp and lp[0] == obj else
                             "drifted onto it mid-round")
                    how[cause] = how.get(cause, 0) + 1
                else:
                    seen[obj] = chosen != obj  # learned by a round that chose another object
        print(f"  classes of an object learned before: {how}")
        print(f"  rounds whose learn pushes left the chosen object: {drift_rounds} of {rounds}; "
              f"learn pushes on another object than the chosen: {drift_pushes} of {pushes}")


main()
