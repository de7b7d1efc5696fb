#!/usr/bin/python3
"""Session 44: which signal tells a robot's rounds of one object from rounds of two objects?
Reads runs made with --rounds (DIR/motion-sS.json, and DIR/motion-sS/decisions.jsonl or the
events saved as DIR/motion-sS-rounds.jsonl), whose "distance" events log every pair of rounds'
distances: the views' words (word_distance), the views' colour words (view_colour_distance) and
the looks' colours (look_colour_distance). A pair is "one object" when the ground truth names
the same object as pushed most in both rounds. Prints per signal the AUC (the chance that a
random one-object pair is nearer than a random two-object pair) and, were the rounds grouped
into C = 4 classes by average linkage on that signal, how many of the 4 objects get a class (a
group is named after its rounds' most frequent object), against what the oracle grouping would
give (every object pushed in some round gets a class).
usage: diag44.py DIR SEED...   Standard library only."""
import json, statistics, sys

d, seeds = sys.argv[1], [int(s) for s in sys.argv[2:]]
SIGNALS = ("word_distance", "view_colour_distance", "look_colour_distance")


def events(s):
    for p in (f"{d}/motion-s{s}/decisions.jsonl", f"{d}/motion-s{s}-rounds.jsonl"):
        try:
            return [json.loads(l) for l in open(p)]
        except FileNotFoundError:
            pass
    return []


def average_linkage(rounds, dist, k):
    groups = [[r] for r in rounds]
    while len(groups) > k:
        _, i, j = min((statistics.mean(dist[(a, b)] for a in g for b in h), i, j)
                      for i, g in enumerate(groups) for j, h in enumerate(groups) if i < j)
        groups[i] += groups.pop(j)
    return groups


def covered(groups, ro):
    names = set()
    for g in groups:
        objs = [ro[r] for r in g if ro[r]]
        if objs:
            names.add(max(objs, key=lambda o: (objs.count(o), -objs.index(o))))
    return len(names)


pairs = {s: ([], []) for s in SIGNALS + ("rank sum of the colours",)}
cov = {s: [] for s in SIGNALS + ("rank sum of the colours",)}
oracle, actual = [], []
for s in seeds:
    j = json.load(open(f"{d}/motion-s{s}.json"))
    ro = j["ground_truth"]["round_object"]
    ev = [e for e in events(s) if e["event"] == "distance" and "merged" in e]
    if not ev or not all(k in e for e in ev for k in SIGNALS):
        print(f"seed {s}: no diagnostic distances; left out")
        continue
    rounds = sorted({r for e in ev for r in e["merged"]})
    dist = {k: {} for k in cov}
    for k in SIGNALS:
        vals = sorted(e[k] for e in ev)
        for e in ev:
            a, b = e["merged"]
            dist[k][(a, b)] = dist[k][(b, a)] = e[k]
    # The two colour signals by their ranks within the run, summed (neither's scale counts).
    rank = {k: {v: i for i, v in enumerate(sorted(e[k] for e in ev))} for k in SIGNALS[1:]}
    for e in ev:
        a, b = e["merged"]
        v = sum(rank[k][e[k]] for k in SIGNALS[1:])
        dist["rank sum of the colours"][(a, b)] = dist["rank sum of the colours"][(b, a)] = v
    for k in cov:
        for e in ev:
            a, b = e["merged"]
            if ro[a] and ro[b]:
                pairs[k][0 if ro[a] == ro[b] else 1].append(dist[k][(a, b)])
        cov[k].append(covered(average_linkage(rounds, dist[k], 4), ro))
    oracle.append(len({ro[r] for r in rounds if ro[r]}))
    actual.append(sum(1 for o in j["ground_truth"]["objects"] if o["classes"]))


def auc(one, two):
    if not one or not two:
        return float("nan")
    wins = sum((x < y) + 0.5 * (x == y) for x in one for y in two)
    return wins / (len(one) * len(two))


n = len(oracle)
print(f"{n} runs; round pairs: {len(pairs['word_distance'][0])} of one object, "
      f"{len(pairs['word_distance'][1])} of two")
print("| signal | AUC (one-object pairs nearer) | objects with a class, average linkage into 4 |")
print("|---|---|---|")
for k in cov:
    print(f"| {k} | {auc(*pairs[k]):.3f} | {statistics.mean(cov[k]):.2f} |")
print(f"| the run's own grouping (pooled looks' colours) | | {statistics.mean(actual):.2f} |")
print(f"| oracle (every object pushed in some round) | | {statistics.mean(oracle):.2f} |")
