#!/usr/bin/python3
"""Session 30's decision rule (docs/results/push.md): the loop's defaults against the defaults with
--first-hand-margin 0.01. Usage: rule30.py BASE_FEAS.json CAND_FEAS.json BASE_ISSUE.json
CAND_ISSUE.json  (stdlib only). All must hold:
  1. feasible targets (--target-clearance 0.01): only intended per executed table not lower
     (point estimates) and executed tables not fewer by more than 1;
  2. feasible targets: tables (of all) within the loop's tolerance not fewer by more than 3;
  3. feasible targets: median final distance (executed) below 20 mm and not above the defaults'
     by more than 2 mm;
  4. the issue's targets: 1 and 2 as above;
  5. a gain: only-intended tables, summed over both target distributions, more than the
     defaults' (an option that changes nothing does not become a default).
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
fails = check(sys.argv[1], sys.argv[2], True, 'feasible targets')
fails += check(sys.argv[3], sys.argv[4], False, "issue's targets")
gain = 0
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
if gain <= 0:
    fails.append(f'5: only-intended tables over both distributions {gain:+d}, not a gain')
print(f'only-intended tables over both distributions: {gain:+d}')
print('rule30: ' + ('PASSES' if not fails else 'FAILS: ' + '; '.join(fails)))
