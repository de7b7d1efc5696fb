#!/usr/bin/python3
"""Per-batch processor milliseconds of the data-parallel LDA's phases, from bench_mpi.py's JSON:
for each 2-rank run and rank, the communication phase split into the collectives (processor time
inside the MPI calls, waiting included: on a loaded machine mostly the scheduler) and the rest
(the batch's assembly, packing and unpacking: the program's own work, little affected by load),
with the MPI calls a batch; medians over the repeats.

usage: bench_mpi_phases.py RESULT.json [RESULT.json ...]
"""
import json
import statistics
import sys


def main():
    for path in sys.argv[1:]:
        doc = json.load(open(path))
        print(f"{path} (K {doc['topics']}, B {doc['batch']}, {doc['passes']} passes)")
        names = sorted({n for r in doc["repeats"] for n in r["runs"] if n != "1x1"})
        print("| run | rank | communication | in the collectives | assembly, packing, unpacking "
              "| collectives' wall | MPI calls | E-step | beta | statistics | M-step | load |")
        print("|---|---|---|---|---|---|---|---|---|---|---|---|")
        one = [r["runs"]["1x1"]["phase_cpu_seconds_rank0"] for r in doc["repeats"]]
        def ms(ts, key):
            vals = [1000 * t.get(key, float("nan")) / t["updates"] for t in ts if t]
            return statistics.median(vals) if vals else float("nan")
        load = statistics.median(r["runs"]["1x1"]["load_before"][0] for r in doc["repeats"])
        print(f"| 1 process | 0 | {ms(one, 'communication'):.3f} | | | | | {ms(one, 'estep'):.2f} "
              f"| {ms(one, 'beta'):.2f} | {ms(one, 'statistics'):.2f} | {ms(one, 'mstep'):.2f} "
              f"| {load:.1f} |")
        for n in names:
            for rank in ("0", "1"):
                ts = [r["runs"][n]["phases_by_rank"].get(rank) for r in doc["repeats"]]
                ts = [t for t in ts if t]
                own = statistics.median(1000 * (t["communication"] - t.get("collective_cpu", 0))
                                        / t["updates"] for t in ts) \
                    if all("collective_cpu" in t for t in ts) else float("nan")
                calls = statistics.median(t.get("collectives", float("nan")) / t["updates"]
                                          for t in ts)
                load = statistics.median(r["runs"][n]["load_before"][0] for r in doc["repeats"])
                print(f"| {n} | {rank} | {ms(ts, 'communication'):.3f} | "
                      f"{ms(ts, 'collective_cpu'):.3f} | {own:.3f} | "
                      f"{ms(ts, 'collective_wall'):.3f} | {calls:.2f} | {ms(ts, 'estep'):.2f} | "
                      f"{ms(ts, 'beta'):.2f} | {ms(ts, 'statistics'):.2f} | {ms(ts, 'mstep'):.2f} "
                      f"| {load:.1f} |")


if __name__ == "__main__":
    main()
