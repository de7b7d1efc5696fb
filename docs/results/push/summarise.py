#!/usr/bin/python3
"""Summarise `proprio evaluate push --json` files: medians with bootstrap 95% intervals, rates with
Wilson intervals, per object. Usage: summarise.py EVAL.json [...]  (stdlib only, seeded)."""
import json
import math
import random
import sys
from collections import defaultdict


def median(v):
    v = sorted(v)
    n = len(v)
    return float('nan') if n == 0 else (v[n // 2] if n % 2 else 0.5 * (v[n // 2 - 1] + v[n // 2]))


def percentile(v, q):
    """As loop::run_push_evaluation: linear between the two nearest ranks."""
    v = sorted(v)
    if not v:
        return float('nan')
    pos = q * (len(v) - 1)
    lo = int(math.floor(pos))
    hi = min(lo + 1, len(v) - 1)
    return v[lo] + (pos - lo) * (v[hi] - v[lo])


def boot(v, q=0.5, n=2000):
    if len(v) < 2:
        return (float('nan'), float('nan'))
    rng = random.Random(1)
    s = sorted(median([rng.choice(v) for _ in v]) for _ in range(n))
    return s[int(0.025 * n)], s[int(0.975 * n) - 1]


def wilson(k, n, z=1.96):
    if n == 0:
        return (float('nan'), float('nan'))
    p = k / n
    d = 1 + z * z / n
    c = (p + z * z / (2 * n)) / d
    h = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / d
    return c - h, c + h


def mm(x):
    return f"{1000 * x:.0f}"


def main():
    for path in sys.argv[1:]:
        j = json.load(open(path))
        rows = j['pushes']
        pushed = [r for r in rows if r['final_distance'] is not None]
        d = [r['final_distance'] for r in pushed]
        first = [r['steps'][0]['true_distance'] for r in pushed
                 if r.get('steps') and r['steps'][0]['true_distance'] is not None]
        ce = [r['centre_error'] for r in pushed if r['centre_error'] is not None]
        only = sum(r['only_intended'] for r in pushed)
        within = sum(x < 0.02 for x in d)
        lo, hi = boot(d)
        flo, fhi = boot(first)
        print(f"== {path}: {len(rows)} tables, {len(pushed)} executed, "
              f"{sum(r['outcome'] == 'object-not-seen' for r in rows)} object not seen")
        print(f"final distance median {mm(median(d))} mm [{mm(lo)}, {mm(hi)}], "
              f"90th pct {mm(percentile(d, 0.9))} mm; "
              f"within 2 cm {within}/{len(d)}")
        print(f"after the first push alone: median {mm(median(first))} mm [{mm(flo)}, {mm(fhi)}]")
        print(f"centre error (first look) median {mm(median(ce))} mm")
        w = wilson(only, len(pushed))
        print(f"only intended {only}/{len(pushed)} = {100 * only / max(1, len(pushed)):.0f}% "
              f"[{100 * w[0]:.0f}, {100 * w[1]:.0f}]; off table {sum(r['off_table'] for r in rows)}; "
              f"pushes per executed table {sum(r.get('pushes', 1) for r in pushed) / max(1, len(pushed)):.2f}")
        touched = sum(r['touched_other'] for r in pushed)
        tw = wilson(touched, len(pushed))
        plan = [r['plan_ms'] for r in pushed]
        print(f"touched another object {touched}/{len(pushed)} = {100 * touched / max(1, len(pushed)):.0f}% "
              f"[{100 * tw[0]:.0f}, {100 * tw[1]:.0f}]; plan time median {median(plan):.0f} ms, "
              f"max {max(plan, default=0):.0f} ms (wall); refused {sum(r['outcome'] == 'robot-refused' for r in rows)}, "
              f"not planned {sum(r['outcome'] == 'not-planned' for r in rows)}")
        by = defaultdict(list)
        for r in rows:
            by[r['object']].append(r)
        print("object        tables seen pushed  median  first  centre_err only")
        for name in sorted(by):
            rs = by[name]
            p = [r for r in rs if r['final_distance'] is not None]
            f = [r['steps'][0]['true_distance'] for r in p
                 if r.get('steps') and r['steps'][0]['true_distance'] is not None]
            print(f"{name:13s} {len(rs):6d} {sum(r['outcome'] != 'object-not-seen' for r in rs):4d} "
                  f"{len(p):6d} {mm(median([r['final_distance'] for r in p])):>7s} {mm(median(f)):>6s} "
                  f"{mm(median([r['centre_error'] for r in p if r['centre_error'] is not None])):>11s} "
                  f"{sum(r['only_intended'] for r in p)}/{len(p)}")
        # Why the closed loop stopped, per executed table.
        why = defaultdict(int)
        biased = 0
        for r in pushed:
            steps = r.get('steps', [])
            done = [s for s in steps if s['executed']]
            last = done[-1] if done else None
            if not steps or last is None:
                continue
            if not steps[-1]['executed']:
                why['a later push not planned or refused'] += 1
            elif 'not found again' in last['message']:
                why['pushed object not found again'] += 1
            elif last['seen_distance'] is not None and last['seen_distance'] <= j['options'].get('tolerance', 0.015):
                why['seen within the tolerance'] += 1
                biased += last['true_distance'] is not None and last['true_distance'] > 0.02
            else:
                why['push budget spent'] += 1
        print("loop stopped: " + ", ".join(f"{k} {v}" for k, v in sorted(why.items())) +
              f" (seen within tolerance but truly > 2 cm off: {biased})")


if __name__ == "__main__":
    main()
