#!/usr/bin/python3
"""Issue 21's speed goal: the perception of a push (the segmentation of its frames, the word and
Dirichlet updates, the top-down recognition of the looks after it) takes less processor time on
one core than the push itself lasts, so that a real robot would never wait for it.

usage: bench_learn_perception.py --proprio build/app/proprio [--seeds 1] [--quick]
                                 [--core 0] [--extra "..."] [--out FILE.json]

Runs `proprio learn` (the default world: book, bottle, CD, giraffe, 3 objects of clutter, the
moving backdrop) pinned to one core (taskset -c CORE; OpenCV's and OpenMP's threads then share
it) and reads learn.json: each executed push's `perception_cpu_seconds` (processor time of the
whole process, every thread) against its `robot_seconds` (the push's duration on the robot's
clock, from the transit out to the arm's rest), its recorded part (the episode's frames over the
frame rate: what the camera saw of it, the stricter yardstick), and the processor seconds per
stage (`timing`). The simulator's rendering and physics
(stage "push") stand for the robot and are not perception. The machine's load average
(/proc/loadavg) is recorded before and after each run: processor time does not grow with the
load, but caches shared with other processes may.
"""
import argparse
import json
import os
import pathlib
import shlex
import statistics
import subprocess
import sys
import tempfile

PERCEPTION = ("segmentation", "words", "recognition")


def loadavg():
    return [float(x) for x in pathlib.Path("/proc/loadavg").read_text().split()[:3]]


def one_run(args, seed, out):
    cmd = ["taskset", "-c", str(args.core), args.proprio, "learn", "--seed", str(seed),
           "--out", str(out), "--overwrite", "-q"]
    if args.quick:
        cmd.append("--quick")
    cmd += shlex.split(args.extra)
    env = dict(os.environ, OMP_NUM_THREADS="1")
    before = loadavg()
    subprocess.run(cmd, check=True, env=env, stdout=subprocess.DEVNULL)
    after = loadavg()
    j = json.loads((out / "learn.json").read_text())
    pushes = [p for p in j["pushes"] if p["executed"] and p.get("robot_seconds", 0) > 0]
    if not pushes:
        sys.exit(f"seed {seed}: no executed push recorded its times (an older proprio?)")
    fps = j["options"]["fps"]
    rows = [{"index": p["index"], "class": p.get("class", ""),
             "robot_seconds": p["robot_seconds"],
             "recorded_seconds": p["frames"] / fps,
             "perception_cpu_seconds": p["perception_cpu_seconds"],
             "ratio": p["perception_cpu_seconds"] / p["robot_seconds"],
             "ratio_recorded": p["perception_cpu_seconds"] * fps / max(p["frames"], 1)}
            for p in pushes]
    stages = {t["stage"]: t for t in j["timing"]}
    cpu = {s: stages[s].get("cpu_seconds", 0.0) for s in PERCEPTION if s in stages}
    shown = [("RUN_DIR" if c == str(out) else c) for c in cmd]  # no temporary path recorded
    return {"seed": seed, "command": " ".join(shlex.quote(c) for c in shown),
            "loadavg_before": before, "loadavg_after": after, "pushes": rows,
            "perception_stage_cpu_seconds": cpu,
            "stage_cpu_seconds": {s: t["cpu_seconds"] for s, t in stages.items()
                                  if "cpu_seconds" in t},
            "stage_wall_seconds": {s: t["seconds"] for s, t in stages.items()}}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--proprio", default="build/app/proprio")
    ap.add_argument("--seeds", default="1", help="space-separated seeds")
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--core", type=int, default=0)
    ap.add_argument("--extra", default="", help="more learn options")
    ap.add_argument("--out", help="write the figures here (JSON)")
    args = ap.parse_args()
    runs = []
    with tempfile.TemporaryDirectory(prefix="proprio-bench-learn-") as tmp:
        for seed in args.seeds.split():
            runs.append(one_run(args, int(seed), pathlib.Path(tmp) / f"s{seed}"))
    rows = [r for run in runs for r in run["pushes"]]
    ratios = sorted(r["ratio"] for r in rows)
    faster = sum(1 for r in ratios if r < 1)
    recorded = sorted(r["ratio_recorded"] for r in rows)
    faster_recorded = sum(1 for r in recorded if r < 1)
    stage_cpu = {s: sum(run["perception_stage_cpu_seconds"].get(s, 0.0) for run in runs)
                 for s in PERCEPTION}
    total = sum(stage_cpu.values())
    summary = {
        "pushes": len(rows),
        "perceived_faster_than_pushed": faster,
        "perception_cpu_seconds_mean": statistics.mean(r["perception_cpu_seconds"] for r in rows),
        "robot_seconds_mean": statistics.mean(r["robot_seconds"] for r in rows),
        "ratio_median": statistics.median(ratios),
        "ratio_max": ratios[-1],
        "recorded_seconds_mean": statistics.mean(r["recorded_seconds"] for r in rows),
        "perceived_faster_than_recorded": faster_recorded,
        "ratio_recorded_median": statistics.median(recorded),
        "ratio_recorded_max": recorded[-1],
        "perception_cpu_share": {s: (stage_cpu[s] / total if total > 0 else 0.0)
                                 for s in PERCEPTION},
    }
    print(f"{len(rows)} executed pushes over seeds {args.seeds}{' (--quick)' if args.quick else ''}"
          f", one core ({args.core}):")
    print(f"  perception {summary['perception_cpu_seconds_mean']:.2f} s of processor time a push"
          f" against {summary['robot_seconds_mean']:.2f} s of push (robot clock) on average")
    print(f"  ratio perception / push: median {summary['ratio_median']:.2f}, "
          f"largest {summary['ratio_max']:.2f}; {faster} of {len(rows)} pushes perceived faster "
          "than they lasted")
    print(f"  against the recorded part ({summary['recorded_seconds_mean']:.2f} s a push on "
          f"average): median {summary['ratio_recorded_median']:.2f}, largest "
          f"{summary['ratio_recorded_max']:.2f}; {faster_recorded} of {len(rows)} faster")
    print("  perception's processor time: " + ", ".join(
        f"{s} {100 * summary['perception_cpu_share'][s]:.0f}%" for s in PERCEPTION))
    for run in runs:
        print(f"  seed {run['seed']}: load {run['loadavg_before'][0]:.2f} -> "
              f"{run['loadavg_after'][0]:.2f}; processor s per stage: " + ", ".join(
                  f"{s} {v:.1f}" for s, v in sorted(run["stage_cpu_seconds"].items())))
    if args.out:
        pathlib.Path(args.out).write_text(json.dumps(
            {"summary": summary, "runs": runs}, indent=1) + "\n")


if __name__ == "__main__":
    main()
