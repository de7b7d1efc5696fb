"""Paired comparison of two `proprio experiment clutter --json` files of the same seeds and cells.

usage: /usr/bin/python3 scripts/clutter_compare.py BASE.json OTHER.json [--min-topics 15]

At T >= --min-topics (the issue's measure): the supervised held-out render accuracy of each file
(mean over seeds x fractions x T, worst and best cell), per seed, the paired difference OTHER -
BASE per seed with its 95% interval over the seeds (t, n-1 degrees of freedom), the cells higher
/ equal / lower, per object (mean, per seed, paired with its interval), the confusion matrix of
each file summed over those cells, and the other seeds' pushes (cross_seed) beside.
"""
import json
import statistics
import sys

T975 = {1: 12.71, 2: 4.30, 3: 3.18, 4: 2.78, 5: 2.57, 6: 2.45, 7: 2.36, 8: 2.31, 9: 2.26}


def half_width(values):
    if len(values) < 2:
        return float("nan")
    return T975.get(len(values) - 1, 2.0) * statistics.stdev(values) / len(values) ** 0.5


def main():
    args = sys.argv[1:]
    min_topics = 15
    if "--min-topics" in args:
        i = args.index("--min-topics")
        min_topics = int(args[i + 1])
        del args[i : i + 2]
    base, other = (json.load(open(a)) for a in args)
    objects = base["options"]["objects"]
    if other["options"]["objects"] != objects:
        sys.exit("the files score other objects")

    def cells(d):
        return {
            (c["seed"], c["fraction"], c["topics"]): c for c in d["cells"] if c["topics"] >= min_topics
        }

    b, o = cells(base), cells(other)
    keys = sorted(set(b) & set(o))
    if not keys:
        sys.exit("no common cells")
    seeds = sorted({k[0] for k in keys})
    print(f"T >= {min_topics}: {len(keys)} common cells, seeds {seeds}")
    for name, d in (("base", b), ("other", o)):
        v = [100 * d[k]["supervised"] for k in keys]
        print(f"  {name}: mean {statistics.mean(v):.1f} %, worst {min(v):.1f} %, best {max(v):.1f} %")

    def seed_mean(d, s, f=lambda c: c["supervised"]):
        return 100 * statistics.mean(f(d[k]) for k in keys if k[0] == s)

    bs = [seed_mean(b, s) for s in seeds]
    os_ = [seed_mean(o, s) for s in seeds]
    diff = [x - y for x, y in zip(os_, bs)]
    print("  per seed base:  " + " ".join(f"{x:.1f}" for x in bs))
    print("  per seed other: " + " ".join(f"{x:.1f}" for x in os_))
    print(f"  paired other - base: {statistics.mean(diff):+.1f} +- {half_width(diff):.1f} points")
    hi = sum(o[k]["supervised"] > b[k]["supervised"] + 1e-9 for k in keys)
    lo = sum(o[k]["supervised"] < b[k]["supervised"] - 1e-9 for k in keys)
    print(f"  cells higher {hi}, equal {len(keys) - hi - lo}, lower {lo}")
    print("  per object (mean; per seed; paired other - base):")
    for i, name in enumerate(objects):

        def per(d, s, i=i):
            return seed_mean(d, s, lambda c: c["supervised_per_object"][i])

        pb = [per(b, s) for s in seeds]
        po = [per(o, s) for s in seeds]
        dd = [x - y for x, y in zip(po, pb)]
        print(
            f"    {name:8s} base {statistics.mean(pb):5.1f} ({' '.join(f'{x:.0f}' for x in pb)})"
            f"  other {statistics.mean(po):5.1f} ({' '.join(f'{x:.0f}' for x in po)})"
            f"  {statistics.mean(dd):+.1f} +- {half_width(dd):.1f}"
        )
    for name, d in (("base", b), ("other", o)):
        m = [[0] * len(objects) for _ in objects]
        for k in keys:
            for r, row in enumerate(d[k]["supervised_confusion"]["counts"]):
                for c, n in enumerate(row):
                    m[r][c] += n
        print(f"  {name} confusion summed (rows true, % of row): " + " | ".join(
            f"{objects[r]}: " + " ".join(f"{100 * n / max(1, sum(row)):.0f}" for n in row)
            for r, row in enumerate(m)))
    xs = [k for k in keys if b[k].get("cross_seed") is not None and o[k].get("cross_seed") is not None]
    if xs:
        cb = [100 * b[k]["cross_seed"] for k in xs]
        co = [100 * o[k]["cross_seed"] for k in xs]
        print(f"  other seeds' pushes: base {statistics.mean(cb):.1f} %, other {statistics.mean(co):.1f} %")


if __name__ == "__main__":
    main()
