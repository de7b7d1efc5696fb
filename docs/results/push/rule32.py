#!/usr/bin/python3
"""Session 32's decision rule (docs/results/push.md), written and committed before any run of the
fresh seeds 11001-11100: the loop's defaults against the defaults with --tall-start-clearance
0.001 (chosen on tuning seeds 1-100 over 0.01: only-intended tables 87 and 79 against 85 and 76,
the defaults 90 and 83; by this rule both fail on tuning). Usage: rule32.py BASE_FEAS.json CAND_FEAS.json BASE_ISSUE.json CAND_ISSUE.json (stdlib
only; each a merged `proprio evaluate push --json` file of the same 100 tables). The option
becomes the loop's default only if all hold, for each target distribution (feasible targets,
--target-clearance 0.01, and the issue's) separately:
  1. objects off the table not more than the defaults';
  2. only-intended tables of all (a table not executed or not planned is not done) not fewer
     than the defaults' by more than 1;
  3. median final distance (executed tables) not above the defaults' by more than 2 mm;
and, summed over both distributions,
  4. objects off the table not more than the defaults' (1 on each implies it; kept explicit).
Prints each file's figures (rule24.py's, per object too), the tables whose only-intended or
off-the-table count changed, and PASSES or FAILS with the conditions that failed."""
import json
import sys

from rule24 import figures, show
from summarise import median


def load(path):
    j = json.load(open(path))
    return j['pushes'], j['options'].get('tolerance', 0.015)


def done(r):
    return r['final_distance'] is not None and r['only_intended']


if len(sys.argv) != 5:
    sys.exit(__doc__)
for path in sys.argv[1:]:
    rows, tol = load(path)
    print(f'== {path}')
    show('all', rows, tol)
fails = []
off_sum = 0
for base, cand, label in ((sys.argv[1], sys.argv[2], 'feasible targets'),
                          (sys.argv[3], sys.argv[4], "issue's targets")):
    (br, bt), (cr, ct) = load(base), load(cand)
    if sorted(r['seed'] for r in br) != sorted(r['seed'] for r in cr):
        fails.append(f'{label}: the two files hold different tables')
    _, be, bo, bw, bd = figures(br, bt)
    _, ce, co, cw, cd = figures(cr, ct)
    boff = sum(r['off_table'] for r in br)
    coff = sum(r['off_table'] for r in cr)
    off_sum += coff - boff
    bm, cm = median(bd), median(cd)
    print(f'{label}: off the table {coff} against {boff}; only-intended tables {co} (of {ce} '
          f'executed) against {bo} (of {be}); within tolerance {cw} against {bw}; median '
          f'{1000 * cm:.1f} against {1000 * bm:.1f} mm')
    if coff > boff:
        fails.append(f'{label} 1: objects off the table {coff} more than {boff}')
    if co < bo - 1:
        fails.append(f'{label} 2: only-intended tables {co} fewer than {bo} - 1')
    if cm > bm + 0.002:
        fails.append(f'{label} 3: median {1000 * cm:.1f} mm above {1000 * bm:.1f} + 2 mm')
    b = {r['seed']: r for r in br}
    for r in cr:
        o = b.get(r['seed'])
        if o is None:
            continue
        if done(o) != done(r) or o['off_table'] != r['off_table']:
            print(f'  {label}: table {r["seed"]} ({r["object"]}) only intended {done(o)} -> '
                  f'{done(r)}, off the table {o["off_table"]} -> {r["off_table"]}, outcome '
                  f'{o["outcome"]} -> {r["outcome"]}')
if off_sum > 0:
    fails.append(f'4: objects off the table over both distributions {off_sum:+d}')
print(f'objects off the table over both distributions: {off_sum:+d}')
print('rule32: ' + ('PASSES' if not fails else 'FAILS: ' + '; '.join(fails)))
