#!/usr/bin/python3
"""Session 42's rules 2 and 3: one setting (OPT) against another (BASE) on the same seeds, paired.
usage: paired42.py model|depth BASE OPT SEED...  (BASE/motion-sS.json, OPT/motion-sS.json)
model: rule-s42-colour-model.md (c; BASE SIFT words, OPT colour words); depth:
rule-s42-depth-alone.md (singulation, colour, c). Standard library only."""
import json, math, statistics, sys

rule, base, opt, seeds = sys.argv[1], sys.argv[2], sys.argv[3], [int(s) for s in sys.argv[4:]]
T = 2.093  # 95 %, 19 degrees of freedom (20 seeds)


def ci(v):
    m = statistics.mean(v)
    return m, (T if len(v) == 20 else 2.0) * statistics.stdev(v) / math.sqrt(len(v))


def load(d, s):
    return json.load(open(f"{d}/motion-s{s}.json"))


def acts(j):
    g = j["ground_truth"]
    return (g["class_learn_pushes"], g["class_chosen"], j["pushes_clear"], j["pushes_learn"])


fields = [("c (MoT)", lambda j: 100 * j["ground_truth"]["mot_accuracy"]),
          ("colour", lambda j: 100 * j["ground_truth"].get("colour_accuracy", float("nan"))),
          ("argmax", lambda j: 100 * j["ground_truth"]["argmax_accuracy"]),
          ("singulation", lambda j: 100 * j["ground_truth"]["singulation"]),
          ("objects with a class", lambda j: sum(1 for o in j["ground_truth"]["objects"] if o["classes"])),
          ("view purity", lambda j: 100 * j["ground_truth"]["purity"]),
          ("only the intended object moved", lambda j: 100 * j["ground_truth"]["only_intended"]),
          ("pushes per object cleared", lambda j: j["ground_truth"]["pushes_per_cleared"]),
          ("off the table", lambda j: j["ground_truth"]["off_table"])]
B = [load(base, s) for s in seeds]
O = [load(opt, s) for s in seeds]
same = [s for s, b, o in zip(seeds, B, O) if acts(b) == acts(o)]
print(f"seeds {seeds[0]}-{seeds[-1]} ({len(seeds)}); the same pushes on {len(same)} of {len(seeds)}"
      + ("" if len(same) == len(seeds) else " (differ: " + " ".join(str(s) for s in seeds if s not in same) + ")"))
print("| figure | base | option | paired (option - base) | higher / lower |")
print("|---|---|---|---|---|")
res = {}
for name, f in fields:
    b = [f(j) for j in B]; o = [f(j) for j in O]
    if any(math.isnan(x) for x in b + o):
        continue
    d = [y - x for x, y in zip(b, o)]
    mb, hb = ci(b); mo, ho = ci(o); md, hd = ci(d)
    res[name] = (md, hd, sum(1 for x in d if x > 0), sum(1 for x in d if x < 0))
    print(f"| {name} | {mb:.2f} +- {hb:.2f} | {mo:.2f} +- {ho:.2f} | {md:+.2f} +- {hd:.2f} "
          f"({md - hd:+.2f} to {md + hd:+.2f}) | {res[name][2]} / {res[name][3]} |")
wb = statistics.median(j["seconds"] for j in B); wo = statistics.median(j["seconds"] for j in O)
print(f"median run: base {wb:.1f} s, option {wo:.1f} s ({100 * (wo / wb - 1):+.1f} %)")
names = ["calculator", "bike", "bottle", "giraffe"]
for key in ("mot_accuracy", "colour_accuracy"):
    if all(key in o for j in B + O for o in j["ground_truth"]["objects"]):
        per = lambda J, n: 100 * statistics.mean(
            next(o[key] for o in j["ground_truth"]["objects"] if o["name"] == n) for j in J)
        print(f"per object {key}, base -> option: " + ", ".join(f"{n} {per(B, n):.1f} -> {per(O, n):.1f}" for n in names))
print("per seed c (MoT) base/option: " + " ".join(
    f"{s}:{100 * b['ground_truth']['mot_accuracy']:.1f}/{100 * o['ground_truth']['mot_accuracy']:.1f}" for s, b, o in zip(seeds, B, O)))
if rule == "model":
    md, hd, hi, lo = res["c (MoT)"]
    cl = [md >= 3 and md - hd > 0, lo <= 6, wo <= 1.15 * wb]
else:
    cl = [res["singulation"][0] > 0 and res["singulation"][0] - res["singulation"][1] > 0,
          res["colour"][0] >= 0, res["c (MoT)"][0] >= -3, wo <= 1.25 * wb]
print("rule clauses: " + ", ".join(f"{i + 1} {'held' if c else 'FAILED'}" for i, c in enumerate(cl))
      + f"; verdict: {'passed' if all(cl) else 'failed'}")
