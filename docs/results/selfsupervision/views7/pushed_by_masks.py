#!/usr/bin/python3
"""Per learn push: the object whose ground-truth mask centroid moved most (episode masks, first vs
last frame), and the round's chosen object; marks refounds/swaps from the decision log."""
import json, sys, os, numpy as np
from PIL import Image
run = sys.argv[1]
d = json.load(open(run + ".json")); g = d["ground_truth"]
names = {}
log = [json.loads(l) for l in open(run + "/decisions.jsonl")]
ev = {}
for j in log:
    if j["event"] == "views": ev[(j["round"], j["push"])] = j
marks = {}
cur = {}
for j in log:
    if j["event"] == "push" and j.get("phase") == "learn": cur[j["round"]] = j.get("episode")
    if j["event"] in ("refound",) and j.get("why", "").startswith("looks"): marks.setdefault(cur.get(j["round"]), []).append("refound")
    if j["event"] == "fault" and j["fault"] == "swapped": marks.setdefault(cur.get(j["round"]), []).append("swap")
ep = run + "/episodes"
out = {}
for e in sorted(os.listdir(ep)):
    p = os.path.join(ep, e)
    if not os.path.isdir(p): continue
    objs = {o["id"]: o["name"] for o in json.load(open(p + "/objects.json"))["objects"]}
    fr = sorted(os.listdir(p + "/masks"))
    a = np.array(Image.open(p + "/masks/" + fr[0])); b = np.array(Image.open(p + "/masks/" + fr[-1]))
    best, bd = "", 0
    for i, n in objs.items():
        if n == "arm": continue
        ya, xa = np.nonzero(a == i); yb, xb = np.nonzero(b == i)
        if len(xa) < 5 or len(xb) < 5: continue
        dd = np.hypot(xa.mean() - xb.mean(), ya.mean() - yb.mean())
        if dd > bd: best, bd = n, dd
    r = int(e[5:e.index("-")]) - 1
    out.setdefault(r, []).append((e, best if bd > 2 else "-", marks.get(e, [])))
for r in sorted(out):
    print("round", r, "chosen", g["class_chosen"][r], "pushed most", g["class_object"][r])
    print("   ", " ".join(f"{m}{'*' + '+'.join(k) if k else ''}" for e, m, k in out[r]))
tot = sum(len(v) for v in out.values())
hit = sum(1 for r, v in out.items() for e, m, k in v if m == g["class_chosen"][r])
first = sum(1 for r, v in out.items() if v and v[0][1] == g["class_chosen"][r])
print(f"SUMMARY learn pushes {tot}, moving the chosen object most {hit}, rounds whose first push did {first} of {len(out)}")
