#!/usr/bin/python3
"""What learn's training views show, from documents.txt's ground truth (session 40).

Usage: documents_purity.py RUN_DIR... (each written by `proprio learn --write-documents`, which
since session 40 also records the ground-truth masks, so that every view line names the object
under most of its mask).

Prints per run and over all runs:
  purity   the share of training views whose object is their class's name (the object its
           pushes were aimed at most, learn.json's naming; views with no object known left out);
  colour   held-out accuracy of learn's colour classifier (each class's multinomial over the
           colour words of its views, views weighed alike, add-one, naive Bayes with a prior by
           views: held_out_words.colour), the robot's own labels;
  content  the same classifier with every view labelled by the object it shows (one class an
           object seen, named after it): what the same views would give if each were labelled
           by its content, which also gives a class to every object seen in any view.
Standard library and numpy; reads, never writes.
"""
import collections
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from documents_classifiers import read_documents  # noqa: E402


def colour_accuracy(x, labels, names, held_x, truth):
    """Held-out accuracy (mean over objects) of the views-alike colour naive Bayes."""
    k = len(names)
    tokens = x.sum(1)
    weight = tokens.mean() / np.maximum(tokens, 1)
    counts = np.zeros((k, x.shape[1]))
    for row, c, w in zip(x, labels, weight):
        counts[c] += w * row
    log_phi = np.log(counts + 1.0) - np.log((counts + 1.0).sum(1, keepdims=True))
    prior = np.log(np.bincount(labels, minlength=k) + 1.0)
    pred = (held_x @ log_phi.T + prior).argmax(1)
    per = collections.defaultdict(list)
    for p, t in zip(pred, truth):
        per[t].append(names[p] == t)
    return float(np.mean([np.mean(v) for v in per.values()]))


def run(path):
    _, vocab, classes, views, held = read_documents(path)
    keep = [v for v in views if v[0] >= 0]
    if not keep or not held:
        raise SystemExit(f"{path}: no training or held-out views")
    x = np.array([v[4][vocab:] for v in keep])
    held_x = np.array([h[1][vocab:] for h in held])
    truth = [h[0] for h in held]
    names = [classes[c] for c in range(len(classes))]
    shown = [v[3] for v in keep]
    known = [i for i, o in enumerate(shown) if o != "-"]
    if not known:
        raise SystemExit(f"{path}: no view names its object (a run before session 40?)")
    purity = float(np.mean([shown[i] == names[keep[i][0]] for i in known]))
    own = colour_accuracy(x, np.array([v[0] for v in keep]), names, held_x, truth)
    objects = sorted({shown[i] for i in known})
    by_content = np.array([objects.index(shown[i]) for i in known])
    content = colour_accuracy(x[known], by_content, objects, held_x, truth)
    return {"views": len(keep), "purity": purity, "colour": own, "content": content}


def main(dirs):
    rows = []
    for d in dirs:
        r = run(os.path.join(d, "documents.txt"))
        rows.append(r)
        print(f"{d}: views {r['views']}, purity {100 * r['purity']:.1f} %, colour "
              f"{100 * r['colour']:.1f} %, labelled by content {100 * r['content']:.1f} %")
    if rows:
        print(f"mean over {len(rows)} runs: views {np.mean([r['views'] for r in rows]):.0f}, "
              f"purity {100 * np.mean([r['purity'] for r in rows]):.1f} %, colour "
              f"{100 * np.mean([r['colour'] for r in rows]):.1f} %, labelled by content "
              f"{100 * np.mean([r['content'] for r in rows]):.1f} %")


if __name__ == "__main__":
    if len(sys.argv) < 2:
        raise SystemExit(__doc__)
    main(sys.argv[1:])
