#!/usr/bin/python3
"""Why tables are not executed or miss (session 31), from `proprio evaluate push --json`:
  - tables not executed: object not seen; not planned; refused by the robot, split by what the
    arm would meet (the pushed object itself or a neighbour) and by which link (arm_palm, the
    fingers and pusher = the hand; arm_link2/3 = the upper arm and above);
  - executed tables whose loop ended on a push not made: a refusal (same split), a correction not
    made by correction_hand_margin, or the second leg of a waypoint push (a first push through
    a waypoint and no later push made);
  - objects off the table; executed tables beyond 2 cm.
Usage: why31.py EVAL.json [...]  (stdlib only)."""
import collections
import json
import re
import sys

MET = re.compile(r"would meet an object \((.+?) \(by (\S+)\) at")


def link(part):
    if part.startswith('arm_link'):
        return 'upper arm (' + part.replace('_geom', '') + ')'
    return 'hand (' + part.replace('_geom', '') + ')'


def refusal(msg, pushed):
    m = MET.search(msg or '')
    if not m:
        return 'refused (unparsed)'
    what = 'the pushed object itself' if m.group(1) == pushed else 'a neighbour'
    return f'{what} by the {link(m.group(2))}'


for path in sys.argv[1:]:
    d = json.load(open(path))
    rows = d['pushes']
    ex = [r for r in rows if r['final_distance'] is not None]
    print(f'== {path}: {len(rows)} tables, {len(ex)} executed')
    why = collections.defaultdict(list)
    for r in rows:
        if r['final_distance'] is not None:
            continue
        if r['outcome'] == 'robot-refused':
            why['not executed: refused, ' + refusal(r.get('message'), r['object'])].append(r['seed'])
        else:
            why['not executed: ' + r['outcome']].append(r['seed'])
    later = collections.defaultdict(list)
    for r in ex:
        steps = r['steps']
        made = [s for s in steps if s['executed']]
        last = steps[-1]
        if not last['executed']:
            msg = last['message']
            tag = 'second leg of a waypoint' if made and made[-1].get('via') else 'correction'
            if 'transit' in msg:
                later[f'{tag} refused, ' + refusal(msg, r['object'])].append(
                    f"{r['seed']} ({1000 * r['final_distance']:.0f} mm)")
            elif 'correction not made' in msg:
                later[f'{tag} not made (correction_hand_margin)'].append(
                    f"{r['seed']} ({1000 * r['final_distance']:.0f} mm)")
            else:
                later[f'{tag} not planned'].append(f"{r['seed']} ({1000 * r['final_distance']:.0f} mm)")
        elif made[-1].get('via'):
            later['second leg of a waypoint: none after it'].append(
                f"{r['seed']} ({1000 * r['final_distance']:.0f} mm)")
    for k in sorted(why):
        print(f'  {k}: {len(why[k])} ({", ".join(map(str, why[k]))})')
    for k in sorted(later):
        print(f'  executed, loop ended on {k}: {len(later[k])} ({", ".join(later[k])})')
    off = [r['seed'] for r in rows if r['off_table']]
    far = [r['seed'] for r in ex if r['final_distance'] > 0.02]
    print(f'  off the table: {len(off)} {off}; executed beyond 2 cm: {len(far)}; '
          f'not only intended: {sum(not r["only_intended"] for r in ex)}')
