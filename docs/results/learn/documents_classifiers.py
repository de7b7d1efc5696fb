#!/usr/bin/python3
"""Held-out accuracy of word classifiers fitted to learn runs' own training views.

Usage: documents_classifiers.py RUN_DIR... (each written by `proprio learn --write-documents`)

Reads each run's documents.txt (the training views' and held-out views' documents, lda-c lines)
and scores, on exactly the robot's training set and the run's held-out views, multinomial naive
Bayes variants (the pooled classifier at weight 1 is the first, "joint"): the colour words'
tokens weighed by alpha ("aA"; SIFT and colour words as two multinomials), views weighed alike
("...v"), the colour words alone ("colour"; "colv" with views weighed alike: learn's
held_out_words.colour), the smoothing ("_pP"), and alpha chosen by leaving one push out of the
robot's own views ("acv"). A held-out view is right when the class it is given
is named after its object (the run's own naming, learn.json's). Prints one line a run and the
means.
"""
import sys

import numpy as np


def read_documents(path):
    """The documents.txt of one run: W, V, class names, views, held-out views."""
    with open(path) as f:
        lines = f.read().splitlines()
    if not lines or lines[0] != "# proprio learn documents, version 1":
        raise SystemExit(f"{path}: not a proprio learn documents file, version 1")
    head = lines[1].split()
    words, vocab = int(head[1]), int(head[3])
    classes, views, held = {}, [], []

    def doc(fields):
        n = int(fields[0])
        x = np.zeros(words)
        for wc in fields[1 : 1 + n]:
            w, c = wc.split(":")
            x[int(w)] += int(c)
        return x

    for ln in lines[2:]:
        f = ln.split()
        if f[0] == "class":
            classes[int(f[1])] = f[3]
        elif f[0] == "view":
            views.append((int(f[1]), int(f[2]), f[3], f[4], doc(f[5:])))
        elif f[0] == "held":
            held.append((f[1], doc(f[2:])))
    return words, vocab, classes, views, held


def nb_scores(x_train, y_train, n_classes, x_test, alpha_colour, vocab, pseudo=1.0,
              view_weights=None):
    """Log-likelihood scores (test x class) of add-pseudo multinomial naive Bayes with colour
    tokens (ids >= vocab) weighed by alpha_colour in the test documents and in the fit."""
    w = np.ones(x_train.shape[1])
    w[vocab:] = alpha_colour
    counts = np.zeros((n_classes, x_train.shape[1]))
    vw = np.ones(len(y_train)) if view_weights is None else view_weights
    for x, y, v in zip(x_train, y_train, vw):
        counts[y] += v * x
    log_phi_sift = np.log(counts[:, :vocab] + pseudo)
    log_phi_sift -= np.log((counts[:, :vocab] + pseudo).sum(1, keepdims=True))
    log_phi_col = np.log(counts[:, vocab:] + pseudo)
    log_phi_col -= np.log((counts[:, vocab:] + pseudo).sum(1, keepdims=True))
    # SIFT and colour words as two multinomials (a token of each per feature).
    s = x_test[:, :vocab] @ log_phi_sift.T + alpha_colour * (x_test[:, vocab:] @ log_phi_col.T)
    prior = np.log(np.bincount(y_train, minlength=n_classes) + 1.0)
    return s + prior


def nb_joint(x_train, y_train, n_classes, x_test, pseudo=1.0):
    """The pooled classifier at weight 1: one multinomial over all W words, the prior by views."""
    counts = np.zeros((n_classes, x_train.shape[1]))
    for x, y in zip(x_train, y_train):
        counts[y] += x
    log_phi = np.log(counts + pseudo) - np.log((counts + pseudo).sum(1, keepdims=True))
    prior = np.log(np.bincount(y_train, minlength=n_classes) + 1.0)
    return x_test @ log_phi.T + prior


def training_and_held(path):
    """One run's training views with a class (labels y, counts xt, the views kept) and held-out
    views (counts xh, their objects), the vocabulary's size and the class names."""
    _, vocab, classes, views, held = read_documents(path)
    keep = [v for v in views if v[0] >= 0]
    y = np.array([v[0] for v in keep])
    xt = np.array([v[4] for v in keep])
    xh = np.array([h[1] for h in held])
    truth = [h[0] for h in held]
    names = [classes[c] for c in range(len(classes))]
    return vocab, keep, y, xt, xh, truth, names


def run(path):
    vocab, keep, y, xt, xh, truth, names = training_and_held(path)
    n_classes = len(names)

    def acc(scores):
        pred = scores.argmax(1)
        return float(np.mean([names[p] == t for p, t in zip(pred, truth)]))

    out = {"joint": acc(nb_joint(xt, y, n_classes, xh))}
    for a in (1.0, 2.0, 3.0, 4.0, 6.0, 8.0, 16.0):
        out[f"a{a:g}"] = acc(nb_scores(xt, y, n_classes, xh, a, vocab))
    out["colour"] = acc(nb_scores(xt, y, n_classes, xh, 1.0, vocab) -
                        nb_scores(xt, y, n_classes, xh, 0.0, vocab))
    # Views weighed alike (each view's counts scaled to the mean view's tokens).
    tokens = xt.sum(1)
    vw = tokens.mean() / np.maximum(tokens, 1)
    out["a4v"] = acc(nb_scores(xt, y, n_classes, xh, 4.0, vocab, view_weights=vw))
    for a in (8.0, 16.0, 32.0):
        out[f"a{a:g}v"] = acc(nb_scores(xt, y, n_classes, xh, a, vocab, view_weights=vw))
    for p in (0.1, 10.0):
        out[f"colv_p{p:g}"] = acc(
            nb_scores(xt, y, n_classes, xh, 1.0, vocab, pseudo=p, view_weights=vw) -
            nb_scores(xt, y, n_classes, xh, 0.0, vocab, pseudo=p, view_weights=vw))
    out["colv"] = acc(nb_scores(xt, y, n_classes, xh, 1.0, vocab, view_weights=vw) -
                      nb_scores(xt, y, n_classes, xh, 0.0, vocab, view_weights=vw))
    # alpha chosen by the robot's own views: leave one push out, its views classified by the
    # rest (labels: the robot's own classes).
    pushes = np.array([v[1] for v in keep])
    grid = (1.0, 2.0, 4.0, 8.0, 16.0)
    cv = []
    for a in grid:
        right = 0
        for p in np.unique(pushes):
            tr = pushes != p
            sc = nb_scores(xt[tr], y[tr], n_classes, xt[~tr], a, vocab)
            right += int((sc.argmax(1) == y[~tr]).sum())
        cv.append(right)
    out["acv"] = acc(nb_scores(xt, y, n_classes, xh, grid[int(np.argmax(cv))], vocab))
    return out


def main(dirs):
    rows = []
    for d in dirs:
        r = run(f"{d}/documents.txt")
        rows.append(r)
        print(d, " ".join(f"{k} {100 * v:.1f}" for k, v in r.items()))
    keys = rows[0].keys()
    print("mean", " ".join(f"{k} {100 * np.mean([r[k] for r in rows]):.1f}" for k in keys))


if __name__ == "__main__":
    main(sys.argv[1:])
