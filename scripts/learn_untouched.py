#!/usr/bin/python3
"""Offline estimate for learn's untouched_radius (session 37): at each turn's choice after the first, the candidates
that no executed push has passed near and that stand where the first look saw a candidate.
Ground truth: ground_truth.class_blobs (objects under each blob of the turn's choice look).
Only turns with one choose event (class_blobs is the last choice's). Runs read by scripts/learn_runs.py.
usage: scripts/learn_untouched.py RADIUS SAME RUN_DIR... (e.g. 0.06 0.03 OUT/D/quick-s51 ...)
"""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import learn_runs  # noqa: E402

R_PUSH = float(sys.argv[1]); R_SAME = float(sys.argv[2]); runs = sys.argv[3:]
def seg_dist(p, a, b):
    ax, ay = a; bx, by = b; px, py = p
    dx, dy = bx - ax, by - ay; L = dx*dx + dy*dy
    t = 0 if L == 0 else max(0, min(1, ((px-ax)*dx + (py-ay)*dy) / L))
    return math.hypot(px - (ax + t*dx), py - (ay + t*dy))
tot = dict(turns=0, with_untouched=0, untouched=0, untouched_new=0, untouched_learned=0,
           untouched_other=0, chosen_repeat=0, repeat_with_untouched_new=0, chosen_new=0)
for run in runs:
    r = learn_runs.load(run); g = r.truth
    table = r.table()
    first = r.first_look_centres()
    for c, turn in r.turns().items():
        if c == 0 or len(turn.choices) != 1 or c >= len(g['class_blobs']): continue
        choice = turn.choices[0]; e, done = choice.event, choice.pushed; look = turn.look
        if look is None: continue
        cents = look['centres']; truth = g['class_blobs'][c]
        if len(truth) != len(cents): continue
        learned = {x for x in g['class_chosen'][:c] if x}
        skipped = {k['blob']: k['reason'] for k in e.get('skipped', [])}
        tot['turns'] += 1
        unt = []
        for b, p in enumerate(cents):
            if skipped.get(b) in ('out-of-reach', 'no-features'): continue
            if any(seg_dist(p, a, z) < R_PUSH for a, z in done): continue
            if not any(math.hypot(p[0]-q[0], p[1]-q[1]) < R_SAME for q in first): continue
            unt.append(b)
        if unt: tot['with_untouched'] += 1
        new_unt = False
        for b in unt:
            o = truth[b]; tot['untouched'] += 1
            if o in table and o not in learned: tot['untouched_new'] += 1; new_unt = True
            elif o in learned: tot['untouched_learned'] += 1
            else: tot['untouched_other'] += 1
        ch = g['class_chosen'][c]
        if ch in learned: 
            tot['chosen_repeat'] += 1
            if new_unt: tot['repeat_with_untouched_new'] += 1
        elif ch in table: tot['chosen_new'] += 1
print(tot)
