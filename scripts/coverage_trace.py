#!/usr/bin/python3
"""Why a named object got no views (no class named after it): issues 19 and 21, session 33.

usage: scripts/coverage_trace.py RUN [RUN ...]

RUN is a `proprio learn` run directory (learn.json, decisions.jsonl, pushes/; read by
scripts/learn_runs.py) or a `proprio selfsupervise` run directory (selfsupervise.json,
decisions.jsonl) or its JSON (its decisions.jsonl is the one the JSON names, or
DIR/decisions.jsonl beside it).
Standard library only; reads, never writes.

A named object is "missed" when no class is named after it (ground_truth.objects[].views == 0):
it scores 0 % held out whatever the classifier. For each, the cause is one of
  1 never a candidate: at no choice look was it its own blob in reach (sub-status from the
    pushes' ground-truth masks at that look: out-of-reach (a blob beyond the arm's reach lies on
    it), merged (a neighbour's blob centre lies on it), no-blob (in reach, in view, no blob:
    too few features or not standing out of the table), unseen (fewer than 15 pixels: hidden,
    out of the camera's view or off the table));
  2 a candidate at the last choice look too, skipped at every choice (the logged reason per turn:
    not-drawn, less-new, known (as which class; by its region or top-down / where it was left),
    no-features; selfsupervise: not-drawn, claimed-by-class-N, lower-score(its distance < the
    chosen's)); the turns ran out with it still a candidate (selfsupervise re-scatters the table
    every round: there a candidate at any round's choice);
  3 chosen (learn: the object under the turn's chosen blob; selfsupervise: also a round's first
    choice lost while clearing) but its turn's pushes went (also) to another object: the class
    is named after the object its executed pushes were aimed at most (ties: the one its views
    show most, then the first name; before session 34 the first name alone);
  4 chosen and pushed, but its pushes gave no views (refused, nothing segmented);
  5 a candidate earlier, then moved by a push (push number, whose turn, aimed at what) and never
    a candidate again (out of reach, off the table, merged into a neighbour).
The sub-status of a look where it was no candidate comes from the masks in
pushes/push_NNN/episode/masks (16-bit PNG, decoded here with zlib; runs with --oracle-ladder keep
them) and the episode's calib.yml (K, R, t; the table is z = 0); without masks it is "absent",
or a guess marked "?" from the planned target of the last push aimed at it.
Then, over the runs: the causes, what else the missed objects' logs say (skip reasons, drift onto
them, ties lost for a class's name) and, for learn, every executed push by drift and how its
blob was located.
"""
import json
import math
import os
import re
import struct
import sys
import zlib
from collections import Counter, defaultdict

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import learn_runs  # noqa: E402

CAUSES = {
    1: "never a candidate",
    2: "a candidate, skipped at every choice",
    3: "chosen, its turn's pushes went (also) to another object",
    4: "chosen and pushed, no views",
    5: "a candidate, then moved by a push and never a candidate again",
}


# ---------------------------------------------------------------- ground-truth masks (stdlib)
PUSHES = Counter()  # learn runs: executed pushes by drift and how their blob was located


def read_png16(path):
    """A 16-bit greyscale PNG as (width, height, flat list of ints)."""
    data = open(path, "rb").read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", path
    pos, idat, w = 8, [], 0
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        if kind == b"IHDR":
            w, h, depth, colour = struct.unpack(">IIBB", body[:10])
            if (depth, colour) not in ((16, 0), (8, 0)):
                raise ValueError(f"{path}: bit depth {depth}, colour type {colour}")
            bpp = depth // 8
        elif kind == b"IDAT":
            idat.append(body)
        pos += 12 + n
    raw = zlib.decompress(b"".join(idat))
    stride = w * bpp
    prev = bytearray(stride)
    out = []
    i = 0
    for _ in range(h):
        f = raw[i]
        line = bytearray(raw[i + 1:i + 1 + stride])
        i += 1 + stride
        if f == 1:
            for x in range(bpp, stride):
                line[x] = (line[x] + line[x - bpp]) & 255
        elif f == 2:
            for x in range(stride):
                line[x] = (line[x] + prev[x]) & 255
        elif f == 3:
            for x in range(stride):
                a = line[x - bpp] if x >= bpp else 0
                line[x] = (line[x] + ((a + prev[x]) >> 1)) & 255
        elif f == 4:
            for x in range(stride):
                a = line[x - bpp] if x >= bpp else 0
                b = prev[x]
                c = prev[x - bpp] if x >= bpp else 0
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[x] = (line[x] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        if bpp == 2:
            out.extend(struct.unpack(f">{w}H", bytes(line)))
        else:
            out.extend(line)
        prev = line
    return w, h, out


def read_calib(path):
    text = open(path).read()

    def mat(name):
        m = re.search(name + r": !!opencv-matrix.*?data: \[([^\]]*)\]", text, re.S)
        return [float(x) for x in m.group(1).replace("\n", " ").split(",")]

    return mat("camera_matrix"), mat("R"), mat("t")


def project(calib, xy):
    k, r, t = calib
    x, y = xy[0], xy[1]
    c = [r[3 * i] * x + r[3 * i + 1] * y + t[i] for i in range(3)]
    return k[0] * c[0] / c[2] + k[2], k[4] * c[1] / c[2] + k[5]


class Scene:
    """One look's ground truth: the mask of the next push's first frame."""

    def __init__(self, episode, last=False):
        names = json.load(open(f"{episode}/objects.json"))["objects"]
        self.name = {o["id"]: o["name"] for o in names}
        frames = sorted(os.listdir(f"{episode}/masks"))
        self.w, self.h, self.m = read_png16(f"{episode}/masks/{frames[-1 if last else 0]}")
        self.calib = read_calib(f"{episode}/calib.yml")
        self.pixels = Counter(self.m)

    def count(self, obj):
        ids = [i for i, n in self.name.items() if n == obj]
        return self.pixels.get(ids[0], 0) if ids else 0

    def under(self, xy, radius=4):
        """The object most under a table point's image (object pixels within radius px)."""
        u, v = project(self.calib, xy)
        votes = Counter()
        for dy in range(-radius, radius + 1):
            for dx in range(-radius, radius + 1):
                x, y = int(round(u)) + dx, int(round(v)) + dy
                if 0 <= x < self.w and 0 <= y < self.h:
                    i = self.m[y * self.w + x]
                    if i and i in self.name and self.name[i] != "arm":
                        votes[self.name[i]] += 1
        return votes.most_common(1)[0][0] if votes else ""


# ---------------------------------------------------------------- learn
def learn_scene(run, j, push_index):
    """The scene at a look: the first push from push_index on with an episode; else the last
    frame of the last push with one before it."""
    pushes = j["pushes"]
    for p in pushes[push_index:] if push_index is not None else []:
        ep = f"{run}/{p['dir']}/episode"
        if os.path.isdir(f"{ep}/masks"):
            return Scene(ep)
    for p in reversed(pushes[:push_index] if push_index is not None else pushes):
        ep = f"{run}/{p['dir']}/episode"
        if os.path.isdir(f"{ep}/masks"):
            return Scene(ep, last=True)
    return None


def guess_absent(obj, look, blob_truth, pushes, before):
    """Without masks: the object's place after the last push before `before` that moved it, if
    that push was aimed at it (its plan's target), against the look's blobs (6 cm)."""
    last = [p for p in pushes[:before] if p["executed"] and obj in p.get("moved", [])]
    if not last:
        return "absent(never moved)"
    p = last[-1]
    if p.get("intended") != obj:
        return f"absent(last moved by #{p['index']}, aimed at {p.get('intended') or '?'})"
    at = p["plan"]["target"]
    far = [math.dist(at, xy) for xy in look.get("out_of_reach", [])]
    near = [(math.dist(at, xy), k) for k, xy in enumerate(look.get("centres", []))]
    if far and min(far) < 0.06:
        return f"out-of-reach?(#{p['index']}'s target)"
    if near and min(near)[0] < 0.06:
        k = min(near)[1]
        return f"merged?(#{p['index']}'s target on b{k}:" \
               f"{blob_truth[k] if k < len(blob_truth) else '?'})"
    return f"absent(#{p['index']}'s target near no blob)"


def trace_learn(run):
    r = learn_runs.load(run)
    j, dec = r.json, r.events
    g = j["ground_truth"]
    named = [o["name"] for o in g["objects"]]
    missed = [o["name"] for o in g["objects"] if o["views"] == 0]
    cls_names = j["classes"]
    class_object, class_chosen = g["class_object"], g["class_chosen"]
    class_blobs = g["class_blobs"]
    pushes = j["pushes"]
    cls_index = {n: i for i, n in enumerate(cls_names)}
    # Turns: each look, the push that follows it, and the turn's choice (the last one logged).
    looks, choice = {}, {}
    pending = []
    region_known = set()  # classes whose last push's region lies on a candidate of the look
    for e in dec:
        if e["event"] == "candidates":
            region_known = {k["object"] for k in e.get("known", [])}
        elif e["event"] == "look":
            looks.setdefault(e["object"], e)
            looks[e["object"]].setdefault("_region", region_known)
            pending.append(e["object"])
        elif e["event"] in ("choose", "none-chosen"):
            choice[e["object"]] = e
        elif e["event"] == "push":
            for c in pending:
                looks[c]["_push"] = e["index"]
            pending = []
    scenes = {c: learn_scene(run, j, lk.get("_push", len(pushes))) for c, lk in looks.items()}
    rows = []
    for obj in missed:
        status = []  # per turn: ("cand", reason) or ("absent", sub)
        for c in sorted(looks):
            bt = class_blobs[c] if c < len(class_blobs) else []
            idx = [i for i, t in enumerate(bt) if t == obj]
            ch = choice.get(c, {})
            if idx:
                reasons = {k["blob"]: k["reason"] for k in ch.get("skipped", [])}
                by = {k["blob"]: k["object"] for k in ch.get("known", [])}
                rs = []
                for i in idx:
                    r = "CHOSEN" if i == ch.get("blob") else reasons.get(i, "?")
                    if r == "known" and i in by:
                        src = "region" if by[i] in looks[c]["_region"] else "top-down-or-left"
                        r += f"(as {by[i] + 1}={class_object[by[i]] or '-'},{src})"
                    rs.append(r)
                status.append((c, "cand", "/".join(rs)))
                continue
            sc = scenes.get(c)
            lk = looks[c]
            if sc is None:
                # No ground-truth masks (a run without the oracle ladder): where the last
                # executed push that moved it before this look aimed it (its plan's target),
                # when it was aimed at it; "absent" otherwise.
                status.append((c, "absent", guess_absent(obj, lk, bt, pushes, lk.get("_push"))))
                continue
            if sc.count(obj) < 15:
                status.append((c, "absent", "unseen"))
                continue
            far = [sc.under(xy) for xy in lk.get("out_of_reach", [])]
            if obj in far:
                status.append((c, "absent", "out-of-reach"))
                continue
            near = [(k, sc.under(xy, 2)) for k, xy in enumerate(lk.get("centres", []))]
            on = [f"b{k}:{bt[k] if k < len(bt) else t}" for k, t in near if t == obj]
            status.append((c, "absent", "merged(" + ",".join(on) + ")" if on else "no-blob"))
        aimed = [p for p in pushes if p.get("intended") == obj]
        moved = [p for p in pushes if p["executed"] and obj in p.get("moved", [])]
        chosen = [c for c, x in enumerate(class_chosen) if x == obj]
        turns_aimed = sorted({cls_index[p["class"]] for p in aimed})
        ev = []
        flags = Counter()
        execd = [p for p in aimed if p["executed"]]
        if chosen:
            # Chosen: its turn's executed pushes went (also) to others (3), or there were none
            # or all were aimed at it and gave no views (4).
            turn_exec = [p for p in pushes if cls_index[p["class"]] in chosen and p["executed"]]
            cause = 3 if any(p.get("intended") != obj for p in turn_exec) else 4
        else:
            # Not chosen: still a candidate at the last look (skipped until the turns ran out:
            # 2), a candidate until a push moved it and never again (5), never a candidate (1).
            cands = [s for s in status if s[1] == "cand"]
            last_cand = max((s[0] for s in cands), default=-1)
            after = [s for s in status if s[0] > last_cand]
            if not cands:
                cause = 1
            elif not after:
                cause = 2
            else:
                nxt = after[0][0]
                lo = looks[last_cand].get("_push", 0)
                hi = looks[nxt].get("_push", len(pushes))
                who = [p for p in moved if lo <= p["index"] < hi]
                cause = 5 if who else 2
                if who:
                    own = any(p.get("intended") == obj for p in who)
                    flags["5: carried off by a push aimed at it (another object's turn)" if own
                          else "5: carried off by pushes aimed at other objects"] += 1
                    if all(cls_index[p["class"]] == 0 for p in who):
                        flags["5: carried off in turn 1 (the random first choice's turn)"] += 1
                ev.append("no longer a candidate after " + (", ".join(
                    f"#{p['index']} (t{cls_index[p['class']] + 1}, aimed at "
                    f"{p.get('intended') or '?'})" for p in who) or "no push moved it") +
                    f" (t{nxt + 1}: {after[0][2]})")
            skips = [r for c, kind, rs in status if kind == "cand" and c > 0
                     for r in rs.split("/")]
            for x in skips:
                x = re.sub(r"[(][^,]*,", "(", x)
                flags[f"skipped while a candidate at a scored choice: {x}"] += 1
            if skips:
                kinds = Counter(re.sub(r"[(].*", "", x) for x in skips).most_common()
                ev.append(f"skipped at the scored choices: {len(skips)} "
                          f"({', '.join(f'{k} {v}' for k, v in kinds)})")
        for c in sorted(set(chosen) | set(turns_aimed)):
            tp = [p for p in pushes if cls_index[p["class"]] == c]
            seq = " ".join(
                f"#{p['index']}{'' if p['executed'] else 'R'}:{p.get('intended') or '?'}"
                f">{'+'.join(p.get('moved', [])) or '-'}({p['views']})" for p in tp)
            ev.append(f"t{c + 1} chose {class_chosen[c] or '-'}, named "
                      f"{class_object[c] or '-'}: {seq or 'no push'}")
        # The classes its executed pushes were in: named after the object most pushed (the
        # intended one), ties to the object the views show most, then the first name
        # (loop::pushed_most; runs before session 34: the first name); did it tie and lose?
        for c in sorted({cls_index[p["class"]] for p in execd}):
            n = Counter(p["intended"] for p in pushes if cls_index[p["class"]] == c
                        and p["executed"] and p.get("intended"))
            if n[obj] == max(n.values()) and class_object[c] != obj:
                flags["lost a tie for a class's name"] += 1
                ev.append(f"t{c + 1}: tied for the most pushes ({n[obj]}) with "
                          f"{class_object[c]}, which the class is named after")
        if execd and not chosen:
            flags["pushed on purpose in other objects' turns (drift onto it): objects"] += 1
            flags["pushed on purpose in other objects' turns: their views"] += sum(
                p["views"] for p in execd)
            ev.append(f"pushed on purpose only in other objects' turns (drift onto it): "
                      f"{len(execd)} pushes, {sum(p['views'] for p in execd)} views, "
                      f"in classes named after others")
        ev.append("looks: " + " ".join(f"t{c + 1}:{s}" for c, _, s in status))
        ob = next(o for o in g["objects"] if o["name"] == obj)
        if ob.get("tipped", 0) or ob.get("tipped_by_others", 0):
            flags["tipped over in the run (stood before a push, lay after)"] += 1
            ev.append(f"tipped over: by {ob.get('tipped', 0)} push(es) aimed at it, "
                      f"{ob.get('tipped_by_others', 0)} aimed at others")
        if moved:
            ev.append("moved in " + " ".join(f"#{p['index']}" for p in moved))
            # Moving in every executed push from some push to the run's end, whatever was
            # pushed: rolling (lying, or off the table).
            ex = [p["index"] for p in pushes if p["executed"]]
            mv = {p["index"] for p in moved}
            k = len(ex)
            while k > 0 and ex[k - 1] in mv:
                k -= 1
            if len(ex) - k >= 5:
                flags["moving in every push to the end (rolling: lying or off the table?)"] += 1
                ev.append(f"moving in every executed push from #{ex[k]} to the end "
                          f"({len(ex) - k} pushes, whatever was pushed): rolling (lying or off "
                          f"the table?)")
        rows.append((obj, cause, ev, flags))
    # Every executed push: aimed at the turn's chosen object or not (drift), by how its blob was
    # found (located: chosen, segmented, top-down, tracked); and those aimed at a missed object
    # in another object's turn.
    for p in pushes:
        if not p["executed"] or not p.get("intended"):
            continue
        c = cls_index[p["class"]]
        drift = p["intended"] != class_chosen[c]
        aim = "aimed at another object than the turn chose" if drift else \
            "aimed at the chosen object"
        PUSHES[f"executed pushes {aim}, located {p['located']}"] += 1
        if drift and p["intended"] in missed:
            PUSHES[f"of them aimed at a missed object, located {p['located']}"] += 1
    none = sum(1 for e in dec if e["event"] == "none-chosen")
    extra = [f"{g.get('off_table', 0)} off the table"] if g.get("off_table", 0) else []
    if none:
        extra.append(f"{none} turns chose nothing (every blob in reach taken for a known object)")
    dup = [f"t{c + 1} ({class_object[c]})" for c in range(len(class_object))
           if class_object[c] and class_object[c] in class_object[:c]]
    if dup:
        extra.append("turns whose class repeats an earlier class's object: " + ", ".join(dup))
    return named, rows, extra


# ---------------------------------------------------------------- selfsupervise
def trace_self(path):
    if os.path.isdir(path):
        jpath = f"{path}/selfsupervise.json"
    else:
        jpath = path
    j = json.load(open(jpath))
    dpath = j.get("decisions", "")
    if not os.path.exists(dpath):
        dpath = os.path.join(os.path.dirname(jpath), "decisions.jsonl")
    dec = [json.loads(x) for x in open(dpath) if x.strip()]
    g = j["ground_truth"]
    named = [o["name"] for o in g["objects"]]
    missed = [o["name"] for o in g["objects"] if o["views"] == 0]
    # Per round: where the attendant put each object (rescatter; round 0 from the first look's
    # truth only), the looks of the choice and the choices.
    placed, chooses, looks = {}, defaultdict(list), defaultdict(list)
    faults = defaultdict(list)
    views = Counter()
    for e in dec:
        r = e.get("round")
        if e["event"] == "rescatter":
            placed[r] = {m.group(1): (float(m.group(2)), float(m.group(3)))
                         for m in re.finditer(r"(\w+) \(([-\d.]+), ([-\d.]+)\) m", e["what"])}
        elif e["event"] == "look" and e.get("phase", "choose") == "choose":
            looks[r].append(e)
        elif e["event"] == "choose":
            chooses[r].append(e)
        elif e["event"] == "fault":
            faults[r].append(e["fault"])
        elif e["event"] == "views" and e.get("phase", "learn") == "learn":
            views[r] += e.get("views", 0)
    rounds = sorted(set(chooses) | set(looks))
    rows = []
    for obj in missed:
        ev = []
        status = []
        for r in rounds:
            ch = chooses[r]
            bt = g["class_blobs"][r] if r < len(g["class_blobs"]) else []
            parts = []
            # The first choice of the round: its look's blobs against the attendant's placement.
            if ch and looks[r] and r in placed:
                first = ch[0]
                blobs = looks[r][0].get("blobs", [])
                near = []
                for k, b in enumerate(blobs):
                    cx, cy = b["centre"]
                    d, o = min((math.dist((cx, cy), xy), n) for n, xy in placed[r].items())
                    near.append(o if d < 0.08 else "")
                idx = [k for k, o in enumerate(near) if o == obj]
                if idx:
                    parts.append("first:" + "/".join(
                        "CHOSEN" if k == first["blob"] else why_self(first, k) for k in idx))
                else:
                    parts.append("first:no-blob-within-8cm")
            # The last choice of the round (class_blobs' look).
            idx = [k for k, t in enumerate(bt) if t == obj]
            last = ch[-1] if ch else {}
            if len(ch) > 1 or not (looks[r] and r in placed):
                parts.append("last:" + ("/".join("CHOSEN" if k == last.get("blob")
                                                  else why_self(last, k) for k in idx)
                                        if idx else "absent"))
            status.append(f"r{r + 1}:" + ",".join(parts))
        chosen = [c for c, x in enumerate(g["class_chosen"]) if x == obj]
        first_chosen = [r for r, st in zip(rounds, status) if "first:CHOSEN" in st]
        if chosen:
            # The round's class named after it with no views (4), or after another (3).
            cause = 4 if any(g["class_object"][c] == obj for c in chosen) else 3
        elif first_chosen:
            cause = 3  # chosen at a round's first choice, lost while clearing: another chosen
        elif any(re.search(r"(first|last):(?!absent|no-blob)", st) for st in status):
            cause = 2
        else:
            cause = 1
        for c in sorted(set(chosen) | set(first_chosen)):
            ev.append(f"round {c + 1} chose it first, then {g['class_chosen'][c] or '-'}; class "
                      f"named {g['class_object'][c] or '-'} ({views[c]} views): learn pushes "
                      f"{' '.join(g['class_learn_pushes'][c]) or 'none'}")
        ev.append("choices: " + " ".join(status))
        ev.append("faults: " + " ".join(
            f"r{r + 1}:{'+'.join(sorted(set(faults[r])))}" for r in rounds if faults[r]))
        flags = Counter()
        for st in status:
            for part in st.split(":", 1)[1].split(","):
                why = part.split(":", 1)[1]
                why = re.sub(r"[(].*", "", re.sub(r"-class-\d+", "", why))
                for w in why.split("/"):
                    flags[f"at a choice: {w}"] += 1
        rows.append((obj, cause, ev, flags))
    extra = [f"{g.get('off_table', 0)} off the table"] if g.get("off_table", 0) else []
    co = g["class_object"]
    dup = [f"round {c + 1} ({co[c]}, chose {g['class_chosen'][c] or '-'})"
           for c in range(len(co)) if co[c] and co[c] in co[:c]]
    if dup:
        extra.append("rounds spent on an object learned already: " + ", ".join(dup))
    return named, rows, extra


def why_self(choose, k):
    """Why selfsupervise's choice passed over blob k: at random, claimed by a learned class's
    look (the class), or a lower score (its distance to the nearest class, against the chosen;
    --choice dirichlet: its best log score under the classes, higher than the chosen's)."""
    if choose.get("why", "").startswith("at random"):
        return "not-drawn"
    sc = {s["blob"]: s for s in choose.get("scores", [])}
    s = sc.get(k)
    if s is None:
        return "?"
    if s.get("claimed_by", -1) >= 0 and not choose["why"].startswith("every blob"):
        return f"claimed-by-class-{s['claimed_by'] + 1}"
    if "nearest" not in s and "best_log_score" in s:
        # --choice dirichlet: the least likely blob under the classes' models is chosen.
        best = sc.get(choose["blob"], {}).get("best_log_score", float("nan"))
        return f"more-likely({s['best_log_score']:.1f}>{best:.1f})"
    best = sc.get(choose["blob"], {}).get("nearest", float("nan"))
    return f"lower-score({s.get('nearest', float('nan')):.2f}<{best:.2f})"


def main(args):
    runs = args
    if not runs:
        print(__doc__)
        return 2
    total = Counter()
    flag_total = Counter()
    named_total = 0
    for run in runs:
        is_learn = learn_runs.exists(run)
        named, rows, extra = (trace_learn if is_learn else trace_self)(run)
        named_total += len(named)
        print(f"== {run}: {len(rows)} of {len(named)} named objects missed"
              + "".join(f", {x}" for x in extra))
        for obj, cause, ev, flags in rows:
            total[cause] += 1
            flag_total.update(flags)
            print(f"  {obj:10s} cause {cause} ({CAUSES[cause]})")
            for x in ev:
                print(f"      {x}")
    print(f"== causes over the {len(runs)} runs ({sum(total.values())} of {named_total} named "
          f"objects missed):")
    for k in sorted(CAUSES):
        print(f"  {total[k]:3d}  {k} {CAUSES[k]}")
    print("== what else the missed objects' logs say (counts over them):")
    for k, v in sorted(flag_total.items()):
        print(f"  {v:4d}  {k}")
    if PUSHES:
        print("== learn runs' executed pushes (ground truth: intended against the turn's choice):")
        for k, v in sorted(PUSHES.items()):
            print(f"  {v:4d}  {k}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
