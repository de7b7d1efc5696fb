#!/usr/bin/python3
"""Why `proprio learn` learned an object twice or never (issue 21, session 26).

usage: scripts/learn_coverage.py RUN_DIR [RUN_DIR ...]

Reads each run's learn.json (ground truth: the object under every blob of each turn's choice
look, each learn push's intended object and what moved) and decisions.jsonl (the choose events:
skipped candidates and why, each scored blob's best object and how far below that object's own
views it lies), both read by scripts/learn_runs.py, and prints per run:
  - per class: the object chosen, the object it is named after, its purity and views, and its
    pushes as intended>moved (views);
  - per object on the table never given a class: why (never a candidate in reach; taken for a
    known object; never chosen though new-looking; chosen but its pushes moved something else);
  - per duplicate class (its object named an earlier class): the chosen blob's word score against
    the class it duplicates, and how far the blob lay from where that class's last push ended;
  - identity checks (learn.json's "identity" when the run has them);
and the causes counted over all runs.
"""
import math
import os
import sys
from collections import Counter, defaultdict

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import learn_runs  # noqa: E402


def main(runs):
    causes = Counter()
    for run in runs:
        r = learn_runs.load(run)
        j, dec = r.json, r.events
        g = j.get("ground_truth", {})
        names = g.get("class_object", [])
        chosen = g.get("class_chosen", [])
        purity = g.get("class_purity", [])
        blobs_truth = g.get("class_blobs", [])
        table = [o["name"] for o in g.get("objects", [])]
        opts = j.get("options", {})
        every = [x for x in (opts.get("objects", "") + "," + opts.get("clutter", "")).split(",") if x]
        print(f"== {run}: MoT {100 * g.get('mot_accuracy', 0):.1f} %, argmax "
              f"{100 * g.get('argmax_accuracy', 0):.1f} %, named {table}")
        pushes = defaultdict(list)
        last_end = {}
        for p in j["pushes"]:
            if not p["executed"]:
                continue
            pushes[p["class"]].append(f"{p.get('intended', '?')}>{'+'.join(p.get('moved', []))}"
                                      f"({p['views']})")
            last_end[p["class"]] = p["plan"]["end"]
        classes = j.get("classes", [])
        views = {o["class"]: o["views"] for o in j["objects"]}
        # The last choose event of each class (its blob indices are those of class_blobs).
        choose = {}
        looks = {}
        for e in dec:
            if e["event"] == "choose":
                choose[e["object"]] = e
            if e["event"] == "look":
                looks.setdefault(e["object"], e)
        learned = []
        for c, cls in enumerate(classes):
            nm = names[c] if c < len(names) else ""
            ch = chosen[c] if c < len(chosen) else ""
            pur = purity[c] if c < len(purity) else 0
            dup = nm and views.get(cls, 0) > 0 and nm in learned
            print(f"  {cls}: chosen {ch or '-'}, named {nm or '-'} ({views.get(cls, 0)} views, "
                  f"purity {100 * pur:.0f} %){' DUPLICATE' if dup else ''}: "
                  f"{' '.join(pushes.get(cls, [])) or 'no push executed'}")
            aimed = [x.split(">")[0] for x in pushes.get(cls, [])]
            drift = bool(ch) and any(a != ch for a in aimed)
            if drift:
                print(f"    drift: chosen {ch}, pushes aimed at {','.join(aimed)}")
                causes["classes whose pushes drifted from the chosen object"] += 1
            if dup:
                causes["duplicate class: " + ("its turn drifted to the known object" if nm != ch
                                              else "chosen again, not taken for known")] += 1
                e = choose.get(c, {})
                first = names.index(nm)
                sc = [s for s in e.get("scores", []) if s["blob"] == e.get("blob")]
                s = sc[0] if sc else {}
                centres = looks.get(c, {}).get("centres", [])
                b = e.get("blob", -1)
                where = ""
                end = last_end.get(classes[first])
                if end and 0 <= b < len(centres):
                    where = f", {math.dist(end, centres[b]):.3f} m from where {classes[first]}'s " \
                            f"last push ended"
                known = [k["object"] for k in e.get("known", [])]
                print(f"    why not known: {classes[first]} ({nm}) known at blobs "
                      f"{[k['blob'] for k in e.get('known', []) if k['object'] == first]} "
                      f"(known objects {known}); the chosen blob's best class "
                      f"{s.get('best_object', '-')}, below its own {s.get('below_own', 0):+.2f} "
                      f"nats{where}")
            if views.get(cls, 0) > 0 and nm:
                learned.append(nm)
        for obj in every:
            if obj in learned:
                continue
            why = []
            intended = sum(1 for p in j["pushes"] if p["executed"] and p.get("intended") == obj)
            moved = sum(1 for p in j["pushes"] if p["executed"] and obj in p.get("moved", []))
            for c, e in sorted(choose.items()):
                bt = blobs_truth[c] if c < len(blobs_truth) else []
                idx = [i for i, t in enumerate(bt) if t == obj]
                if not idx:
                    why.append(f"t{c + 1}:absent")
                    continue
                reasons = {k["blob"]: k["reason"] for k in e.get("skipped", [])}
                for i in idx:
                    why.append(f"t{c + 1}:" + ("CHOSEN" if i == e.get("blob") else reasons.get(i, "?")))
            if intended > 0:
                cause = "chosen/aimed at, but its class named after another object"
            elif any(w.endswith(":known") for w in why):
                cause = "taken for a known object"
            elif all(w.endswith(":absent") for w in why):
                cause = "never a candidate in reach (merged blob / out of reach)"
            else:
                cause = "never chosen though offered"
            causes[f"never learned: {cause}"] += 1
            print(f"  never learned {obj} ({'named' if obj in table else 'clutter'}): {cause}; "
                  f"aimed at {intended}, moved in {moved} pushes; {' '.join(why)}")
        # Identity checks (decisions.jsonl "identity", session 26): the turn's first push with
        # views against each known class, beside the truth of that push and of the classes.
        truth_of = {p["index"]: p for p in j["pushes"]}
        for e in dec:
            if e["event"] != "identity":
                continue
            p = truth_of.get(e["index"], {})
            sc = " ".join(f"{classes[s['best_object']]}({names[s['best_object']] or '-'})"
                          f" {s['below_own']:+.2f}" for s in e.get("scores", []))
            it = p.get("intended", "?")
            rep = any(names[s["best_object"]] == it for s in e.get("scores", [])
                      if views.get(classes[s["best_object"]], 0) > 0)
            best = max(e.get("scores", []), key=lambda s: s["below_own"], default=None)
            right = best is not None and names[best["best_object"]] == it
            print(f"  identity {classes[e['object']]} push {e['index']}: aimed at {it}, moved "
                  f"{'+'.join(p.get('moved', []))}; {'REPEAT' if rep else 'new'}; best "
                  f"{'right' if right else 'other'}; below own: {sc}"
                  f"{'; MERGED' if 'why' in e else ''}")
            causes[f"identity checks: {'repeat' if rep else 'new'}"] += 1
    print("== causes over the runs:")
    for k, v in causes.most_common():
        print(f"  {v:3d}  {k}")


if __name__ == "__main__":
    main(sys.argv[1:])
