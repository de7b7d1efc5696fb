#!/usr/bin/python3
"""Session 25: why margin + split ends farther than split alone. Usage: why25.py SPLIT.json MARGIN_SPLIT.json
(run from the repository root). Paired tables, shortened pushes, per object."""
import json, sys
from collections import defaultdict
sys.path.insert(0, 'docs/results/push')
from summarise import median
A = {r['seed']: r for r in json.load(open(sys.argv[1]))['pushes']}   # split alone
B = {r['seed']: r for r in json.load(open(sys.argv[2]))['pushes']}   # margin + split
worse, better, same = [], [], []
for s in sorted(A):
    a, b = A[s], B[s]
    if a['final_distance'] is None or b['final_distance'] is None: continue
    d = b['final_distance'] - a['final_distance']
    (worse if d > 0.002 else better if d < -0.002 else same).append(s)
print(f"both executed {len(worse)+len(better)+len(same)}: m+s worse {len(worse)}, better {len(better)}, within 2 mm {len(same)}")
def desc(r):
    st = r['steps']
    return ' | '.join(f"{'ex' if x['executed'] else 'no'} sh{1000*x.get('shortened',0):.0f} bl{1000*x.get('blocked',0):.0f} d{1000*(x['true_distance'] or -1):.0f}" for x in st)
short_w = 0
for s in worse:
    a, b = A[s], B[s]
    sh = any(x.get('shortened', 0) > 0 for x in b['steps'])
    short_w += sh
    print(f"{s:4d} {b['object']:13s} split {1000*a['final_distance']:4.0f} mm ({a['pushes']}p) m+s {1000*b['final_distance']:4.0f} mm ({b['pushes']}p) oi {a['only_intended']}/{b['only_intended']}\n      split: {desc(a)}\n      m+s:   {desc(b)}")
print(f"worse tables with a shortened push under m+s: {short_w}/{len(worse)}")
# over all executed tables: tables with any shortened push; their final distances
for nm, T in (('split', A), ('m+s', B)):
    ex = [r for r in T.values() if r['final_distance'] is not None]
    sh = [r for r in ex if any(x.get('shortened', 0) > 0 for x in r['steps'])]
    ns = [r for r in ex if not any(x.get('shortened', 0) > 0 for x in r['steps'])]
    print(f"{nm}: executed {len(ex)}; with a shortened push {len(sh)} median {1000*median([r['final_distance'] for r in sh]) if sh else float('nan'):.0f} mm; without {len(ns)} median {1000*median([r['final_distance'] for r in ns]):.0f} mm")
    nshort = sum(1 for r in ex for x in r['steps'] if x.get('shortened', 0) > 0)
    print(f"   pushes shortened {nshort}; last push shortened on {sum(1 for r in ex if r['steps'][-1].get('shortened',0)>0)} tables")
by = defaultdict(lambda: [[], []])
for s in A:
    if A[s]['final_distance'] is None or B[s]['final_distance'] is None: continue
    by[A[s]['object']][0].append(A[s]['final_distance']); by[A[s]['object']][1].append(B[s]['final_distance'])
print("per object, tables both executed: n, median split, median m+s (mm)")
for o in sorted(by):
    print(f"  {o:13s} {len(by[o][0]):3d} {1000*median(by[o][0]):4.0f} {1000*median(by[o][1]):4.0f}")
