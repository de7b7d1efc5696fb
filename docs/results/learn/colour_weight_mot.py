#!/usr/bin/python3
"""Usage: KS="1 8 16" colour_weight_mot.py T RUN_DIR... (each written by `proprio learn --write-documents`)

Offline check: does weighing the colour words in learn's documents raise a Dirichlet-on-theta
classifier (the Mixture of Topics' shape)? For each run (documents.txt from --write-documents) and
weight k, colour counts x k in the training and held-out documents, LDA (sklearn, T topics) on the
training views, one Dirichlet per class on their theta (Minka's fixed point), held-out views by the
largest log-likelihood + log prior."""
import sys
import numpy as np
from scipy.special import digamma, polygamma, gammaln
from sklearn.decomposition import LatentDirichletAllocation
sys.path.insert(0, __import__("os").path.dirname(__import__("os").path.abspath(__file__)))
from documents_classifiers import training_and_held


def inv_digamma(y):
    x = np.where(y >= -2.22, np.exp(y) + 0.5, -1.0 / (y - digamma(1)))
    for _ in range(5):
        x -= (digamma(x) - y) / polygamma(1, x)
    return x


def fit_dirichlet(th, iters=200):
    th = np.clip(th, 1e-6, None)
    th /= th.sum(1, keepdims=True)
    logp = np.log(th).mean(0)
    m = th.mean(0)
    a = m * 5.0
    for _ in range(iters):
        a = inv_digamma(digamma(a.sum()) + logp)
    return a


def dir_loglik(th, a):
    th = np.clip(th, 1e-6, None)
    th /= th.sum(1, keepdims=True)
    return gammaln(a.sum()) - gammaln(a).sum() + ((a - 1) * np.log(th)).sum(1)


def run(path, k, topics, seed=0):
    vocab, _, y, xt, xh, truth, names = training_and_held(path)
    n = len(names)
    xt[:, vocab:] *= k
    xh[:, vocab:] *= k
    lda = LatentDirichletAllocation(n_components=topics, random_state=seed, max_iter=30,
                                    learning_method="batch")
    tt = lda.fit_transform(xt)
    th = lda.transform(xh)
    scores = np.zeros((len(xh), n))
    for c in range(n):
        if (y == c).sum() < 2:
            scores[:, c] = -np.inf
            continue
        a = fit_dirichlet(tt[y == c])
        scores[:, c] = dir_loglik(th, a) + np.log((y == c).sum())
    pred = scores.argmax(1)
    return float(np.mean([names[p] == t for p, t in zip(pred, truth)]))


if __name__ == "__main__":
    topics = int(sys.argv[1])
    dirs = sys.argv[2:]
    ks = tuple(int(x) for x in __import__("os").environ.get("KS", "1 2 4 8").split())
    rows = []
    for d in dirs:
        r = [run(f"{d}/documents.txt", k, topics) for k in ks]
        rows.append(r)
        print(d, " ".join(f"k{k} {100 * v:.1f}" for k, v in zip(ks, r)), flush=True)
    rows = np.array(rows)
    print("mean", " ".join(f"k{k} {100 * v:.1f}" for k, v in zip(ks, rows.mean(0))))
    for i, k in enumerate(ks[1:], 1):
        d = rows[:, i] - rows[:, 0]
        print(f"k{k}-k1 {100 * d.mean():+.1f} +- {100 * 1.96 * d.std(ddof=1) / np.sqrt(len(d)):.1f}")
