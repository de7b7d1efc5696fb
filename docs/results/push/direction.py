#!/usr/bin/python3
"""First executed push of each table: true distance after it, by the push's direction against the
arm's radius (|cos| of the push to the direction from the base at the start > 0.9: radial; else
across). Usage: direction.py EVAL.json [...]"""
import json, math, sys

def med(v):
    v = sorted(v); n = len(v)
    return float('nan') if not n else (v[n//2] if n % 2 else 0.5*(v[n//2-1]+v[n//2]))

for f in sys.argv[1:]:
    d = json.load(open(f))
    rad, tan, pairs = [], [], {}
    for t in d['pushes']:
        for s in t.get('steps', []):
            if not s.get('executed') or s.get('true_distance') is None or s['true_distance'] < 0:
                continue
            sx, sy = s['start']; ex, ey = s['end']
            dx, dy = ex-sx, ey-sy; L = math.hypot(dx, dy); r = math.hypot(sx, sy)
            c = abs((dx*sx+dy*sy)/(L*r)) if L > 0 and r > 0 else 0
            (rad if c > 0.9 else tan).append(s['true_distance']*1000)
            pairs[t['seed']] = (c, s['true_distance']*1000)
            break
    print(f"{f}: first push radial n={len(rad)} median {med(rad):.1f} mm; across n={len(tan)} median {med(tan):.1f} mm")
