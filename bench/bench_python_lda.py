#!/usr/bin/python3
"""proprio's LDA through the Python bindings against scikit-learn's, in one Python process.

usage: bench_python_lda.py --proprio BUILD/app/proprio [--corpus DIR] [--repeats 3]
                           [--out F.json] [--blas openblas|reference] [--skip-cpp-bench]

The man-page corpus (DIR/train, DIR/heldout: scripts/make-manpage-corpus; bench/bench_topics.py's
setting: K = 100, alpha = eta = 1/K, mini-batches of 256, tau0 = 1, kappa = 0.7, 5 passes, one
thread each). Per repeat r (seed r), in an order rotated per repeat:
  proprio-py   proprio.topics.LatentDirichletAllocation(...).fit(X) on the scipy CSR matrix a
               user has (float64 counts): wall time of the whole fit, conversion included
  proprio-call proprio.topics.train_online_lda(corpus, options), the library call itself on a
               corpus built beforehand (the binding's own call cost is microseconds)
  sklearn      sklearn.decomposition.LatentDirichletAllocation(learning_method="online", ...)
               .fit(X), the same X, numpy on the chosen BLAS
Every model is scored by the same function as bench_topics.py (document completion on the
held-out pages: proprio.topics.perplexity, which `proprio lda perplexity` also calls).

The binding's overhead on a whole training run: the fit's wall time against the training time
the C++ engine measured inside the same call (OnlineLdaSummary.seconds), and against `proprio lda
train` (the CLI, a separate process) for the same seed. Then bench_topics.py runs in the same
session (proprio CLI vs scikit-learn in its own process), and the two speed ratios are compared.

The process re-executes itself with Debian's serial OpenBLAS first on its library path (as
bench_topics.py does for its peers) and checks with threadpoolctl what numpy loaded.
"""
import argparse
import json
import os
import pathlib
import statistics
import subprocess
import sys
import tempfile
import time

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(HERE))
from bench_topics import BLAS_DIRS, check_blas, peer_env  # noqa: E402

MARK = "PROPRIO_BENCH_PYTHON_LDA_BLAS"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--proprio", required=True, type=pathlib.Path)
    ap.add_argument("--corpus", type=pathlib.Path, default=pathlib.Path("/tmp/proprio-manpage-corpus"))
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--out", type=pathlib.Path)
    ap.add_argument("--blas", choices=sorted(BLAS_DIRS), default="openblas")
    ap.add_argument("--skip-cpp-bench", action="store_true")
    ap.add_argument("--skip-sklearn", action="store_true",
                    help="only the binding's overhead (proprio-py, proprio-call, proprio-cli)")
    ap.add_argument("-k", type=int, default=100)
    ap.add_argument("--passes", type=int, default=5)
    a = ap.parse_args()

    if os.environ.get(MARK) != a.blas:
        env = peer_env(a.blas)
        env[MARK] = a.blas
        env["OPENBLAS_NUM_THREADS"] = "1"
        env["OMP_NUM_THREADS"] = "1"
        os.execve(sys.executable, [sys.executable, *sys.argv], env)

    import numpy as np
    import sklearn
    from sklearn.decomposition import LatentDirichletAllocation as SkLda
    from threadpoolctl import threadpool_info

    import proprio
    from proprio.topics import Corpus, LatentDirichletAllocation, LdaModel, perplexity, read_corpus

    blas = [{k: i.get(k) for k in ("internal_api", "version", "architecture", "num_threads",
                                   "filepath")} for i in threadpool_info()]
    check_blas("numpy", a.blas, blas)

    if not (a.corpus / "train" / "docword.txt").exists():
        r = subprocess.run([str(ROOT / "scripts" / "make-manpage-corpus"), str(a.corpus),
                            "--exclude", "gcloud*"], capture_output=True, text=True)
        if r.returncode != 0:
            sys.exit(r.stderr)
    X = read_corpus(a.corpus / "train").astype(np.float64)  # what a scikit-learn user has
    heldout = Corpus.read(str(a.corpus / "heldout"))
    alpha = 1.0 / a.k
    print(f"corpus: {X.shape[0]} pages, {int(X.sum())} tokens, {X.shape[1]} words; "
          f"proprio {proprio.__version__}, scikit-learn {sklearn.__version__}, numpy "
          f"{np.__version__} on {blas[0].get('internal_api')} {blas[0].get('version')}")

    def fit_proprio(seed):
        lda = LatentDirichletAllocation(a.k, doc_topic_prior=alpha, topic_word_prior=alpha,
                                        learning_offset=1.0, learning_decay=0.7,
                                        max_iter=a.passes, batch_size=256, n_jobs=1,
                                        random_state=seed)
        t0, c0 = time.perf_counter(), time.process_time()
        lda.fit(X)
        wall, cpu = time.perf_counter() - t0, time.process_time() - c0
        return lda.model_, wall, cpu, lda.training_summary_["seconds"]

    def fit_sklearn(seed):
        lda = SkLda(n_components=a.k, doc_topic_prior=alpha, topic_word_prior=alpha,
                    learning_method="online", learning_decay=0.7, learning_offset=1.0,
                    max_iter=a.passes, batch_size=256, evaluate_every=-1, n_jobs=1,
                    max_doc_update_iter=100, mean_change_tol=1e-3, random_state=seed)
        t0, c0 = time.perf_counter(), time.process_time()
        lda.fit(X)
        wall, cpu = time.perf_counter() - t0, time.process_time() - c0
        return LdaModel.from_lambda(np.ascontiguousarray(lda.components_), alpha, alpha), wall, \
            cpu, None

    corpus = Corpus.read(str(a.corpus / "train"))  # built once: the C++ call's own input

    def call_proprio(seed):
        # The library call through the binding, on a prebuilt corpus: what the C++ program does.
        o = proprio.topics.OnlineLdaOptions(topics=a.k, batch=256, tau0=1.0, kappa=0.7,
                                            alpha=alpha, eta=alpha, passes=a.passes, threads=1,
                                            seed=seed)
        t0, c0 = time.perf_counter(), time.process_time()
        model, summary = proprio.topics.train_online_lda(corpus, o)
        wall, cpu = time.perf_counter() - t0, time.process_time() - c0
        return model, wall, cpu, summary["seconds"]

    def cli_seconds(seed, work):
        js = work / f"cli{seed}.json"
        r = subprocess.run([str(a.proprio), "lda", "train", "--corpus", str(a.corpus / "train"),
                            "-k", str(a.k), "--batch", "256", "--tau0", "1", "--kappa", "0.7",
                            "--passes", str(a.passes), "--alpha", str(alpha), "--eta", str(alpha),
                            "--threads", "1", "--seed", str(seed), "--model",
                            str(work / f"cli{seed}.lda"), "--json", str(js)],
                           capture_output=True, text=True)
        if r.returncode != 0:
            sys.exit(f"bench_python_lda: proprio lda train failed: {r.stderr.strip()}")
        return json.loads(js.read_text())["seconds"], LdaModel.load(work / f"cli{seed}.lda")

    work = pathlib.Path(tempfile.mkdtemp(prefix="bench_python_lda_"))
    engines = [("proprio-py", fit_proprio), ("proprio-call", call_proprio), ("proprio-cli", None)]
    if not a.skip_sklearn:
        engines.insert(1, ("sklearn", fit_sklearn))
    runs = {name: [] for name, _ in engines}
    for rep in range(a.repeats):
        seed = rep + 1
        order = engines[rep % len(engines):] + engines[:rep % len(engines)]
        for name, fit in order:
            load = os.getloadavg()[0]
            if fit is None:
                seconds, model = cli_seconds(seed, work)
                row = {"seed": seed, "seconds": seconds, "load_before": load,
                       "same_model_as_python": bool(
                           np.array_equal(model.lambda_, runs_model[seed].lambda_))
                       if seed in runs_model else None}
            else:
                model, wall, cpu, engine_seconds = fit(seed)
                row = {"seed": seed, "seconds": wall, "cpu_seconds": cpu,
                       "engine_seconds": engine_seconds, "load_before": load}
                if name == "proprio-py":
                    runs_model[seed] = model
            row["perplexity"] = perplexity(model, heldout, method="completion")["perplexity"]
            runs[name].append(row)
            extra = f" (engine {row['engine_seconds']:.2f} s)" if row.get("engine_seconds") else ""
            print(f"  repeat {rep + 1} {name:12s} {row['seconds']:7.2f} s{extra}  perplexity "
                  f"{row['perplexity']:7.1f}", flush=True)

    def med(xs):
        return statistics.median(xs)

    by_seed = {name: {r["seed"]: r for r in rows} for name, rows in runs.items()}
    seeds = sorted(by_seed["proprio-py"])
    ratio_py = [by_seed["sklearn"][s]["seconds"] / by_seed["proprio-py"][s]["seconds"]
                for s in seeds] if "sklearn" in by_seed and by_seed["sklearn"] else [float("nan")]
    overhead_call = [by_seed["proprio-py"][s]["seconds"] / by_seed["proprio-call"][s]["seconds"]
                     - 1 for s in seeds]
    overhead_engine = [by_seed["proprio-py"][s]["seconds"] / by_seed["proprio-py"][s]["engine_seconds"]
                       - 1 for s in seeds]
    overhead_cli = [by_seed["proprio-py"][s]["seconds"] / by_seed["proprio-cli"][s]["seconds"] - 1
                    for s in seeds]
    ppl = {name: statistics.mean(r["perplexity"] for r in rows) for name, rows in runs.items()
           if rows}
    summary = {
        "speedup_over_sklearn_in_python": ratio_py,
        "speedup_over_sklearn_in_python_median": med(ratio_py),
        "overhead_vs_call_wall": overhead_call,
        "overhead_vs_call_wall_median": med(overhead_call),
        "overhead_vs_engine_seconds": overhead_engine,
        "overhead_vs_engine_seconds_median": med(overhead_engine),
        "overhead_vs_cli_seconds": overhead_cli,
        "overhead_vs_cli_seconds_median": med(overhead_cli),
        "perplexity_mean": ppl,
        "perplexity_proprio_over_sklearn": ppl["proprio-py"] / ppl["sklearn"]
        if "sklearn" in ppl else None,
        "same_model_python_and_cli": all(r["same_model_as_python"] is not False
                                         for r in runs["proprio-cli"]),
    }
    print()
    if not a.skip_sklearn:
        print(f"speed-up over scikit-learn, one Python process: per repeat "
              f"{', '.join(f'{x:.2f}' for x in ratio_py)}; median {med(ratio_py):.2f}x")
    print(f"binding overhead vs the library call (train_online_lda on a prebuilt corpus, same "
          f"process): {', '.join(f'{100 * x:+.1f}%' for x in overhead_call)}")
    print(f"binding overhead vs the engine's own training time: "
          f"{', '.join(f'{100 * x:+.1f}%' for x in overhead_engine)}")
    print(f"binding overhead vs `proprio lda train`'s training time: "
          f"{', '.join(f'{100 * x:+.1f}%' for x in overhead_cli)}")
    if "sklearn" in ppl:
        print(f"held-out perplexity: proprio {ppl['proprio-py']:.1f}, scikit-learn "
              f"{ppl['sklearn']:.1f} (ratio {summary['perplexity_proprio_over_sklearn']:.3f})")
    print(f"Python and CLI models identical: {summary['same_model_python_and_cli']}")

    cpp = None
    if not a.skip_cpp_bench and not a.skip_sklearn:
        out = work / "bench_topics.json"
        r = subprocess.run(["/usr/bin/python3", str(HERE / "bench_topics.py"), "--proprio",
                            str(a.proprio), "--corpus", str(a.corpus), "--repeats",
                            str(a.repeats), "--peers", "sklearn", "--blas", a.blas, "--passes",
                            str(a.passes), "-k", str(a.k), "--out", str(out)],
                           capture_output=True, text=True)
        if r.returncode != 0:
            sys.exit(f"bench_python_lda: bench_topics.py failed: {r.stderr.strip()}")
        cpp = json.loads(out.read_text())
        ratio_cpp = cpp["ratios"]["sklearn/proprio-1 seconds"]
        summary["speedup_over_sklearn_cpp_bench"] = ratio_cpp
        summary["speedup_over_sklearn_cpp_bench_median"] = med(ratio_cpp)
        rel = med(ratio_py) / med(ratio_cpp) - 1
        summary["python_ratio_vs_cpp_ratio"] = rel
        print(f"bench_topics.py (CLI vs scikit-learn in its own process), same session: per "
              f"repeat {', '.join(f'{x:.2f}' for x in ratio_cpp)}; median {med(ratio_cpp):.2f}x")
        print(f"the Python ratio against the C++ benchmark's: {100 * rel:+.1f}% (target within 10%)")
    if a.out:
        a.out.write_text(json.dumps({
            "format": "proprio.bench.python_lda", "corpus": str(a.corpus),
            "settings": {"k": a.k, "batch": 256, "tau0": 1.0, "kappa": 0.7, "passes": a.passes,
                         "alpha": alpha, "eta": alpha, "blas": a.blas},
            "blas": blas, "versions": {"proprio": proprio.__version__,
                                       "sklearn": sklearn.__version__, "numpy": np.__version__},
            "runs": runs, "summary": summary, "bench_topics": cpp, "load": os.getloadavg()},
            indent=2))


runs_model = {}

if __name__ == "__main__":
    main()
