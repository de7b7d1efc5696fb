// The LDA engine's own speed: the per-document E-step on each instruction set, and online
// mini-batch updates on 1 and 2 threads, on a synthetic corpus shaped like the man-page one
// (K = 100, W = 10,000, about 600 tokens per document). The comparison with gensim and
// scikit-learn on real text is bench/bench_topics.py. Last, the Dirichlet fit (issue 17).
#include <benchmark/benchmark.h>

#include "engine.hpp"
#include "kernels.hpp"
#include "proprio/core/random.hpp"
#include "proprio/topics/dirichlet.hpp"
#include "proprio/topics/dirichlet_fit.hpp"
#include "proprio/topics/dirichlet_stats.hpp"
#include "proprio/topics/online_lda.hpp"
#include "proprio/topics/synthetic.hpp"

namespace proprio::topics {
namespace {

const SyntheticCorpus& corpus() {
  static const SyntheticCorpus s = [] {
    SyntheticCorpusOptions o;
    o.num_topics = 100;
    o.num_words = 10000;
    o.num_documents = 1024;
    o.mean_length = 600;
    o.alpha = 0.05;
    o.eta = 0.01;
    o.seed = 1;
    return make_synthetic_corpus(o);
  }();
  return s;
}

// One document E-step against a trained-looking beta (the true topics, floored).
void BM_EStepDocument(benchmark::State& state, const char* kernel) {
  const detail::Kernels* k = nullptr;
  try {
    k = &detail::kernels_named(kernel);
  } catch (...) {
    state.SkipWithError("kernel not supported here");
    return;
  }
  const auto& s = corpus();
  const int K = 100;
  const int stride = detail::padded(K, k->lanes);
  detail::FloatBuffer beta(static_cast<std::size_t>(s.corpus.num_words() * stride), 0.0f);
  for (int w = 0; w < s.corpus.num_words(); ++w) {
    for (int t = 0; t < K; ++t) {
      beta[static_cast<std::size_t>(w * stride + t)] =
          static_cast<float>(std::max(s.topics(t, w), 1e-12));
    }
  }
  detail::BatchDocs docs;
  detail::corpus_docs(s.corpus, 1, 0, docs);
  detail::FloatBuffer gamma(static_cast<std::size_t>(stride)), eth(gamma), scratch(gamma);
  detail::FloatBuffer weights(docs.rows.size());
  std::size_t d = 0;
  std::int64_t iterations = 0;
  std::int64_t entries = 0;
  for (auto _ : state) {
    const std::size_t b = docs.offsets[d];
    const int n = static_cast<int>(docs.offsets[d + 1] - b);
    std::fill(gamma.begin(), gamma.end(), 1.0f);
    detail::DocEStepArgs a;
    a.ids = docs.rows.data() + b;
    a.counts = docs.counts.data() + b;
    a.n = n;
    a.beta = beta.data();
    a.num_topics = K;
    a.stride = stride;
    a.alpha = 0.01f;
    a.gamma = gamma.data();
    a.exp_elog_theta = eth.data();
    a.weights = weights.data() + b;
    a.scratch = scratch.data();
    const auto out = k->estep_doc(a);
    iterations += out.iterations;
    entries += static_cast<std::int64_t>(n) * out.iterations;
    benchmark::DoNotOptimize(gamma.data());
    d = (d + 1) % docs.size();
  }
  state.counters["iterations/doc"] =
      benchmark::Counter(static_cast<double>(iterations) / static_cast<double>(state.iterations()));
  state.counters["word-iterations/s"] =
      benchmark::Counter(static_cast<double>(entries), benchmark::Counter::kIsRate);
}
BENCHMARK_CAPTURE(BM_EStepDocument, generic, "generic");
BENCHMARK_CAPTURE(BM_EStepDocument, avx2, "avx2");
BENCHMARK_CAPTURE(BM_EStepDocument, avx512, "avx512");

// Online updates with mini-batches of 256 documents, K = 100.
void BM_OnlineMiniBatches(benchmark::State& state) {
  const auto& s = corpus();
  OnlineLdaOptions o;
  o.num_topics = 100;
  o.batch_size = 256;
  o.threads = static_cast<int>(state.range(0));
  for (auto _ : state) {
    state.PauseTiming();
    OnlineLda lda(o, s.corpus.num_words(), static_cast<std::int64_t>(s.corpus.num_documents()));
    state.ResumeTiming();
    for (std::size_t b = 0; b < s.corpus.num_documents(); b += 256) {
      lda.update(s.corpus, b, std::min(s.corpus.num_documents(), b + 256));
    }
  }
  state.counters["docs/s"] = benchmark::Counter(
      static_cast<double>(s.corpus.num_documents()) * static_cast<double>(state.iterations()),
      benchmark::Counter::kIsRate);
}
BENCHMARK(BM_OnlineMiniBatches)->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMillisecond);

// The Dirichlet fit of issue 17 on 10,000 x 25 proportions (alpha log-uniform in [0.05, 20]):
// the one pass that checks the rows and sums log p (the floor of any fit), and the whole fit
// (that pass, then O(T) per iteration). Target: the fit under 5 ms and at most 1.5x the pass.
const Eigen::MatrixXd& dirichlet_proportions() {
  static const Eigen::MatrixXd p = [] {
    core::Rng rng(17);
    Eigen::VectorXd alpha(25);
    for (auto& a : alpha) a = std::exp(rng.uniform(std::log(0.05), std::log(20.0)));
    return Eigen::MatrixXd(Dirichlet(alpha).sample_log(rng, 10000).array().exp());
  }();
  return p;
}

void BM_DirichletStatsPass(benchmark::State& state) {
  const auto& p = dirichlet_proportions();
  for (auto _ : state) {
    auto stats = DirichletStats::of_proportions(p);
    benchmark::DoNotOptimize(stats);
  }
  state.SetItemsProcessed(state.iterations() * p.size());
}
BENCHMARK(BM_DirichletStatsPass)->Unit(benchmark::kMillisecond);

void BM_DirichletFit(benchmark::State& state) {
  const auto& p = dirichlet_proportions();
  int iterations = 0;
  for (auto _ : state) {
    auto fit = fit_dirichlet(p);
    iterations = fit.summary.iterations();
    benchmark::DoNotOptimize(fit);
  }
  state.SetItemsProcessed(state.iterations() * p.size());
  state.counters["fit-iterations"] = iterations;
}
BENCHMARK(BM_DirichletFit)->Unit(benchmark::kMillisecond);

// The fit's own part, from statistics already computed: O(T) per iteration.
void BM_DirichletFitFromStats(benchmark::State& state) {
  const auto stats = DirichletStats::of_proportions(dirichlet_proportions());
  for (auto _ : state) {
    auto fit = fit_dirichlet(stats);
    benchmark::DoNotOptimize(fit);
  }
}
BENCHMARK(BM_DirichletFitFromStats)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace proprio::topics

BENCHMARK_MAIN();
