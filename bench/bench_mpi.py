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
The processor time of rank 0 is recorded beside (cpu_ratio: one process's over rank 0's), and
its processor seconds per phase of the updates (E-step, exp E[log beta], sufficient statistics,
M-step, communication: `lda train --phase-times`; every rank's line is kept in phases_by_rank,
with its E-step and wait wall seconds and its E-step imbalance). Each repeat runs one process and 2 ranks of each
design in --designs (--mpi-design: by-topic, the default, and replicated); a design
written DESIGN/three runs with the earlier exchange of three allgathers a batch
(--mpi-exchange three) instead of the lean one (2026-12-03), e.g. --designs
by-topic,by-topic/three. Each line also gives rank 0's processor milliseconds a batch in the
communication phase (the batch's assembly, the collectives with their waiting, the unpacking).
"""
import argparse
import json
import re
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
    phases = {}  # by rank (every rank prints its line; "rank" is absent before 2026-12-02)
    for line in p.stderr.splitlines():
        if re.match(r'^\{"phase_times"', line):
            t = json.loads(line)["phase_times"]
            phases[t.get("rank", 0)] = t
    return before, loadavg(), wall, phases


def comm_ms(run_record):
    """Rank 0's processor milliseconds a batch in the communication phase (nan without it)."""
    t = run_record.get("phase_cpu_seconds_rank0") or {}
    return 1000 * t["communication"] / t["updates"] if t.get("updates") else float("nan")


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
    ap.add_argument("--designs", default="by-topic,replicated",
                    help="the 2-rank designs to run, comma-separated")
    ap.add_argument("--out")
    a = ap.parse_args()
    designs = [d for d in a.designs.split(",") if d]
    corpus = pathlib.Path(a.corpus)
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    tmp = pathlib.Path(tempfile.mkdtemp(prefix="proprio_bench_mpi_"))
    results = []
    for r in range(1, a.repeats + 1):
        runs = {}
        names = ["1x1"] + [f"2x1-{d.replace('/', '-')}" for d in designs]
        order = names if r % 2 else names[::-1]
        for name in order:
            model = tmp / f"{name}.lda"
            js = tmp / f"{name}.json"
            train = [a.proprio, "lda", "train", "--corpus", str(corpus / "train"), "--heldout",
                     str(corpus / "heldout"), "-k", str(a.topics), "--batch", str(a.batch),
                     "--passes", str(a.passes), "--seed", str(r), "--threads", "1",
                     "--model", str(model), "--json", str(js), "--phase-times"]
            if name != "1x1":
                design = designs[names.index(name) - 1]
                train += ["--mpi-design", design.split("/")[0]]
                if design.endswith("/three"):
                    train += ["--mpi-exchange", "three"]
            cmd = train if name == "1x1" else \
                [a.mpirun] + a.mpirun_options.split() + ["-np", "2"] + train
            before, after, wall, phases = run(cmd, env)
            doc = json.loads(js.read_text())
            runs[name] = {"seconds": doc["seconds"], "cpu_seconds_rank0": doc["cpu_seconds"],
                          "command_wall_seconds": wall, "perplexity": doc["heldout_perplexity"],
                          "load_before": before, "load_after": after,
                          "phase_cpu_seconds_rank0": phases.get(0),
                          "phases_by_rank": phases,
                          "model_bytes": model.read_bytes()}
        one = runs["1x1"].pop("model_bytes")
        same = all(runs[n].pop("model_bytes") == one for n in names[1:])
        if not same:
            sys.exit("bench_mpi: a 2-rank model differs from the one-process model")
        entry = {"seed": r, "runs": runs, "same_model": same, "speedup": {}, "cpu_ratio": {}}
        line = (f"seed {r}: 1 rank {runs['1x1']['seconds']:.2f} s "
                f"(load {runs['1x1']['load_before'][0]:.1f})")
        for n in names[1:]:
            entry["speedup"][n] = runs["1x1"]["seconds"] / runs[n]["seconds"]
            # Processor time of one process over that of rank 0 of two: the speed-up an idle
            # machine would give if no rank ever waited.
            entry["cpu_ratio"][n] = runs["1x1"]["cpu_seconds_rank0"] / runs[n]["cpu_seconds_rank0"]
            line += (f"; {n} {runs[n]['seconds']:.2f} s, speed-up {entry['speedup'][n]:.2f}x, "
                     f"processor time {entry['cpu_ratio'][n]:.2f}x, "
                     f"communication {comm_ms(runs[n]):.2f} ms a batch "
                     f"(load {runs[n]['load_before'][0]:.1f})")
        results.append(entry)
        print(line + f", perplexity {runs['1x1']['perplexity']:.1f} (all)", flush=True)
    summary = {"corpus": str(corpus), "topics": a.topics, "batch": a.batch, "passes": a.passes,
               "cpus": os.cpu_count(), "designs": designs,
               "median_speedup": {n: statistics.median(x["speedup"][n] for x in results)
                                  for n in names[1:]},
               "median_cpu_ratio": {n: statistics.median(x["cpu_ratio"][n] for x in results)
                                    for n in names[1:]},
               "median_communication_ms_rank0": {
                   n: statistics.median(comm_ms(x["runs"][n]) for x in results) for n in names[1:]},
               "mpirun_options": a.mpirun_options, "repeats": results}
    for n in names[1:]:
        print(f"{n}: median speed-up {summary['median_speedup'][n]:.2f}x, processor-time ratio "
              f"{summary['median_cpu_ratio'][n]:.2f}x, communication "
              f"{summary['median_communication_ms_rank0'][n]:.2f} ms a batch (rank 0, processor)")
    if a.out:
        pathlib.Path(a.out).write_text(json.dumps(summary, indent=2) + "\n")


if __name__ == "__main__":
    main()
