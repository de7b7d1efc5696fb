"""Session 26: why a round's learn pushes leave the object it chose (ground truth, scoring only).

usage: python3 drift.py RUN.json [RUN.json ...]
For every round: the chosen object (class_chosen), each learn push "intended>moved" and the pushed
blob's points by object (class_learn_blobs, "name:share+..."). A drift is a learn push whose
intended object (most of the pushed blob's points) is not the chosen one while the push before
it was on the chosen one (or it is the round's first). Each drift is put in one kind:
  merged:   the pushed blob still holds the chosen object (>= 20% of its points): the chosen
            object and a neighbour touch and make one blob, the neighbour the larger part;
  jumped:   the pushed blob holds < 20% of the chosen object: the round follows a neighbour's
            own blob;
and for each: whether the push before moved the new object too (it pushed the neighbour), and
whether it is the round's first learn push (after (b)).
"""
import json
import sys


def parse(blob):
    out = {}
    for part in blob.split("+") if blob else []:
        name, share = part.rsplit(":", 1)
        out[name] = float(share)
    return out


def main():
    tot = {"rounds": 0, "rounds_left": 0, "pushes": 0, "off": 0, "off_merged": 0, "multi_blob": 0}
    kinds = {}
    for f in sys.argv[1:]:
        g = json.load(open(f))["ground_truth"]
        if "class_learn_blobs" not in g:
            print(f"{f}: no class_learn_blobs (older build)")
            continue
        print(f"== {f}: classes {g['class_object']}, chosen {g['class_chosen']}")
        for r, (chosen, lp, lb) in enumerate(zip(g["class_chosen"], g["class_learn_pushes"], g["class_learn_blobs"])):
            if not lp:
                continue
            tot["rounds"] += 1
            left = False
            rows = []
            for k, (p, b) in enumerate(zip(lp, lb)):
                intended, moved = p.split(">")
                moved = moved.split("+") if moved else []
                comp = parse(b)
                tot["pushes"] += 1
                tot["multi_blob"] += sum(1 for s in comp.values() if s >= 0.1) > 1
                if intended != chosen:
                    tot["off"] += 1
                    tot["off_merged"] += comp.get(chosen, 0) >= 0.2
                prev_on = k == 0 or lp[k - 1].split(">")[0] == chosen
                tag = ""
                if intended and intended != chosen and prev_on:
                    left = True
                    kind = "merged" if comp.get(chosen, 0) >= 0.2 else "jumped"
                    why = ("first learn push" if k == 0 else
                           "push before moved it" if intended in lp[k - 1].split(">")[1].split("+") else
                           "push before did not move it")
                    kinds[(kind, why)] = kinds.get((kind, why), 0) + 1
                    tag = f"  <- drift: {kind}, {why}"
                rows.append(f"    {k + 1:2d} {p:40s} {b}{tag}")
            tot["rounds_left"] += left
            print(f"  round {r + 1}: chose {chosen}")
            print("\n".join(rows))
    print(f"\nrounds {tot['rounds']}, rounds that left their chosen object {tot['rounds_left']}")
    print(f"learn pushes {tot['pushes']}; on another object than the chosen {tot['off']} "
          f"(of which the blob still held the chosen object, >= 20%: {tot['off_merged']}); "
          f"pushed blob made of two or more objects (>= 10% each): {tot['multi_blob']}")
    for (kind, why), n in sorted(kinds.items()):
        print(f"  drift {kind:7s} {why:28s} {n}")


main()
