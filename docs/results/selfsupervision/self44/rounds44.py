#!/usr/bin/python3
"""Session 44's rule (rule-s44-rounds-by-colour.md): the rounds judged by their looks' colours
(OPT) against the defaults (BASE) on the same seeds, paired; and what the rounds' colour
distances said against the ground truth.
usage: rounds44.py BASE OPT SEED...  (DIR/motion-sS.json and DIR/motion-sS/decisions.jsonl, or
the events saved as DIR/motion-sS-rounds.jsonl)
Standard library only."""
import json, math, statistics, sys

base, opt, seeds = sys.argv[1], sys.argv[2], [int(s) for s in sys.argv[3:]]
TS = {6: 2.571, 20: 2.093, 26: 2.060}  # 95 % t, n - 1 degrees of freedom (26: since session 48; 2.0 before)


def ci(v):
    m = statistics.mean(v)
    t = TS.get(len(v), 2.0)
    return m, t * statistics.stdev(v) / math.sqrt(len(v)) if len(v) > 1 else 0.0


def load(d, s):
    return json.load(open(f"{d}/motion-s{s}.json"))


def log(d, s):
    """The run's decision log, or its judge/distance/merge events as saved beside the JSON."""
    for p in (f"{d}/motion-s{s}/decisions.jsonl", f"{d}/motion-s{s}-rounds.jsonl"):
        try:
            return [json.loads(l) for l in open(p)]
        except FileNotFoundError:
            pass
    return []


fields = [("c (MoT)", lambda j: 100 * j["ground_truth"]["mot_accuracy"]),
          ("colour", lambda j: 100 * j["ground_truth"]["colour_accuracy"]),
          ("argmax", lambda j: 100 * j["ground_truth"]["argmax_accuracy"]),
          ("objects with a class", lambda j: sum(1 for o in j["ground_truth"]["objects"] if o["classes"])),
          ("rounds run", lambda j: len(j["ground_truth"]["round_object"])),
          ("pushes (clear + learn)", lambda j: j["pushes_clear"] + j["pushes_learn"]),
          ("singulation", lambda j: 100 * j["ground_truth"]["singulation"]),
          ("view purity", lambda j: 100 * j["ground_truth"]["purity"]),
          ("pushes per object cleared", lambda j: j["ground_truth"]["pushes_per_cleared"]),
          ("off the table", lambda j: j["ground_truth"]["off_table"])]
B = [load(base, s) for s in seeds]
O = [load(opt, s) for s in seeds]
print(f"seeds {seeds[0]}-{seeds[-1]} ({len(seeds)}), 95 % t intervals")
print("| figure | base | option | paired (option - base) | higher / lower |")
print("|---|---|---|---|---|")
res = {}
for name, f in fields:
    b = [f(j) for j in B]; o = [f(j) for j in O]
    d = [y - x for x, y in zip(b, o)]
    mb, hb = ci(b); mo, ho = ci(o); md, hd = ci(d)
    res[name] = (md, hd, sum(1 for x in d if x > 0), sum(1 for x in d if x < 0))
    print(f"| {name} | {mb:.2f} +- {hb:.2f} | {mo:.2f} +- {ho:.2f} | {md:+.2f} +- {hd:.2f} "
          f"({md - hd:+.2f} to {md + hd:+.2f}) | {res[name][2]} / {res[name][3]} |")
wb = statistics.median(j["seconds"] for j in B); wo = statistics.median(j["seconds"] for j in O)
print(f"median run: base {wb:.1f} s, option {wo:.1f} s ({100 * (wo / wb - 1):+.1f} %)")
names = ["calculator", "bike", "bottle", "giraffe"]
for key in ("mot_accuracy", "colour_accuracy"):
    per = lambda J, n: 100 * statistics.mean(
        next(o[key] for o in j["ground_truth"]["objects"] if o["name"] == n) for j in J)
    print(f"per object {key}, base -> option: " + ", ".join(f"{n} {per(B, n):.1f} -> {per(O, n):.1f}" for n in names))
print("per seed colour base/option (objects with a class): " + " ".join(
    f"{s}:{100 * b['ground_truth']['colour_accuracy']:.0f}/{100 * o['ground_truth']['colour_accuracy']:.0f}"
    f"({fields[3][1](b)}/{fields[3][1](o)})" for s, b, o in zip(seeds, B, O)))

# The option's round distances against the ground truth: a pair of rounds is "same" when the
# ground truth names one object as pushed most in both.
same, diff = [], []
print("\nper seed (option): rounds' objects by the ground truth; the judgement; the classes")
for s, j in zip(seeds, O):
    ro = j["ground_truth"]["round_object"]
    for e in log(opt, s):
        if e["event"] == "distance" and "merged" in e:
            a, b = e["merged"]
            if ro[a] and ro[b]:
                (same if ro[a] == ro[b] else diff).append(e["distance"])
    judges = [e.get("classes") for e in log(opt, s) if e["event"] == "judge"]
    print(f"  {s}: rounds {' '.join(o or '-' for o in ro)}; judged distinct after each round from "
          f"the 4th: {judges}; classes {j['ground_truth']['class_object']}")
same.sort(); diff.sort()
print(f"\nround-pair colour distances: {len(same)} pairs of one object, {len(diff)} of two")
for t in (0.1, 0.15, 0.2, 0.25, 0.3, 0.35, 0.4):
    f = lambda v: f"{sum(x < t for x in v)}/{len(v)}" if v else "-"
    print(f"  below {t:.2f}: one object {f(same)}, two objects {f(diff)}")
if len(seeds) == 20:
    cl = [res["objects with a class"][0] > 0, res["colour"][0] > 0, res["c (MoT)"][0] >= 0,
          wo <= 2 * wb]
    print("rule clauses: " + ", ".join(f"{i + 1} {'held' if c else 'FAILED'}" for i, c in enumerate(cl))
          + f"; verdict: {'passed' if all(cl) else 'failed'}")
else:
    g = [res["objects with a class"][0] > 0, res["colour"][0] >= 0]
    print(f"tuning gate: objects with a class {'held' if g[0] else 'FAILED'}, colour "
          f"{'held' if g[1] else 'FAILED'}")
