#!/usr/bin/python3
"""Trains gensim's LdaModel (online variational Bayes) on a UCI corpus, one thread.

usage: gensim_lda.py --corpus DIR -k K --batch B --tau0 T --kappa C --passes P --alpha A
                     --eta E --seed S --lambda-out lambda.csv --json result.json
Exit 3 when gensim is not installed.
"""
import logging
import sys

import common

try:
    import gensim
    import numpy as np
    from gensim.models import LdaModel
except ImportError as e:
    print(f"gensim_lda: {e}", file=sys.stderr)
    sys.exit(3)


def main():
    a = common.parse_args()
    logging.getLogger("gensim").setLevel(logging.WARNING)
    docs, vocab, _ = common.read_uci(a.corpus)
    id2word = dict(enumerate(vocab))
    # The E-step as the other engines run it: at most 100 iterations, mean change below 1e-3.
    # eval_every=None: no perplexity estimates inside the timed training.
    lda, seconds, cpu_seconds = common.timed(lambda: LdaModel(
        corpus=docs, id2word=id2word, num_topics=a.k, chunksize=a.batch, passes=a.passes,
        update_every=1, alpha=np.full(a.k, a.alpha), eta=a.eta, decay=a.kappa, offset=a.tau0,
        eval_every=None, iterations=100, gamma_threshold=1e-3, random_state=a.seed))
    tokens = float(sum(c for doc in docs for _, c in doc))
    common.write_result(a, "gensim", gensim.__version__, lda.state.get_lambda(), len(docs), tokens,
                        seconds, cpu_seconds, dtype=str(lda.dtype))


if __name__ == "__main__":
    main()
