#!/usr/bin/python3
"""Motion views and before views of the same pushes, combined offline (session 40).

Usage: views_combined.py MOTION_DIR BEFORE_DIR SEED...

MOTION_DIR and BEFORE_DIR hold scripts/experiment-learn runs (quick-sSEED/documents.txt) made
with --write-documents, the first with the default views (motion), the second with
--views before. The views do not steer the robot, so both runs of a seed made the same pushes;
their training views are joined by class (learn.json's object_N) and push. Prints, per seed and
on average, the held-out accuracy of learn's colour classifier (views weighed alike, add-one,
naive Bayes with a prior by views) trained on: the motion views, the before views, both, and
both with each before view weighing as much as all the motion views of its push ("both_bw").
Standard library and numpy; reads, never writes.
"""
import collections
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from documents_classifiers import read_documents  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "..", "scripts"))
from oracle_ladder_table import ci  # noqa: E402


def load(path):
    """Views as (class object_N, push, colour counts), class names and held-out views."""
    _, vocab, classes, views, held = read_documents(path)
    key = {}
    with open(path) as f:
        for line in f:
            if line.startswith("class "):
                fields = line.split()
                key[int(fields[1])] = fields[2]
    names = {key[c]: classes[c] for c in classes}
    train = [(key[v[0]], v[1], v[4][vocab:]) for v in views if v[0] >= 0]
    return train, names, held, vocab


def accuracy(train, weights, names, held_x, truth):
    order = sorted({c for c, _, _ in train})
    at = {c: i for i, c in enumerate(order)}
    counts = np.zeros((len(order), held_x.shape[1]))
    n_views = collections.Counter()
    mean_tokens = np.mean([x.sum() for _, _, x in train])
    for (c, _, x), w in zip(train, weights):
        counts[at[c]] += w * mean_tokens * x / max(x.sum(), 1)
        n_views[c] += 1
    log_phi = np.log(counts + 1.0) - np.log((counts + 1.0).sum(1, keepdims=True))
    prior = np.log(np.array([n_views[c] for c in order]) + 1.0)
    pred = (held_x @ log_phi.T + prior).argmax(1)
    per = collections.defaultdict(list)
    for p, t in zip(pred, truth):
        per[t].append(names[order[p]] == t)
    return float(np.mean([np.mean(v) for v in per.values()]))


def main(motion_dir, before_dir, seeds):
    rows = collections.defaultdict(list)
    for s in seeds:
        motion, names_m, held, vocab = load(os.path.join(motion_dir, f"quick-s{s}", "documents.txt"))
        before, names_b, _, _ = load(os.path.join(before_dir, f"quick-s{s}", "documents.txt"))
        names = dict(names_m)
        names.update(names_b)
        held_x = np.array([h[1][vocab:] for h in held])
        truth = [h[0] for h in held]
        per_push = collections.Counter((c, p) for c, p, _ in motion)
        figures = {
            "motion": accuracy(motion, [1] * len(motion), names, held_x, truth),
            "before": accuracy(before, [1] * len(before), names, held_x, truth),
            "both": accuracy(motion + before, [1] * (len(motion) + len(before)), names, held_x,
                             truth),
            "both_bw": accuracy(motion + before,
                                [1] * len(motion) + [max(per_push[(c, p)], 1)
                                                     for c, p, _ in before],
                                names, held_x, truth),
        }
        for k, v in figures.items():
            rows[k].append(100 * v)
        print(f"seed {s}: " + ", ".join(f"{k} {100 * v:.1f}" for k, v in figures.items()))
    for k, v in rows.items():
        line = f"{k}: {np.mean(v):.1f} %"
        if k != "motion":
            d = [a - b for a, b in zip(v, rows["motion"])]
            m, h = ci(d)
            line += (f"; - motion {m:+.1f} +- {h:.1f} (higher on {sum(x > 0 for x in d)}, "
                     f"lower on {sum(x < 0 for x in d)} of {len(d)})")
        print(line)


if __name__ == "__main__":
    if len(sys.argv) < 4:
        raise SystemExit(__doc__)
    main(sys.argv[1], sys.argv[2], sys.argv[3:])
