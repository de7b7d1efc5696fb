#!/usr/bin/python3
"""Online LDA speed and quality: proprio against gensim and scikit-learn, in one run.

usage: bench_topics.py --proprio BUILD/app/proprio [--corpus DIR] [--repeats 3] [--out F.json]
                       [-k 100] [--batch 256] [--tau0 1] [--kappa 0.7] [--passes 5]
                       [--peers sklearn,gensim] [--blas openblas|reference]

DIR holds train/ and heldout/ UCI corpora (scripts/make-manpage-corpus builds them; without
--corpus the man-page corpus is built under /tmp, the Google Cloud SDK's ~16,000 near-identical
pages excluded). Each repeat r trains, with seed r, proprio on 1 thread and on 2 threads and each
installed peer on 1 thread, in an order rotated per repeat so that the machine's load falls on
all alike; every model's lambda is then scored by the same function, `proprio lda perplexity`
(document completion: theta from half of each held-out page's tokens, the other half scored).
A peer that is not installed is skipped. Prints a table; --out writes every figure as JSON.

The peers' numpy runs on the BLAS that users of pip's numpy get, OpenBLAS (--blas openblas, the
default: Debian's libopenblas0-serial, one thread, put first on the peer processes' library path
only), or on Debian's reference BLAS (--blas reference) for comparison. Which BLAS numpy really
loaded is read back with threadpoolctl in each peer process, recorded, and checked: a run whose
peer loaded another BLAS stops. `scripts/install-deps --bench` installs the peers and OpenBLAS.
"""
import argparse
import json
import os
import pathlib
import statistics
import subprocess
import sys
import tempfile

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parent
# Debian's BLAS builds, each a directory with its own libblas.so.3 / liblapack.so.3.
BLAS_DIRS = {
    "openblas": pathlib.Path("/usr/lib/x86_64-linux-gnu/openblas-serial"),
    "reference": pathlib.Path("/usr/lib/x86_64-linux-gnu/blas"),
}
BLAS_NAMES = {"openblas": "openblas", "reference": None}


def peer_env(blas):
    """The environment of a peer process: the chosen BLAS first on its library path."""
    env = dict(os.environ)
    dirs = [str(BLAS_DIRS[blas])]
    if blas == "reference":
        dirs.append("/usr/lib/x86_64-linux-gnu/lapack")
    if env.get("LD_LIBRARY_PATH"):
        dirs.append(env["LD_LIBRARY_PATH"])
    env["LD_LIBRARY_PATH"] = ":".join(dirs)
    return env


def check_blas(name, blas, info):
    """Stops the run when the peer's numpy loaded another BLAS than the one asked for."""
    apis = [i.get("internal_api") for i in info]
    loaded = [i.get("filepath") or i.get("internal_api") or i.get("error") for i in info]
    if blas == "openblas":
        ok = "openblas" in apis
    else:
        ok = "openblas" not in apis and "mkl" not in apis and "blis" not in apis
    if not ok:
        sys.exit(f"bench_topics: {name} loaded {loaded}, not the {blas} BLAS asked for")


def run(cmd, **kw):
    r = subprocess.run([str(c) for c in cmd], capture_output=True, text=True, **kw)
    return r


def perplexity(proprio, heldout, work, name, model=None, lam=None, alpha=None):
    out = work / f"{name}.perplexity.json"
    cmd = [proprio, "lda", "perplexity", "--corpus", heldout, "--json", out]
    cmd += ["--model", model] if model else ["--lambda", lam, "--alpha", alpha]
    r = run(cmd)
    if r.returncode != 0:
        sys.exit(f"bench_topics: perplexity of {name} failed: {r.stderr.strip()}")
    return json.loads(out.read_text())["perplexity"]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--proprio", required=True, type=pathlib.Path)
    ap.add_argument("--corpus", type=pathlib.Path)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--out", type=pathlib.Path)
    ap.add_argument("-k", type=int, default=100)
    ap.add_argument("--batch", type=int, default=256)
    ap.add_argument("--tau0", type=float, default=1.0)
    ap.add_argument("--kappa", type=float, default=0.7)
    ap.add_argument("--passes", type=int, default=5)
    ap.add_argument("--peers", default="sklearn,gensim")
    ap.add_argument("--blas", choices=sorted(BLAS_DIRS), default="openblas")
    a = ap.parse_args()
    if not (BLAS_DIRS[a.blas] / "libblas.so.3").exists():
        sys.exit(f"bench_topics: {BLAS_DIRS[a.blas]}/libblas.so.3 is missing "
                 "(scripts/install-deps --bench installs it)")

    work = pathlib.Path(tempfile.mkdtemp(prefix="bench_topics_"))
    corpus = a.corpus
    if corpus is None:
        corpus = pathlib.Path("/tmp/proprio-manpage-corpus")
        if not (corpus / "train" / "docword.txt").exists():
            r = run([ROOT / "scripts" / "make-manpage-corpus", corpus, "--exclude", "gcloud*"])
            if r.returncode != 0:
                sys.exit(r.stderr)
            print(r.stdout.strip())
    train, heldout = corpus / "train", corpus / "heldout"
    alpha = 1.0 / a.k
    common = ["-k", a.k, "--batch", a.batch, "--tau0", a.tau0, "--kappa", a.kappa,
              "--passes", a.passes]

    engines = [("proprio-1", None), ("proprio-2", None)]
    for p in a.peers.split(","):
        if p:
            engines.append((p, HERE / "peers" / f"{p}_lda.py"))

    results = {name: [] for name, _ in engines}
    skipped = set()
    for rep in range(a.repeats):
        seed = rep + 1
        order = engines[rep % len(engines):] + engines[:rep % len(engines)]
        for name, script in order:
            if name in skipped:
                continue
            tag = f"{name}.seed{seed}"
            load = os.getloadavg()[0]
            js = work / f"{tag}.json"
            if script is None:
                threads = name.split("-")[1]
                model = work / f"{tag}.lda"
                r = run([a.proprio, "lda", "train", "--corpus", train, *common, "--alpha", alpha,
                         "--eta", alpha, "--threads", threads, "--seed", seed, "--model", model,
                         "--json", js])
                if r.returncode != 0:
                    sys.exit(f"bench_topics: {name} failed: {r.stderr.strip()}")
                doc = json.loads(js.read_text())
                ppl = perplexity(a.proprio, heldout, work, tag, model=model)
            else:
                lam = work / f"{tag}.lambda.csv"
                r = run(["/usr/bin/python3", script, "--corpus", train, *common, "--alpha", alpha,
                         "--eta", alpha, "--seed", seed, "--lambda-out", lam, "--json", js],
                        env=peer_env(a.blas))
                if r.returncode == 3:
                    print(f"bench_topics: {name} is not installed: skipped ({r.stderr.strip()})")
                    skipped.add(name)
                    continue
                if r.returncode != 0:
                    sys.exit(f"bench_topics: {name} failed: {r.stderr.strip()}")
                doc = json.loads(js.read_text())
                check_blas(name, a.blas, doc.get("blas", []))
                ppl = perplexity(a.proprio, heldout, work, tag, lam=lam, alpha=alpha)
            row = {"seed": seed, "seconds": doc["seconds"], "cpu_seconds": doc.get("cpu_seconds"),
                   "docs_per_s": doc["docs_per_s"], "tokens_per_s": doc["tokens_per_s"],
                   "perplexity": ppl, "load_before": load, "blas": doc.get("blas"),
                   "version": doc.get("version")}
            results[name].append(row)
            print(f"  repeat {rep + 1} {name:10s} {row['seconds']:8.2f} s wall "
                  f"{(row['cpu_seconds'] or 0):8.2f} s cpu  perplexity {ppl:8.1f}", flush=True)

    def ratios(num, den, key):
        out = []
        for x, y in zip(results[num], results[den]):
            if x.get(key) and y.get(key):
                out.append(x[key] / y[key])
        return out

    summary = {}
    print()
    print(f"{'engine':12s} {'wall s (median)':>16s} {'cpu s (median)':>15s} {'perplexity (mean)':>18s}")
    for name, rows in results.items():
        if not rows:
            continue
        summary[name] = {
            "seconds_median": statistics.median(r["seconds"] for r in rows),
            "cpu_seconds_median": statistics.median(r["cpu_seconds"] for r in rows),
            "perplexity_mean": statistics.mean(r["perplexity"] for r in rows),
            "perplexities": [r["perplexity"] for r in rows],
        }
        s = summary[name]
        print(f"{name:12s} {s['seconds_median']:16.2f} {s['cpu_seconds_median']:15.2f} "
              f"{s['perplexity_mean']:18.1f}")
    speed = {}
    for peer in [n for n, _ in engines[2:] if results[n]]:
        for key in ("seconds", "cpu_seconds"):
            r = ratios(peer, "proprio-1", key)
            speed[f"{peer}/proprio-1 {key}"] = r
            print(f"speed-up over {peer} ({key}): per repeat {', '.join(f'{x:.1f}' for x in r)}; "
                  f"median {statistics.median(r):.1f}x")
        pp = summary["proprio-1"]["perplexity_mean"] / summary[peer]["perplexity_mean"]
        speed[f"perplexity proprio-1/{peer}"] = pp
        print(f"perplexity proprio-1 / {peer}: {pp:.3f}")
    r2 = ratios("proprio-1", "proprio-2", "seconds")
    speed["proprio-1/proprio-2 seconds"] = r2
    print(f"2 threads over 1 (wall): per repeat {', '.join(f'{x:.2f}' for x in r2)}; "
          f"median {statistics.median(r2):.2f}x")
    if a.out:
        doc = {"format": "proprio.bench.topics", "corpus": str(corpus),
               "settings": {"k": a.k, "batch": a.batch, "tau0": a.tau0, "kappa": a.kappa,
                            "passes": a.passes, "alpha": alpha, "eta": alpha, "blas": a.blas},
               "runs": results, "summary": summary, "ratios": speed, "load": os.getloadavg()}
        a.out.write_text(json.dumps(doc, indent=2))


if __name__ == "__main__":
    main()
