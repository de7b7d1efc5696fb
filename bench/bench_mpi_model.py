#!/usr/bin/python3
"""Strong-scaling model of data-parallel online LDA (issue 23) from measured constants.

usage: bench_mpi_model.py MEASURED.json [--markdown]
MEASURED.json is bench_mpi's output (build/bench/bench_mpi CORPUS/train 100 1000): per K, the
E-step per document, exp E[log beta] per (batch word x topic), the sufficient statistics per
(entry x topic), the M-step per (word x topic) and the combination (y += x) per element.

The job: one pass over D = 3,000,000 documents, W = 100,000 words, K topics, mini-batches of B
documents, P ranks of one thread, on a network of bandwidth bw and latency lat. Per mini-batch:

  E-step        t_doc * ceil(B / P)                    (parallel)
  beta cache    t_beta * V_B * K                       (batch words; replicated, or / P by topic)
  statistics    t_ss * E_B * K                         (replicated in `gather`, / P otherwise)
  M-step        t_m * W * K                            (replicated, or / P by topic)
  messages      a collective of n bytes: ceil(log2 P) * lat + (P - 1) / P * n / bw per pass
                (allgather, reduce-scatter); an allreduce is a reduce-scatter and an allgather.

Designs:
  gather     (implemented, `--mpi-design replicated`; bit-identical): allgather the
             batch's word ids and counts (8 E_B bytes), then what the E-step leaves (4 B K + 4 E_B
             + 8 B bytes); every rank sums the statistics and applies the M-step.
  by-topic-gather  (implemented, the default; bit-identical): the same two allgathers, plus an
             allgather of the batch's beta rows (4 V_B K bytes); each rank computes exp E[log
             beta], the statistics (over every document, in document order) and the M-step of
             its K / P topic rows only (the first two on whole vectors of 16 topics, so at most
             (ceil(K / P / 16) + 1) * 16 topics a rank).
  allreduce  the issue's first design: each rank sums its documents' statistics, allreduce of
             V_B x K (float32 or float64) plus the combination per element; M-step replicated.
             Not bit-identical to one process (another order of the sums).
  by-topic   reduce-scatter of the statistics by topic rows (float32), each rank the M-step and the
             beta cache of its K / P topics, allgather of the next batch's beta rows (float32).
  +lazy      the same with a lazy M-step: the decay of the words a batch does not touch kept as one
             affine map of lambda, so that an update costs V_B x K, not W x K (another rounding
             of lambda than today's one-process model: not bit-identical to it).
E_B = B * entries per document (measured); V_B, the distinct words of a batch, measured for B =
256 and assumed to grow as B^0.7 (Heaps-like), at most W.
"""
import argparse
import json
import math

D = 3_000_000
W = 100_000
NETWORKS = {"10 GbE": (1.25e9, 20e-6), "100 Gb InfiniBand": (12e9, 1.5e-6)}
RANKS = [8, 16, 64]
LANES = 16  # float32 lanes of the AVX-512 kernels


def collective(nbytes, p, bw, lat):
    if p == 1:
        return 0.0
    return math.ceil(math.log2(p)) * lat + (p - 1) / p * nbytes / bw


def batch_time(m, k, b, p, design, net, precision=4):
    bw, lat = net
    lazy = design.endswith("+lazy")
    design = design.replace("+lazy", "")
    e_b = b * m["entries_per_document"]
    v_b = min(W, m["batch_words_per_batch"] * (b / 256.0) ** 0.7)
    estep = m["estep_seconds_per_document"] * math.ceil(b / p)
    beta = m["beta_seconds_per_word_topic"] * v_b * k
    ss = m["sstats_seconds_per_entry_topic"] * e_b * k
    # The M-step decays every word of lambda; a lazy one keeps the decay of the words a batch does
    # not touch as one affine map (lambda = a lambda' + c) and updates the batch's words only.
    mstep = m["mstep_seconds_per_word_topic"] * (v_b if lazy else W) * k
    comb = (m["combine_float32_seconds_per_element"] if precision == 4
            else m["combine_float64_seconds_per_element"])
    if p == 1:
        return estep + beta + ss + mstep, 0.0
    if design == "gather":
        comm = collective(8 * e_b, p, bw, lat) + collective(4 * b * k + 4 * e_b + 8 * b, p, bw, lat)
        return estep + beta + ss + mstep + comm, comm
    if design == "allreduce":
        n = precision * v_b * k
        comm = 2 * collective(n, p, bw, lat)
        return estep + beta + ss / p + mstep + comm + comb * v_b * k * (p - 1) / p, comm
    if design == "by-topic-gather":
        comm = (collective(8 * e_b, p, bw, lat) + collective(4 * v_b * k, p, bw, lat)
                + collective(4 * b * k + 4 * e_b + 8 * b, p, bw, lat))
        # The vector kernels of exp E[log beta] and of the statistics run on whole vectors of
        # LANES topics: a rank's K / P rows cover up to ceil(K / P / LANES) + 1 vectors (measured
        # at K = 100, P = 2: rank 0 did 0.66 and 0.70 of one process's beta and statistics, the
        # M-step 0.49-0.56).
        covered = min(math.ceil(k / LANES) * LANES,
                      (math.ceil(k / p / LANES) + 1) * LANES) / k
        return estep + (beta + ss) * covered + mstep / p + comm, comm
    if design == "by-topic":
        n = 4 * v_b * k
        comm = 2 * collective(n, p, bw, lat) + collective(8 * e_b, p, bw, lat)
        return (estep + beta / p + ss / p + mstep / p + comm + comb * v_b * k * (p - 1) / p,
                comm)
    raise ValueError(design)


def efficiency(m, k, b, p, design, net, precision=4):
    t1, _ = batch_time(m, k, b, 1, design, net, precision)
    tp, comm = batch_time(m, k, b, p, design, net, precision)
    return t1 / (p * tp), comm / tp, tp * D / b


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("measured")
    a = ap.parse_args()
    data = json.load(open(a.measured))
    for m in data["measurements"]:
        k = m["K"]
        print(f"\nK = {k}: E-step {m['estep_seconds_per_document'] * 1e3:.3f} ms/document "
              f"({m['mean_estep_iterations']:.1f} iterations, {m['entries_per_document']:.0f} "
              f"distinct words), M-step {m['mstep_seconds_per_word_topic'] * 1e9:.2f} ns per "
              f"(word, topic) = {m['mstep_seconds_per_word_topic'] * W * k * 1e3:.1f} ms an update "
              f"at W = 100,000; beta {m['beta_seconds_per_word_topic'] * 1e9:.1f} ns, statistics "
              f"{m['sstats_seconds_per_entry_topic'] * 1e9:.2f} ns, y += x "
              f"{m['combine_float32_seconds_per_element'] * 1e9:.2f} ns (float32) / "
              f"{m['combine_float64_seconds_per_element'] * 1e9:.2f} ns (float64) per element")
        t1, _ = batch_time(m, k, 256, 1, "gather", NETWORKS["10 GbE"])
        print(f"one process, B = 256: {t1 * 1e3:.1f} ms a mini-batch, {t1 * D / 256 / 3600:.2f} h "
              f"a pass over 3M documents")
        print("| design | B | 10 GbE: 8 | 16 | 64 | InfiniBand: 8 | 16 | 64 | comm. share at 16, "
              "IB | pass over 3M docs at 16 ranks, IB |")
        print("|---|---|---|---|---|---|---|---|---|---|")
        for design, prec in [("gather", 4), ("by-topic-gather", 4), ("allreduce", 8),
                             ("allreduce", 4), ("by-topic", 4),
                             ("gather+lazy", 4), ("by-topic+lazy", 4)]:
            for b in [256, 4096]:
                label = design if not design.startswith("allreduce") else f"allreduce float{8 * prec}"
                if design in ("gather", "by-topic-gather"):
                    label += " (implemented)"
                row = []
                for net in NETWORKS.values():
                    effs = [efficiency(m, k, b, p, design, net, prec) for p in RANKS]
                    row += [f"{e[0] * 100:.0f}%" for e in effs]
                ib = efficiency(m, k, b, 16, design, NETWORKS["100 Gb InfiniBand"], prec)
                print(f"| {label} | {b} | " + " | ".join(row)
                      + f" | {ib[1] * 100:.0f}% | {ib[2] / 60:.1f} min |")

if __name__ == "__main__":
    main()
