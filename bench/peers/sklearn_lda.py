#!/usr/bin/python3
"""Trains scikit-learn's online LatentDirichletAllocation on a UCI corpus, one thread.

usage: sklearn_lda.py --corpus DIR -k K --batch B --tau0 T --kappa C --passes P --alpha A
                      --eta E --seed S --lambda-out lambda.csv --json result.json
Exit 3 when scikit-learn is not installed.
"""
import argparse
import sys
import time

import common

try:
    import numpy as np
    import scipy.sparse as sp
    import sklearn
    from sklearn.decomposition import LatentDirichletAllocation
except ImportError as e:
    print(f"sklearn_lda: {e}", file=sys.stderr)
    sys.exit(3)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--corpus", required=True)
    ap.add_argument("-k", type=int, default=100)
    ap.add_argument("--batch", type=int, default=256)
    ap.add_argument("--tau0", type=float, default=1.0)
    ap.add_argument("--kappa", type=float, default=0.7)
    ap.add_argument("--passes", type=int, default=5)
    ap.add_argument("--alpha", type=float, default=None)
    ap.add_argument("--eta", type=float, default=None)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--lambda-out", required=True)
    ap.add_argument("--json", required=True)
    a = ap.parse_args()
    docs, _, num_words = common.read_uci(a.corpus)
    rows, cols, vals = [], [], []
    for d, doc in enumerate(docs):
        for w, c in doc:
            rows.append(d)
            cols.append(w)
            vals.append(c)
    X = sp.csr_matrix((np.array(vals, dtype=np.float64), (rows, cols)), shape=(len(docs), num_words))
    alpha = a.alpha if a.alpha else 1.0 / a.k
    eta = a.eta if a.eta else 1.0 / a.k
    lda = LatentDirichletAllocation(
        n_components=a.k, doc_topic_prior=alpha, topic_word_prior=eta,
        learning_method="online", learning_decay=a.kappa, learning_offset=a.tau0,
        max_iter=a.passes, batch_size=a.batch, evaluate_every=-1, n_jobs=1,
        max_doc_update_iter=100, mean_change_tol=1e-3, random_state=a.seed)
    t0 = time.perf_counter()
    c0 = time.process_time()
    lda.fit(X)
    seconds = time.perf_counter() - t0
    cpu_seconds = time.process_time() - c0
    common.write_lambda_csv(a.lambda_out, lda.components_)
    tokens = float(X.sum())
    common.write_json(a.json, {
        "peer": "sklearn", "version": sklearn.__version__, "seconds": seconds, "cpu_seconds": cpu_seconds,
        "documents": len(docs) * a.passes, "tokens": tokens * a.passes,
        "docs_per_s": len(docs) * a.passes / seconds, "tokens_per_s": tokens * a.passes / seconds,
        "alpha": alpha, "eta": eta, "blas": common.blas_info()})


if __name__ == "__main__":
    main()
