#!/usr/bin/python3
"""Session 31's decision rule (docs/results/push.md): the loop's defaults against the defaults with
--refusal-pose-margin 0.01. Usage: rule31.py BASE_FEAS.json CAND_FEAS.json BASE_ISSUE.json
CAND_ISSUE.json  (stdlib only). All must hold:
  1. feasible targets (--target-clearance 0.01): only-intended tables of all (a table not
     executed is not done) not fewer than the defaults'; only intended per executed table not
     lower than the defaults' by more than 2 percentage points; executed tables not fewer by
     more than 1;
  2. feasible targets: tables (of all) within the loop's tolerance not fewer by more than 3;
  3. feasible targets: median final distance (executed) below 20 mm and not above the defaults'
     by more than 2 mm;
  4. the issue's targets: 1 and 2 as above;
  5. a gain: only-intended tables, summed over both target distributions, more than the
     defaults' (rule30.py's 5);
  6. objects off the table, summed over both distributions, not more than the defaults'.
Conditions 2-4 are rule29.py's code (check(), as rule30.py uses it). Its condition 1 compares
only intended per executed table strictly; an option that executes tables the robot refused
(harder tables, the denominator grows) is judged here by only-intended tables of all, with the
per-executed rate allowed 2 points lower: check()'s strict failure is printed, not counted.
Prints each file's figures (rule24.py's, per object too), the tables whose only-intended
changed, and PASSES or FAILS with the conditions that failed."""
import sys

from rule24 import figures, show
from rule29 import check, load  # conditions 1-3 (rule29.py's, the same code)


if len(sys.argv) != 5:
    sys.exit(__doc__)
for path in sys.argv[1:]:
    rows, tol = load(path)
    print(f'== {path}')
    show('all', rows, tol)
fails = []
for base, cand, median_too, label in ((sys.argv[1], sys.argv[2], True, 'feasible targets'),
                                      (sys.argv[3], sys.argv[4], False, "issue's targets")):
    for f in check(base, cand, median_too, label):
        if f.startswith(f'{label} 1: only intended'):
            print(f'  (rule29 condition 1, per executed table, strict: {f}; replaced by 1 below)')
        else:
            fails.append(f)
    (br, bt), (cr, ct) = load(base), load(cand)
    _, be, bo, _, _ = figures(br, bt)
    _, ce, co, _, _ = figures(cr, ct)
    if co < bo:
        fails.append(f'{label} 1: only-intended tables {co} fewer than {bo}')
    if co / max(ce, 1) < bo / max(be, 1) - 0.02:
        fails.append(f'{label} 1: only intended per executed {co}/{ce} more than 2 points below '
                     f'{bo}/{be}')
gain = 0
off = 0
for base, cand in ((sys.argv[1], sys.argv[2]), (sys.argv[3], sys.argv[4])):
    (br, _), (cr, _) = load(base), load(cand)
    b = {r['seed']: r for r in br}
    for r in cr:
        o = b.get(r['seed'])
        bo = o is not None and o['final_distance'] is not None and o['only_intended']
        co = r['final_distance'] is not None and r['only_intended']
        if bo != co:
            print(f'  {cand}: table {r["seed"]} ({r["object"]}) only intended {bo} -> {co}')
    gain += figures(cr, 0.015)[2] - figures(br, 0.015)[2]
    off += sum(r['off_table'] for r in cr) - sum(r['off_table'] for r in br)
if gain <= 0:
    fails.append(f'5: only-intended tables over both distributions {gain:+d}, not a gain')
if off > 0:
    fails.append(f'6: objects off the table {off:+d} against the defaults')
print(f'only-intended tables over both distributions: {gain:+d}; objects off the table: {off:+d}')
print('rule31: ' + ('PASSES' if not fails else 'FAILS: ' + '; '.join(fails)))
