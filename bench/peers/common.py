"""Shared by the peer scripts: single-threaded numerics, arguments, UCI reading, result writing."""
import argparse
import os

# One thread for the BLAS under numpy, set before numpy is imported. OPENBLAS_CORETYPE and
# OPENBLAS_L2_SIZE (set on this machine for old OpenBLAS builds) slow a current numpy down, so
# the peers run without them.
for var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[var] = "1"
for var in ("OPENBLAS_CORETYPE", "OPENBLAS_L2_SIZE"):
    os.environ.pop(var, None)

import json  # noqa: E402
import pathlib  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402


def read_uci(directory):
    """Returns (docs, vocab, num_words): docs as lists of (0-based word id, count)."""
    directory = pathlib.Path(directory)
    with open(directory / "docword.txt") as f:
        num_docs = int(f.readline())
        num_words = int(f.readline())
        int(f.readline())
        docs = [[] for _ in range(num_docs)]
        for line in f:
            d, w, c = line.split()
            docs[int(d) - 1].append((int(w) - 1, int(c)))
    vocab = (directory / "vocab.txt").read_text().split("\n")[:num_words]
    return docs, vocab, num_words


def write_lambda_csv(path, lam):
    """K x W lambda as CSV with a header line w0..w{W-1} (proprio's lambda CSV)."""
    lam = np.asarray(lam, dtype=np.float64)
    header = ",".join(f"w{i}" for i in range(lam.shape[1]))
    np.savetxt(path, lam, delimiter=",", header=header, comments="", fmt="%.17g")


def blas_info():
    try:
        from threadpoolctl import threadpool_info
        return [{k: i.get(k) for k in ("internal_api", "num_threads", "architecture", "version")}
                for i in threadpool_info()]
    except Exception as e:  # threadpoolctl missing: say so, do not fail
        return [{"error": str(e)}]


def write_json(path, doc):
    tmp = pathlib.Path(str(path) + ".tmp")
    tmp.write_text(json.dumps(doc, indent=2))
    tmp.replace(path)


def parse_args():
    """The arguments every peer takes (the usage line of each script)."""
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
    a.alpha = a.alpha if a.alpha else 1.0 / a.k
    a.eta = a.eta if a.eta else 1.0 / a.k
    return a


def timed(train):
    """Runs train(); returns its result with the wall-clock and CPU seconds it took."""
    t0 = time.perf_counter()
    c0 = time.process_time()
    result = train()
    return result, time.perf_counter() - t0, time.process_time() - c0


def write_result(a, peer, version, lam, num_docs, tokens, seconds, cpu_seconds, **extra):
    """Writes lambda CSV and the result JSON that bench_topics.py reads."""
    write_lambda_csv(a.lambda_out, lam)
    doc = {"peer": peer, "version": version, "seconds": seconds, "cpu_seconds": cpu_seconds,
           "documents": num_docs * a.passes, "tokens": tokens * a.passes,
           "docs_per_s": num_docs * a.passes / seconds, "tokens_per_s": tokens * a.passes / seconds,
           "alpha": a.alpha, "eta": a.eta}
    doc.update(extra)
    doc["blas"] = blas_info()
    write_json(a.json, doc)
