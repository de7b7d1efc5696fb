"""Tables of scripts/experiment-mot: per seed, per object and over seeds.

usage: python3 scripts/mot_scatter_table.py OUT_DIR TUNE_SEED SEED...
Methods: argmax theta with merged topics; the supervised MoT on the E-step's theta (the thesis's;
smoothing 0, prior from the views); the supervised MoT on the word-posterior theta
(recognition::ThetaSource::kWordPosterior, same smoothing and prior); each object a mixture of
Dirichlets (MotOptions::components = 10, chosen by BIC) and one precision shared by the objects
(MotOptions::shared_precision), on either theta (from the grid's "model" key, absent before
2026-12-02); the unsupervised MoT.
TUNE_SEED's runs chose among the grid (printed, not counted); the other seeds are the report.
Figures: mean class accuracy; per object: recall; intervals: mean +- t(0.975, n-1) sd / sqrt(n).
"""
import json
import math
import statistics
import sys

out, tune, seeds = sys.argv[1], sys.argv[2], sys.argv[3:]
T975 = {1: 12.71, 2: 4.30, 3: 3.18, 4: 2.78, 5: 2.57, 6: 2.45, 7: 2.36, 8: 2.31, 9: 2.26}


def grid(run, theta, s=0.0, prior="views", model="dirichlet", components=10):
    """The grid point; a mixture's with at most `components` per object (files before
    2026-12-03 have only 10, unrecorded)."""
    for g in run["mot_grid"]:
        if (g["theta"] == theta and g["smoothing"] == s and g["prior"] == prior
                and g.get("model", "dirichlet") == model
                and (not model.startswith("mixture") or g.get("components", 10) == components)):
            return g
    raise KeyError((theta, s, prior, model, components))


def caps(run):
    """The mixtures' component caps in the grid other than 10 (--mot-grid-components)."""
    return sorted({g["components"] for g in run["mot_grid"]
                   if g.get("components", 10) != 10 and g.get("model", "").startswith("mixture")})


MOT = ["MoT, E-step theta", "MoT, word-posterior theta", "MoT mixture, E-step theta",
       "MoT mixture, word-posterior theta", "MoT shared precision, E-step theta",
       "MoT shared precision, word-posterior theta"]


def methods(run):
    out = {"argmax theta, merged": run["classes"], "MoT, E-step theta": run["mot"],
           "MoT, word-posterior theta": grid(run, "word-posterior")}
    if any("model" in g for g in run["mot_grid"]):
        for label, model in (("mixture", "mixture"), ("shared precision", "shared-precision")):
            out[f"MoT {label}, E-step theta"] = grid(run, "estep", model=model)
            out[f"MoT {label}, word-posterior theta"] = grid(run, "word-posterior", model=model)
    # Since the fifth round: the same fits classifying by the views' words
    # (topics::classify_mot_words), and the ceilings of the representation.
    for label, model in (("one Dirichlet", "dirichlet-words"), ("mixture", "mixture-words"),
                         ("shared precision", "shared-precision-words")):
        for theta, name in (("estep", "E-step"), ("word-posterior", "word-posterior")):
            try:
                out[f"MoT {label}, by words ({name} fit)"] = grid(run, theta, model=model)
            except KeyError:
                pass
    # Since 2026-12-03: the mixture with other component caps (--mot-grid-components).
    for k in caps(run):
        for theta, name in (("estep", "E-step"), ("word-posterior", "word-posterior")):
            out[f"MoT mixture of <= {k}, {name} theta"] = grid(run, theta, model="mixture",
                                                                components=k)
            out[f"MoT mixture of <= {k}, by words ({name} fit)"] = grid(
                run, theta, model="mixture-words", components=k)
    for c in run.get("ceilings", []):
        out[f"ceiling: {c['name']}"] = c
    if "mot_unsupervised" in run:
        out["MoT, unsupervised (C given)"] = run["mot_unsupervised"]
    return out


def recalls(c):
    return [row[i] / max(1, sum(row)) for i, row in enumerate(c["counts"])]


def interval(v):
    if len(v) < 2:
        return f"{v[0]:.1f}"
    m, s = statistics.mean(v), statistics.stdev(v)
    h = T975.get(len(v) - 1, 2.0) * s / math.sqrt(len(v))
    return f"{m:.1f} +- {h:.1f} (sd {s:.1f}; {min(v):.1f}-{max(v):.1f})"


for n in (3, 4):
    print(f"## {n} objects, T = 8")
    try:
        r = json.load(open(f"{out}/mot{n}-s{tune}.json"))["runs"][0]
    except FileNotFoundError:
        continue
    print(f"tuning seed {tune}: grid (mean class accuracy %):")
    for g in r["mot_grid"]:
        print(f"  {g['theta']:>14} s={g['smoothing']:<5} prior {g['prior']:<8} "
              f"{g.get('model', 'dirichlet'):<16} "
              f"{'<= ' + str(g['components']) if 'components' in g else '':<6} "
              f"{100 * g['mean_class_accuracy']:.1f}")
    for c in r.get("ceilings", []):
        print(f"  ceiling {c['name']:<24} {100 * c['mean_class_accuracy']:.1f}")
    table, per_object, bic, summed = {}, {}, [], {}
    names = None
    for s in seeds:
        try:
            run = json.load(open(f"{out}/mot{n}-s{s}.json"))["runs"][0]
        except FileNotFoundError:
            continue
        names = run["classes"]["rows"]
        for k, c in methods(run).items():
            table.setdefault(k, {})[s] = 100 * c["mean_class_accuracy"]
            per_object.setdefault(k, []).append([100 * x for x in recalls(c)])
            prev = summed.get(k)
            summed[k] = c["counts"] if prev is None else [
                [a + b for a, b in zip(ra, rb)] for ra, rb in zip(prev, c["counts"])]
        u = run.get("mot_unsupervised")
        if u is not None:
            bic.append((s, u["chosen_classes"], u.get("chosen_classes_per_object")))
    if not table:
        print("no report seed done\n")
        continue
    done = sorted(next(iter(table.values())).keys(), key=int)
    print("\n| method | " + " | ".join(f"seed {s}" for s in done) + " | mean +- 95% CI |")
    print("|---|" + "---|" * (len(done) + 1))
    for k, v in table.items():
        vals = [v[s] for s in done]
        print(f"| {k} | " + " | ".join(f"{x:.1f}" for x in vals) + f" | {interval(vals)} |")
    a = table["argmax theta, merged"]
    print()
    for k in (m for m in table if m.startswith("MoT") and "unsupervised" not in m):
        wins = sum(table[k][s] > a[s] for s in done)
        print(f"{k} above argmax on {wins} of {len(done)} seeds")
    print("\nper object, recall % (mean over the seeds, min-max):\n")
    print("| method | " + " | ".join(names) + " |")
    print("|---|" + "---|" * len(names))
    for k, rows in per_object.items():
        cols = list(zip(*rows))
        print(f"| {k} | " + " | ".join(
            f"{statistics.mean(c):.1f} ({min(c):.0f}-{max(c):.0f})" for c in cols) + " |")
    print("\nconfusion matrices summed over the report seeds (rows: true object):")
    for k in ("argmax theta, merged", "MoT, word-posterior theta",
              "MoT mixture, word-posterior theta", "MoT shared precision, word-posterior theta",
              "MoT mixture, by words (E-step fit)",
              *(k for k in summed if k.startswith("MoT mixture of <=") and "E-step fit" in k)):
        if k not in summed:
            continue
        print(f"{k}:\n" + " " * 12 + "".join(f"{x[:10]:>11}" for x in names))
        for label, row in zip(names, summed[k]):
            print(f"{label[:10]:>10}  " + "".join(f"{x:11d}" for x in row))
    print("\nBIC's C (all training views; per object alone):")
    for s, c, per in bic:
        print(f"  seed {s}: {c}; per object " + (str(per) if per is not None else "not recorded"))
    print()
