#!/usr/bin/python3
"""Merge `proprio evaluate push --json` files of consecutive seed chunks (e.g. ten runs of
`--tables 10`) into one: the tables' rows in seed order, options.tables and options.seed of the
whole, each chunk's command line kept, the counts recomputed. Usage: merge.py OUT.json IN.json...
(stdlib only)."""
import json
import os
import sys


def clean(cmd):
    """The program named `proprio`, the --json file's folder OUT/: no machine paths."""
    w = cmd.split()
    w[0] = 'proprio'
    for i in range(len(w) - 1):
        if w[i] == '--json':
            w[i + 1] = 'OUT/' + os.path.basename(w[i + 1])
    return ' '.join(w)

parts = sorted((json.load(open(p)) for p in sys.argv[2:]), key=lambda j: j['options']['seed'])
out = {k: parts[0][k] for k in ('format', 'format_version', 'planner')}
out['options'] = dict(parts[0]['options'])
rows = [r for j in parts for r in j['pushes']]
out['options']['tables'] = len(rows)
out['pushes'] = rows
out['provenance'] = dict(parts[0]['provenance'])
out['provenance']['command_line'] = [clean(j['provenance']['command_line']) for j in parts]
out['seconds'] = sum(j['seconds'] for j in parts)
for k in ('not_seen', 'planned', 'refused', 'not_planned', 'off_table'):
    out[k] = sum(j[k] for j in parts)
ex = [r for r in rows if r['final_distance'] is not None]
out['only_intended_rate'] = sum(r['only_intended'] for r in ex) / max(1, len(ex))
json.dump(out, open(sys.argv[1], 'w'), indent=1, sort_keys=True)
