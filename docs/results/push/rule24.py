#!/usr/bin/python3
"""Session 24's decision rule (docs/results/push.md): for each `proprio evaluate push --json` file,
only intended per executed table (Wilson 95%), tables of all whose pushed object ended within the
loop's tolerance (final_distance <= options.tolerance; a table with no executed push counts as not
within), the median final distance over the executed tables (bootstrap 95%), and per object the
same three. Usage: rule24.py BASE.json CANDIDATE.json  (stdlib only, seeded). Prints whether the
candidate passes: not lower on the first two, median below 20 mm."""
import json
import sys
from collections import defaultdict

from summarise import boot, median, wilson  # the same statistics as summarise.py


def figures(rows, tol):
    ex = [r for r in rows if r['final_distance'] is not None]
    only = sum(r['only_intended'] for r in ex)
    within = sum(r['final_distance'] <= tol for r in ex)
    d = [r['final_distance'] for r in ex]
    return len(rows), len(ex), only, within, d


def show(name, rows, tol):
    n, e, only, within, d = figures(rows, tol)
    w = wilson(only, e)
    t = wilson(within, n)
    lo, hi = boot(d)
    rate = only / e if e else float('nan')
    print(f"  {name:13s} tables {n:3d} executed {e:3d}  only intended {only}/{e} = "
          f"{100 * rate:.0f}% [{100 * w[0]:.0f}, {100 * w[1]:.0f}]  within tolerance {within}/{n} "
          f"[{100 * t[0]:.0f}, {100 * t[1]:.0f}]%  median {1000 * median(d):.0f} mm "
          f"[{1000 * lo:.0f}, {1000 * hi:.0f}]")
    return rate, within, median(d)


res = []
for path in sys.argv[1:]:
    j = json.load(open(path))
    tol = j['options'].get('tolerance', 0.015)
    rows = j['pushes']
    print(f"== {path} (tolerance {1000 * tol:.0f} mm)")
    res.append(show('all', rows, tol))
    by = defaultdict(list)
    for r in rows:
        by[r['object']].append(r)
    for name in sorted(by):
        show(name, by[name], tol)
if len(res) == 2:
    (br, bw, bm), (cr, cw, cm) = res
    ok = [cr >= br, cw >= bw, cm < 0.020]
    print(f"rule: only intended {'not lower' if ok[0] else 'LOWER'}, within tolerance "
          f"{'not lower' if ok[1] else 'LOWER'}, median {'below' if ok[2] else 'NOT below'} 20 mm "
          f"-> {'PASSES' if all(ok) else 'FAILS'}")
