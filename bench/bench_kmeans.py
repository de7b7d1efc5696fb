#!/usr/bin/python3
"""scikit-learn's KMeans as a peer of bench_features: k-means++ start, one init, a fixed number
of Lloyd iterations, on the descriptors bench_features wrote as .npy.

usage: bench_kmeans.py DESCRIPTORS.npy --words 400 --iterations 20 --threads 2 --out F.json
Writes {"seconds", "iterations", "inertia", "centres"}; exits 3 when scikit-learn is missing.
"""
import argparse
import json
import os
import sys
import time

ap = argparse.ArgumentParser()
ap.add_argument("npy")
ap.add_argument("--words", type=int, default=400)
ap.add_argument("--iterations", type=int, default=20)
ap.add_argument("--threads", type=int, default=2)
ap.add_argument("--out", required=True)
a = ap.parse_args()
for var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[var] = str(a.threads)
for var in ("OPENBLAS_CORETYPE", "OPENBLAS_L2_SIZE"):
    os.environ.pop(var, None)
try:
    import numpy as np
    from sklearn.cluster import KMeans
except ImportError:
    sys.exit(3)

x = np.load(a.npy)
t0 = time.perf_counter()
# tol=0: run all the iterations, as cv::kmeans is asked to.
km = KMeans(n_clusters=a.words, init="k-means++", n_init=1, max_iter=a.iterations, tol=0.0,
            algorithm="lloyd", random_state=1).fit(x)
seconds = time.perf_counter() - t0
with open(a.out, "w") as f:
    json.dump({"seconds": seconds, "iterations": int(km.n_iter_), "inertia": float(km.inertia_),
               "centres": km.cluster_centers_.tolist()}, f)
