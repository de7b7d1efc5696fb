#!/usr/bin/python3
"""Trains gensim's LdaModel (online variational Bayes) on a UCI corpus, one thread.

usage: gensim_lda.py --corpus DIR -k K --batch B --tau0 T --kappa C --passes P --alpha A
                     --eta E --seed S --lambda-out lambda.csv --json result.json
Exit 3 when gensim is not installed.
"""
import argparse
import logging
import sys
import time

import common

try:
    import gensim
    import numpy as np
    from gensim.models import LdaModel
except ImportError as e:
    print(f"gensim_lda: {e}", file=sys.stderr)
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
    logging.getLogger("gensim").setLevel(logging.WARNING)
    docs, vocab, num_words = common.read_uci(a.corpus)
    id2word = dict(enumerate(vocab))
    alpha = a.alpha if a.alpha else 1.0 / a.k
    eta = a.eta if a.eta else 1.0 / a.k
    t0 = time.perf_counter()
    c0 = time.process_time()
    # The E-step as the other engines run it: at most 100 iterations, mean change below 1e-3.
    # eval_every=None: no perplexity estimates inside the timed training.
    lda = LdaModel(corpus=docs, id2word=id2word, num_topics=a.k, chunksize=a.batch,
                   passes=a.passes, update_every=1, alpha=np.full(a.k, alpha), eta=eta,
                   decay=a.kappa, offset=a.tau0, eval_every=None, iterations=100,
                   gamma_threshold=1e-3, random_state=a.seed)
    seconds = time.perf_counter() - t0
    cpu_seconds = time.process_time() - c0
    common.write_lambda_csv(a.lambda_out, lda.state.get_lambda())
    tokens = float(sum(c for doc in docs for _, c in doc))
    common.write_json(a.json, {
        "peer": "gensim", "version": gensim.__version__, "seconds": seconds, "cpu_seconds": cpu_seconds,
        "documents": len(docs) * a.passes, "tokens": tokens * a.passes,
        "docs_per_s": len(docs) * a.passes / seconds, "tokens_per_s": tokens * a.passes / seconds,
        "alpha": alpha, "eta": eta, "dtype": str(lda.dtype), "blas": common.blas_info()})


if __name__ == "__main__":
    main()
