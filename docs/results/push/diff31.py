#!/usr/bin/python3
"""The tables two `proprio evaluate push --json` files differ on (session 31): outcome, executed
pushes, final distance (> 2 mm apart), only intended, off the table; each side's last step's
message when a push was not made. Usage: diff31.py BASE.json CAND.json  (stdlib only)."""
import json
import sys

a = {t['seed']: t for t in json.load(open(sys.argv[1]))['pushes']}
b = {t['seed']: t for t in json.load(open(sys.argv[2]))['pushes']}


def desc(r):
    d = r['final_distance']
    made = sum(s['executed'] for s in r['steps'])
    via = ''.join('v' if s.get('via') else '.' for s in r['steps'] if s['executed'])
    s = f"{r['outcome']}" if d is None else f"{1000 * d:.0f} mm, {made} push(es) [{via}], only {r['only_intended']}"
    if r['off_table']:
        s += ', OFF TABLE'
    last = r['steps'][-1] if r['steps'] else None
    if last is not None and not last['executed']:
        s += ' | last not made: ' + last['message'][:110]
    return s


n = 0
for s in sorted(set(a) & set(b)):
    x, y = a[s], b[s]
    dx, dy = x['final_distance'], y['final_distance']
    same = (dx is None) == (dy is None) and (dx is None or abs(dx - dy) <= 0.002) and \
        x['only_intended'] == y['only_intended'] and x['off_table'] == y['off_table']
    if same:
        continue
    n += 1
    print(f"{s} {x['object']}:\n  base {desc(x)}\n  cand {desc(y)}")
print(f'{n} tables differ')
