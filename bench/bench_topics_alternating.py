#!/usr/bin/python3
"""Usage: bench/bench_topics_alternating.py BEFORE/bench_topics AFTER/bench_topics REPEATS THREADS

Process CPU time (user + sys, all threads) of bench_topics' online LDA mini-batches, two builds
alternating: 1 warm-up round, then n rounds in alternating order; one invocation = the synthetic
corpus + 3 timed iterations (each 4 mini-batch updates of 256 documents, K = 100)."""
import resource, statistics, subprocess, sys
B, A, n, arg = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4]
def cpu(binary):
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run([binary, f"--benchmark_filter=BM_OnlineMiniBatches/{arg}/real_time", "--benchmark_min_time=0.000001",
                    "--benchmark_repetitions=3"], check=True, capture_output=True)
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
t = {"before": [], "after": []}
for r in range(-1, n):
    order = ["before", "after"] if r % 2 == 0 else ["after", "before"]
    for side in order:
        x = cpu(B if side == "before" else A)
        if r >= 0: t[side].append(round(x, 3))
mb, ma = statistics.median(t["before"]), statistics.median(t["after"])
sb = (max(t["before"]) - min(t["before"])) / mb / 2
sa = (max(t["after"]) - min(t["after"])) / ma / 2
print(f"threads {arg}: before {mb:.3f} s, after {ma:.3f} s, change {100*(ma-mb)/mb:+.1f}%, spread {100*max(sb,sa):.1f}%; before {t['before']} after {t['after']}")
