#!/usr/bin/python3
"""Per run: learn pushes that moved the intended object alone (ground truth, class_learn_pushes:
'intended>moved+moved', intended = the object under the pushed blob) and that moved the round's
chosen object alone; with the decision log's motion events (new code) the shares vs the truth."""
import json, sys, os, math
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "../../../../scripts"))
from oracle_ladder_table import ci  # mean and 95% t half-width over the seeds
tot = dict(n=0, alone=0, chosen_alone=0, chosen_most=0)
per = []
for run in sys.argv[1:]:
    d = json.load(open(run + ".json")); g = d["ground_truth"]
    n = a = ca = 0
    for r, lst in enumerate(g["class_learn_pushes"]):
        ch = g["class_chosen"][r]
        for line in lst:
            i, m = line.split(">"); moved = m.split("+") if m else []
            n += 1; a += moved == [i]; ca += moved == [ch]
    log = [json.loads(l) for l in open(run + "/decisions.jsonl")]
    faults = {}
    for j in log:
        if j["event"] == "fault": faults[j["fault"]] = faults.get(j["fault"], 0) + 1
    mo = {}
    for j in log:
        if j["event"] == "motion": mo.setdefault(j["round"], []).append(j)
    conf = dict(alone_ok=0, alone_bad=0, notalone_ok=0, notalone_bad=0)
    for r, lst in mo.items():
        gt = g["class_learn_pushes"][r]
        for k, j in enumerate(lst):
            if k >= len(gt): break
            i, m = gt[k].split(">"); moved = m.split("+") if m else []
            sh = j["shares"]; b = j["blob"]
            mv = [q for q, s in enumerate(sh) if s >= 0.25]
            al = mv == [b]
            key = ("alone" if al else "notalone") + ("_ok" if (moved == [i]) == al else "_bad")
            conf[key] += 1
    obj = {o["name"]: o for o in g["objects"]}
    print(f"{run}: learn pushes {n}, intended alone {a} ({a/max(n,1):.0%}), chosen alone {ca} "
          f"({ca/max(n,1):.0%}); c {g['mot_accuracy']:.3f} purity {g['purity']:.3f} "
          f"singulation {g['singulation']:.2f}; faults {faults}; motion vs truth {conf}")
    per.append((a / max(n, 1), ca / max(n, 1), n))
if len(per) > 1:
    for k, name in enumerate(["intended alone", "chosen alone", "learn pushes"]):
        m, h = ci([p[k] for p in per]); print(f"{name}: {m:.3f} +- {h:.3f}")
