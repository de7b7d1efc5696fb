#!/usr/bin/python3
"""The E-step's balance across MPI ranks (issue 23): `mpirun -np N proprio lda train --threads 1`
(split by topic) with the mini-batch's documents dealt d mod N (`--mpi-dealing modulo`) and
dealt by cost (the default), per rank: its E-step (processor seconds and wall seconds), its wait
at the collective after the E-step (wall seconds) and the E-step imbalance (summed over the
updates: the slowest rank's E-step processor time minus this rank's, the wait an idle machine
would see). The models must be the same bytes (the run stops otherwise). With --rss, each rank
runs under /usr/bin/time -v and its peak resident set is recorded, and one process beside.

usage: bench_mpi_balance.py --proprio build/app/proprio --corpus /tmp/mpi-man-small
                            [--ranks 2] [--repeats 3] [--passes 5] [--rss] [--out FILE.json]
"""
import argparse
import json
import os
import pathlib
import re
import statistics
import subprocess
import sys
import tempfile


def loadavg():
    return [float(x) for x in pathlib.Path("/proc/loadavg").read_text().split()[:3]]


def run(cmd, env):
    before = loadavg()
    p = subprocess.run(cmd, env=env, capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit(f"bench_mpi_balance: {' '.join(cmd)} failed ({p.returncode}):\n{p.stderr}")
    phases = {}
    for line in p.stderr.splitlines():
        if re.match(r'^\{"phase_times"', line):
            t = json.loads(line)["phase_times"]
            phases[t.get("rank", 0)] = t
    rss = [int(x) for x in re.findall(r"Maximum resident set size \(kbytes\): (\d+)", p.stderr)]
    return {"load_before": before, "load_after": loadavg(), "phases": phases,
            "max_rss_kb": sorted(rss)}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--proprio", required=True)
    ap.add_argument("--corpus", required=True)
    ap.add_argument("--mpirun", default="mpirun")
    ap.add_argument("--mpirun-options", default="--oversubscribe --bind-to none "
                    "--mca mpi_yield_when_idle 1")
    ap.add_argument("--ranks", type=int, default=2)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--passes", type=int, default=5)
    ap.add_argument("--topics", type=int, default=100)
    ap.add_argument("--batch", type=int, default=256)
    ap.add_argument("--rss", action="store_true", help="peak RSS per rank (/usr/bin/time -v)")
    ap.add_argument("--out")
    a = ap.parse_args()
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    tmp = pathlib.Path(tempfile.mkdtemp(prefix="proprio_bench_balance_"))
    timer = ["/usr/bin/time", "-v"] if a.rss else []
    results = []
    for r in range(1, a.repeats + 1):
        runs = {}
        names = ["d-mod-P", "by-cost"] + (["1x1"] if a.rss else [])
        for name in (names if r % 2 else names[::-1]):
            model = tmp / f"{name}.lda"
            train = timer + [a.proprio, "lda", "train", "--corpus", str(pathlib.Path(a.corpus) /
                             "train"), "-k", str(a.topics), "--batch", str(a.batch), "--passes",
                             str(a.passes), "--seed", str(r), "--threads", "1", "--model",
                             str(model), "--phase-times"]
            if name == "d-mod-P":
                train += ["--mpi-dealing", "modulo"]
            if name == "1x1":
                cmd = train
            else:
                cmd = [a.mpirun] + a.mpirun_options.split() + ["-np", str(a.ranks)] + train
            runs[name] = run(cmd, env)
            runs[name]["model_bytes"] = model.read_bytes()
        one = runs["by-cost"]["model_bytes"]
        if any(runs[n].pop("model_bytes") != one for n in names):
            sys.exit("bench_mpi_balance: the models differ")
        line = f"seed {r}:"
        for n in ["d-mod-P", "by-cost"]:
            ph = runs[n]["phases"]
            est = [ph[q]["estep"] for q in sorted(ph)]
            wait = [ph[q]["wait_wall"] for q in sorted(ph)]
            imb = [ph[q]["estep_imbalance"] for q in sorted(ph)]
            line += (f" {n}: E-step cpu {'/'.join(f'{x:.2f}' for x in est)} s, wait "
                     f"{'/'.join(f'{x:.2f}' for x in wait)} s, imbalance "
                     f"{'/'.join(f'{x:.3f}' for x in imb)} s;")
        if a.rss:
            line += " peak RSS kB " + ", ".join(f"{n} {runs[n]['max_rss_kb']}" for n in names)
        print(line + f" load {runs['by-cost']['load_before'][0]:.1f}", flush=True)
        results.append({"seed": r, "runs": runs})

    def med(n, key):
        return [statistics.median(x["runs"][n]["phases"][q][key] for x in results)
                for q in range(a.ranks)]
    summary = {"corpus": a.corpus, "ranks": a.ranks, "topics": a.topics, "batch": a.batch,
               "passes": a.passes, "mpirun_options": a.mpirun_options,
               "median": {n: {k: med(n, k) for k in ["estep", "estep_wall", "wait_wall",
                                                      "estep_imbalance", "updates"]}
                          for n in ["d-mod-P", "by-cost"]},
               "repeats": results}
    print(json.dumps(summary["median"]))
    if a.out:
        pathlib.Path(a.out).write_text(json.dumps(summary, indent=2) + "\n")


if __name__ == "__main__":
    main()
