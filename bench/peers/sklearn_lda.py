#!/usr/bin/python3
"""Trains scikit-learn's online LatentDirichletAllocation on a UCI corpus, one thread.

usage: sklearn_lda.py --corpus DIR -k K --batch B --tau0 T --kappa C --passes P --alpha A
                      --eta E --seed S --lambda-out lambda.csv --json result.json
Exit 3 when scikit-learn is not installed.
"""
import sys

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
    a = common.parse_args()
    docs, _, num_words = common.read_uci(a.corpus)
    rows, cols, vals = [], [], []
    for d, doc in enumerate(docs):
        for w, c in doc:
            rows.append(d)
            cols.append(w)
            vals.append(c)
    X = sp.csr_matrix((np.array(vals, dtype=np.float64), (rows, cols)), shape=(len(docs), num_words))
    lda = LatentDirichletAllocation(
        n_components=a.k, doc_topic_prior=a.alpha, topic_word_prior=a.eta,
        learning_method="online", learning_decay=a.kappa, learning_offset=a.tau0,
        max_iter=a.passes, batch_size=a.batch, evaluate_every=-1, n_jobs=1,
        max_doc_update_iter=100, mean_change_tol=1e-3, random_state=a.seed)
    _, seconds, cpu_seconds = common.timed(lambda: lda.fit(X))
    common.write_result(a, "sklearn", sklearn.__version__, lda.components_, len(docs),
                        float(X.sum()), seconds, cpu_seconds)


if __name__ == "__main__":
    main()
