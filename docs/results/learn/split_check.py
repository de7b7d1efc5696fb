#!/usr/bin/python3
"""Nothing lost in a page split (session 38): every non-blank line of OLD is in CURRENT or HISTORY
as often as it was. Prints how many are missing and the lines the new pages have beyond OLD's
(the new heads, status blocks and edits), so that a reader can check those are all there is.

usage: split_check.py OLD CURRENT HISTORY
  e.g. git show 95a3d40:docs/results/learn.md > OLD; split_check.py OLD learn.md learn-history.md
Exit 0 when no line is missing."""
import sys
from collections import Counter


def lines(path):
    with open(path) as f:
        return Counter(x for x in f.read().splitlines() if x.strip())


def main(old, current, history):
    o, n = lines(old), lines(current) + lines(history)
    missing, extra = o - n, n - o
    print(f"{old}: {sum(o.values())} non-blank lines; {current} + {history}: {sum(n.values())}; "
          f"missing {sum(missing.values())}; beyond the old page {sum(extra.values())}")
    for x in missing:
        print("missing:", x)
    for x in extra:
        print("new:", x)
    return 1 if missing else 0


if __name__ == "__main__":
    if len(sys.argv) != 4:
        print(__doc__)
        sys.exit(2)
    sys.exit(main(*sys.argv[1:]))
