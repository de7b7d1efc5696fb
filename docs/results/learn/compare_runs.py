#!/usr/bin/python3
"""Compare two proprio learn run directories' learn.json, ignoring only timings and paths.

Ignored keys (and nothing else):
  seconds                       top level: the run's wall clock, s
  timing                        per stage wall-clock seconds and cpu_seconds
  pushes[*].perception_cpu_seconds   a push's perception processor time
  options.out                   the run directory (a path)
  provenance.command_line       holds the binary's path and the out path
  provenance.created_utc        the wall-clock time the run was made
  provenance.git_commit         names the binary's build (differs by design)
Also reported (extra evidence, not part of the verdict): decisions.jsonl line by line.
Usage: compare_runs.py A_DIR B_DIR  -> prints SAME or the differing keys; exit 0 iff SAME.
"""
import json
import sys

IGNORE_TOP = {"seconds", "timing"}
IGNORE_PATHS = {("options", "out"), ("provenance", "command_line"),
                ("provenance", "created_utc"), ("provenance", "git_commit")}
IGNORE_PUSH = {"perception_cpu_seconds"}


def diff(a, b, path, out):
    if isinstance(a, dict) and isinstance(b, dict):
        for k in sorted(set(a) | set(b)):
            p = path + (k,)
            if len(p) == 1 and k in IGNORE_TOP:
                continue
            if p in IGNORE_PATHS:
                continue
            if len(p) == 3 and p[0] == "pushes" and k in IGNORE_PUSH:
                continue
            if k not in a or k not in b:
                out.append(("/".join(map(str, p)), "missing on one side"))
                continue
            diff(a[k], b[k], p, out)
    elif isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            out.append(("/".join(map(str, path)), f"lengths {len(a)} vs {len(b)}"))
        for i, (x, y) in enumerate(zip(a, b)):
            diff(x, y, path + (i,), out)
    elif a != b or type(a) is not type(b):
        out.append(("/".join(map(str, path)), f"{a!r} vs {b!r}"[:200]))


def main():
    da, db = sys.argv[1], sys.argv[2]
    a = json.load(open(da + "/learn.json"))
    b = json.load(open(db + "/learn.json"))
    out = []
    diff(a, b, (), out)
    la = open(da + "/decisions.jsonl").read().splitlines()
    lb = open(db + "/decisions.jsonl").read().splitlines()
    dec = sum(1 for x, y in zip(la, lb) if x != y) + abs(len(la) - len(lb))
    extra = f"decisions.jsonl: {len(la)} vs {len(lb)} lines, {dec} differ"
    if out:
        print(f"DIFFERENT ({len(out)} keys); {extra}")
        for k, v in out[:20]:
            print("  ", k, v)
        return 1
    print(f"SAME learn.json; {extra}")
    return 0


sys.exit(main())
