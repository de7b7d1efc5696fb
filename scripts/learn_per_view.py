#!/usr/bin/python3
"""Learn's held-out figures on the same views, the pooled words classifier's two word
multinomials side by side (session 32): the views' pooled counts (learn.json held_out_words
"pooled") and every view weighing alike ("pooled_per_view", LearnOptions::mot_word_per_view).

usage: scripts/learn_per_view.py RUN_DIR SEED [SEED ...]   (MODE=quick by default)

RUN_DIR holds scripts/experiment-learn's runs (MODE-sSEED/learn.json, read by
scripts/learn_runs.py). Prints per seed the held-out MoT by theta, argmax theta, MoT by words,
pooled counts and pooled per view (%, with the Wilson 95 % interval of the pooled ones), per named
object the pooled counts / per view %, then the means over the seeds and the paired differences
(per view - counts; per view - MoT; per view - argmax) with 95 % t intervals
(scripts/oracle_ladder_table.py's ci) and the seeds each is lower on.
"""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import learn_runs  # noqa: E402
from oracle_ladder_table import ci  # noqa: E402


def wilson(k, n, z=1.96):
    if n == 0:
        return (0.0, 0.0)
    p = k / n
    d = 1 + z * z / n
    c = (p + z * z / (2 * n)) / d
    h = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / d
    return (max(0.0, c - h), min(1.0, c + h))


def main(run_dir, seeds):
    mode = os.environ.get("MODE", "quick")
    rows = []
    objects = {}
    for s in seeds:
        r = learn_runs.load(f"{run_dir}/{mode}-s{s}")
        j, g = r.json, r.truth
        w = j["held_out_words"]
        n = sum(o["held_out"] for o in w["objects"])
        f = {"MoT": 100 * g["mot_accuracy"], "argmax": 100 * g["argmax_accuracy"],
             "words": 100 * w["words"], "counts": 100 * w["pooled"],
             "per_view": 100 * w["pooled_per_view"]}
        rows.append(f)
        ic = wilson(round(w["pooled"] * n), n)
        iv = wilson(round(w["pooled_per_view"] * n), n)
        per = " ".join(f"{o['name']} {100 * o['pooled']:.0f}/{100 * o['pooled_per_view']:.0f}"
                       for o in w["objects"])
        for o in w["objects"]:
            objects.setdefault(o["name"], []).append((o["pooled"], o["pooled_per_view"],
                                                      o["held_out"]))
        print(f"s{s}: MoT {f['MoT']:5.1f} argmax {f['argmax']:5.1f} words {f['words']:5.1f} "
              f"pooled counts {f['counts']:5.1f} [{100 * ic[0]:.0f}-{100 * ic[1]:.0f}] "
              f"per view {f['per_view']:5.1f} [{100 * iv[0]:.0f}-{100 * iv[1]:.0f}] "
              f"(weight {w['weight']:.2f}, n {n}; counts/per view %: {per})")
    for key in ("MoT", "argmax", "words", "counts", "per_view"):
        v = [r[key] for r in rows]
        print(f"{key:<9} mean {sum(v) / len(v):5.1f} [{min(v):.1f}-{max(v):.1f} over seeds]")
    for name, v in objects.items():
        k_c = sum(round(c * n) for c, _, n in v)
        k_v = sum(round(p * n) for _, p, n in v)
        n = sum(n for _, _, n in v)
        ic, iv = wilson(k_c, n), wilson(k_v, n)
        print(f"  {name:<9} pooled counts {100 * k_c / max(n, 1):5.1f} % [{100 * ic[0]:.0f}-"
              f"{100 * ic[1]:.0f}], per view {100 * k_v / max(n, 1):5.1f} % [{100 * iv[0]:.0f}-"
              f"{100 * iv[1]:.0f}] (views pooled over the seeds, n {n})")
    for a, b in (("per_view", "counts"), ("per_view", "MoT"), ("per_view", "argmax"),
                 ("counts", "MoT")):
        d = [r[a] - r[b] for r in rows]
        m, h = ci(d)
        lower = sum(1 for x in d if x < 0)
        print(f"paired {a} - {b}: {' '.join(f'{x:+.1f}' for x in d)}: {m:+.1f} +- {h:.1f} "
              f"points, lower on {lower} of {len(d)} seeds")


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2:])
