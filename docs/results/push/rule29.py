#!/usr/bin/python3
"""Session 29's decision rule (docs/results/push.md): the loop's defaults against the defaults with
--correction-hand-margin 0.01. Usage: rule29.py BASE_FEAS.json CAND_FEAS.json [BASE_ISSUE.json
CAND_ISSUE.json]  (stdlib only). Feasible targets (--target-clearance 0.01), all must hold:
  1. only intended per executed table not lower (point estimates) and executed tables not fewer
     by more than 1;
  2. tables (of all) within the loop's tolerance not fewer by more than 3;
  3. median final distance (executed) below 20 mm and not above the defaults' by more than 2 mm.
The issue's targets (when given): 1 and 2 as above. Prints each file's figures (rule24.py's
figures, per object too) and PASSES or FAILS with the conditions that failed."""
import json
import sys

from rule24 import figures, show  # noqa: F401  (show prints the figures and per object)
from summarise import median


def load(path):
    j = json.load(open(path))
    return j['pushes'], j['options'].get('tolerance', 0.015)


def check(base, cand, with_median, label):
    (br, bt), (cr, ct) = load(base), load(cand)
    _, be, bo, bw, bd = figures(br, bt)
    _, ce, co, cw, cd = figures(cr, ct)
    bm, cm = median(bd), median(cd)
    fails = []
    if co / max(ce, 1) < bo / max(be, 1):
        fails.append(f'{label} 1: only intended {co}/{ce} below {bo}/{be}')
    if ce < be - 1:
        fails.append(f'{label} 1: executed {ce} fewer than {be} - 1')
    if cw < bw - 3:
        fails.append(f'{label} 2: within tolerance {cw} fewer than {bw} - 3')
    if with_median and not (cm < 0.020 and cm <= bm + 0.002):
        fails.append(f'{label} 3: median {1000 * cm:.1f} mm (defaults {1000 * bm:.1f} mm)')
    print(f'{label}: only intended {co}/{ce} against {bo}/{be}; within tolerance {cw} against '
          f'{bw}; median {1000 * cm:.1f} against {1000 * bm:.1f} mm')
    return fails


def main():
    for path in sys.argv[1:]:
        rows, tol = load(path)
        print(f'== {path}')
        show('all', rows, tol)
    fails = check(sys.argv[1], sys.argv[2], True, 'feasible targets')
    if len(sys.argv) >= 5:
        fails += check(sys.argv[3], sys.argv[4], False, "issue's targets")
    print('rule29: ' + ('PASSES' if not fails else 'FAILS: ' + '; '.join(fails)))


if __name__ == '__main__':
    main()
