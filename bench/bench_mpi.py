#!/usr/bin/python3
"""Data-parallel online LDA (issue 23): training time of `mpirun -np 2 proprio lda train
--threads 1` against one process of one thread, on a corpus with train/ and heldout/ (as
scripts/make-manpage-corpus writes it), at the same held-out perplexity (the models must be the
same bytes; the run stops otherwise).

usage: bench_mpi.py --proprio build/app/proprio --corpus /tmp/proprio-manpage-corpus
                    [--repeats 3] [--passes 5] [--topics 100] [--batch 256] [--out FILE.json]

Times are `proprio lda train`'s own "seconds" (training alone: MPI start-up, reading the corpus
and scoring the held-out pages excluded), wall clock of rank 0. The order of the two runs is
rotated per repeat; the machine's load average (/proc/loadavg) is read before and after each run.
The processor time of rank 0 is recorded beside (cpu_ratio: one process's over rank 0's).
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


def loadavg():
    return [float(x) for x in pathlib.Path("/proc/loadavg").read_text().split()[:3]]


def run(cmd, env):
    before = loadavg()
    t0 = time.monotonic()
    p = subprocess.run(cmd, env=env, capture_output=True, text=True)
    wall = time.monotonic() - t0
    if p.returncode != 0:
        sys.exit(f"bench_mpi: {' '.join(cmd)} failed ({p.returncode}):\n{p.stderr}")
    return before, loadavg(), wall


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--proprio", required=True)
    ap.add_argument("--corpus", required=True)
    ap.add_argument("--mpirun", default="mpirun")
    # On a shared machine: no binding of a rank to a core (the other users' processes are not
    # bound), and ranks that wait in a collective yield the processor instead of spinning.
    ap.add_argument("--mpirun-options", default="--oversubscribe --bind-to none "
                    "--mca mpi_yield_when_idle 1")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--passes", type=int, default=5)
    ap.add_argument("--topics", type=int, default=100)
    ap.add_argument("--batch", type=int, default=256)
    ap.add_argument("--out")
    a = ap.parse_args()
    corpus = pathlib.Path(a.corpus)
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    tmp = pathlib.Path(tempfile.mkdtemp(prefix="proprio_bench_mpi_"))
    results = []
    for r in range(1, a.repeats + 1):
        runs = {}
        order = ["1x1", "2x1"] if r % 2 else ["2x1", "1x1"]
        for name in order:
            model = tmp / f"{name}.lda"
            js = tmp / f"{name}.json"
            train = [a.proprio, "lda", "train", "--corpus", str(corpus / "train"), "--heldout",
                     str(corpus / "heldout"), "-k", str(a.topics), "--batch", str(a.batch),
                     "--passes", str(a.passes), "--seed", str(r), "--threads", "1",
                     "--model", str(model), "--json", str(js)]
            cmd = train if name == "1x1" else \
                [a.mpirun] + a.mpirun_options.split() + ["-np", "2"] + train
            before, after, wall = run(cmd, env)
            doc = json.loads(js.read_text())
            runs[name] = {"seconds": doc["seconds"], "cpu_seconds_rank0": doc["cpu_seconds"],
                          "command_wall_seconds": wall, "perplexity": doc["heldout_perplexity"],
                          "load_before": before, "load_after": after,
                          "model_bytes": model.read_bytes()}
        same = runs["1x1"].pop("model_bytes") == runs["2x1"].pop("model_bytes")
        if not same:
            sys.exit("bench_mpi: the 2-rank model differs from the one-process model")
        speedup = runs["1x1"]["seconds"] / runs["2x1"]["seconds"]
        # Processor time of one process over that of rank 0 of two: the speed-up an idle machine
        # would give if no rank ever waited (rank 0 does the replicated work and its half).
        cpu_ratio = runs["1x1"]["cpu_seconds_rank0"] / runs["2x1"]["cpu_seconds_rank0"]
        results.append({"seed": r, "runs": runs, "same_model": same, "speedup": speedup,
                        "cpu_ratio": cpu_ratio})
        print(f"seed {r}: 1 rank {runs['1x1']['seconds']:.2f} s, 2 ranks "
              f"{runs['2x1']['seconds']:.2f} s, speed-up {speedup:.2f}x (processor time "
              f"{runs['1x1']['cpu_seconds_rank0']:.2f} / {runs['2x1']['cpu_seconds_rank0']:.2f} s: "
              f"{cpu_ratio:.2f}x), perplexity "
              f"{runs['1x1']['perplexity']:.1f} (both), load "
              f"{runs['1x1']['load_before'][0]:.1f}/{runs['2x1']['load_before'][0]:.1f}",
              flush=True)
    summary = {"corpus": str(corpus), "topics": a.topics, "batch": a.batch, "passes": a.passes,
               "cpus": os.cpu_count(), "median_speedup":
               statistics.median(x["speedup"] for x in results),
               "median_cpu_ratio": statistics.median(x["cpu_ratio"] for x in results),
               "mpirun_options": a.mpirun_options, "repeats": results}
    print(f"median speed-up {summary['median_speedup']:.2f}x, processor-time ratio "
          f"{summary['median_cpu_ratio']:.2f}x")
    if a.out:
        pathlib.Path(a.out).write_text(json.dumps(summary, indent=2) + "\n")


if __name__ == "__main__":
    main()
