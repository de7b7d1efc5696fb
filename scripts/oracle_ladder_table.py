#!/usr/bin/python3
"""The oracle ladder's table (loop::OracleLadder) over several runs' JSON records.

usage: scripts/oracle_ladder_table.py TITLE FILE...   (selfsupervise --json files or learn.json)

Per rung: held-out accuracy, mean with a 95% t interval over the runs, per run, and per object
(mean over the runs); then the composition of the robot's view masks (object / arm / background /
other objects) and the share of its views whose label is the object mostly in view.
"""
import json
import math
import sys

T95 = {2: 12.71, 3: 4.30, 4: 3.18, 5: 2.78, 6: 2.57, 7: 2.45, 8: 2.36, 9: 2.31, 10: 2.26}


def ci(v):
    n = len(v)
    m = sum(v) / n
    if n < 2:
        return m, float("nan")
    sd = math.sqrt(sum((x - m) ** 2 for x in v) / (n - 1))
    return m, T95.get(n, 2.0) * sd / math.sqrt(n)


def main():
    title, files = sys.argv[1], sys.argv[2:]
    runs = []
    for f in files:
        j = json.load(open(f))
        g = j.get("ground_truth") or {}
        if "oracle_ladder" not in g:
            print(f"{f}: no oracle ladder (run with --oracle-ladder)", file=sys.stderr)
            continue
        runs.append((f, g))
    if not runs:
        return
    objects = [o["name"] for o in runs[0][1]["objects"]]
    names = [r["name"] for r in runs[0][1]["oracle_ladder"]["rungs"]]
    print(f"## oracle ladder: {title} ({len(runs)} runs)")
    print(f"{'rung':9s} {'held-out accuracy':>19s}  {'per run':30s} {'views':>6s} {'cls':>4s} "
          f"{'label ok':>8s}  per object (mean): " + " ".join(objects))
    for k, name in enumerate(names):
        rs = [g["oracle_ladder"]["rungs"][k] for _, g in runs]
        acc = [r["accuracy"] for r in rs]
        m, h = ci(acc)
        per = " ".join(f"{100 * a:3.0f}" for a in acc)
        views = sum(r["training_views"] for r in rs) / len(rs)
        cls = sum(r["classes"] for r in rs) / len(rs)
        lp = [r["label_purity"] for r in rs if r["label_purity"] >= 0]
        lps = f"{100 * sum(lp) / len(lp):7.0f}%" if lp else f"{'':8s}"
        po = []
        for i in range(len(objects)):
            v = [r["per_object"][i] for r in rs if i < len(r["per_object"])]
            po.append(f"{100 * sum(v) / len(v):5.1f}" if v else "   - ")
        hs = "" if math.isnan(h) else f" +- {100 * h:4.1f}"
        print(f"{name:9s} {100 * m:9.1f}%{hs:9s}  {per:30s} {views:6.0f} {cls:4.1f} {lps}  "
              + " ".join(po))
    sh = [g["oracle_ladder"] for _, g in runs]
    f = lambda key: 100 * sum(x[key] for x in sh) / len(sh)
    print(f"robot's view masks: {f('share_object'):.0f}% on the object mostly in view, "
          f"{f('share_arm'):.0f}% arm, {f('share_background'):.0f}% background, "
          f"{f('share_other'):.0f}% other objects")
    pooled_table(runs, names, objects)
    for name in names:
        what = next(r["what"] for r in runs[0][1]["oracle_ladder"]["rungs"] if r["name"] == name)
        print(f"  {name}: {what}")
    print()


def pooled_table(runs, names, objects):
    """The rungs by the pooled words classifier (selfsupervise --pooled-score), when recorded:
    per weight of the word multinomials, mean +- 95% t interval over the runs; the theta figure
    beside it, and the paired difference at each weight."""
    rungs = [g["oracle_ladder"]["rungs"] for _, g in runs]
    if not any(r.get("pooled") for rs in rungs for r in rs):
        return
    print("by the pooled words classifier (--pooled-score): held-out accuracy per weight w of the"
          " word multinomials; 'once' = c's multinomials counting each push once")
    c_pooled = next((r["pooled"] for rs in rungs for r in rs
                     if r.get("pooled") and r["name"] == "c"), [])
    heads = [("once " if f["once"] else "w ") + f"{f['weight']:g}" for f in c_pooled]
    print(f"{'rung':9s} {'theta':>15s}  " + " ".join(f"{h:>15s}" for h in heads))
    for k, name in enumerate(names):
        rs = [x[k] for x in rungs]
        if not all(r.get("pooled") for r in rs):
            continue
        m, h = ci([r["accuracy"] for r in rs])
        cells = [f"{100 * m:6.1f} +- {0 if math.isnan(h) else 100 * h:4.1f}"]
        for j in range(len(rs[0]["pooled"])):
            m, h = ci([r["pooled"][j]["accuracy"] for r in rs])
            cells.append(f"{100 * m:6.1f} +- {0 if math.isnan(h) else 100 * h:4.1f}")
        print(f"{name:9s} " + " ".join(f"{c:>15s}" for c in cells))
    c = [x[-1] for x in rungs]
    if all(r["name"] == "c" and r.get("pooled") for r in c):
        print("c, paired difference pooled - theta (points, mean +- 95% t interval), per run:")
        for j, f in enumerate(c[0]["pooled"]):
            d = [r["pooled"][j]["accuracy"] - r["accuracy"] for r in c]
            m, h = ci(d)
            hs = "" if math.isnan(h) else f" +- {100 * h:4.1f}"
            print(f"  {heads[j]:8s} {100 * m:+6.1f}{hs:9s}  " + " ".join(f"{100 * x:+4.0f}" for x in d)
                  + "   per object (mean): " + " ".join(
                      f"{o} {100 * sum(r['pooled'][j]['per_object'][i] for r in c) / len(c):4.1f}"
                      for i, o in enumerate(objects)))


if __name__ == "__main__":
    main()
