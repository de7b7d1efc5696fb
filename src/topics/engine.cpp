#include "engine.hpp"
#include "proprio/core/random.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <numeric>

namespace proprio::topics::detail {

namespace {
constexpr Eigen::Index kWordBlock = 512;
}

Eigen::VectorXd topic_sums(const Eigen::MatrixXd& lambda, core::ThreadPool& pool) {
  const Eigen::Index K = lambda.rows();
  const Eigen::Index W = lambda.cols();
  const auto blocks = static_cast<std::size_t>((W + kWordBlock - 1) / kWordBlock);
  Eigen::MatrixXd partial = Eigen::MatrixXd::Zero(K, static_cast<Eigen::Index>(blocks));
  // Every row is summed in the same order, whatever K and whatever rows the matrix holds (a rank
  // holding some rows of lambda gets the bits of one process holding all): in a block, the first
  // column, then groups of four columns added pairwise, then the rest one by one. This is the
  // order of Eigen 3.4's vectorised rowwise().sum(), used here before, so that models with an
  // even K are unchanged (with an odd K, Eigen summed its last row in another order).
  core::parallel_for(pool, blocks, [&](std::size_t b, int) {
    const Eigen::Index w0 = static_cast<Eigen::Index>(b) * kWordBlock;
    const Eigen::Index n = std::min(kWordBlock, W - w0);
    double* p = partial.col(static_cast<Eigen::Index>(b)).data();
    const auto column = [&](Eigen::Index i) { return lambda.col(w0 + i).data(); };
    const double* c0 = column(0);
    for (Eigen::Index k = 0; k < K; ++k) p[k] = c0[k];
    const Eigen::Index groups = (n - 1) & ~Eigen::Index{3};
    Eigen::Index i = 1;
    for (; i < groups; i += 4) {
      const double* a = column(i);
      const double* b1 = column(i + 1);
      const double* c = column(i + 2);
      const double* d = column(i + 3);
      for (Eigen::Index k = 0; k < K; ++k) p[k] = p[k] + ((a[k] + b1[k]) + (c[k] + d[k]));
    }
    for (; i < n; ++i) {
      const double* a = column(i);
      for (Eigen::Index k = 0; k < K; ++k) p[k] = p[k] + a[k];
    }
  });
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(K);
  for (std::size_t b = 0; b < blocks; ++b) sum += partial.col(static_cast<Eigen::Index>(b));
  return sum;
}

void exp_elog_beta(const Kernels& kern, const Eigen::MatrixXd& lambda,
                   const Eigen::VectorXd& topic_sum, std::span<const std::int32_t> words,
                   int stride, core::ThreadPool& pool, FloatBuffer& out) {
  const int K = static_cast<int>(lambda.rows());
  out.resize(words.size() * static_cast<std::size_t>(stride));
  FloatBuffer sub(static_cast<std::size_t>(stride), 0.0f);
  for (int k = 0; k < K; ++k)
    sub[static_cast<std::size_t>(k)] = static_cast<float>(digamma(topic_sum(k)));
  std::vector<FloatBuffer> tmp(static_cast<std::size_t>(pool.size()),
                               FloatBuffer(static_cast<std::size_t>(stride), 1.0f));
  constexpr std::size_t kBlock = 64;
  const std::size_t blocks = (words.size() + kBlock - 1) / kBlock;
  core::parallel_for(pool, blocks, [&](std::size_t b, int t) {
    float* x = tmp[static_cast<std::size_t>(t)].data();
    const std::size_t end = std::min(words.size(), (b + 1) * kBlock);
    for (std::size_t i = b * kBlock; i < end; ++i) {
      const double* col = lambda.col(words[i]).data();
      for (int k = 0; k < K; ++k) x[k] = static_cast<float>(col[k]);
      float* row = out.data() + i * static_cast<std::size_t>(stride);
      kern.exp_digamma_minus(x, sub.data(), row, stride);
      for (int k = K; k < stride; ++k) row[k] = 0.0f;
    }
  });
}

namespace {

// The SplitMix64 generator: state advances by the golden gamma, each output is its mix.
std::uint64_t splitmix(std::uint64_t& state) {
  const std::uint64_t z = core::splitmix64(state);
  state += 0x9e3779b97f4a7c15ULL;
  return z;
}

double uniform01(std::uint64_t& state) {
  return (static_cast<double>(splitmix(state) >> 11) + 0.5) * 0x1.0p-53;
}

}  // namespace

void random_gamma(std::uint64_t key, int n, float* out) {
  // Marsaglia & Tsang (2000) for shape 100, scaled by 1/100; normals by Box-Muller.
  constexpr double kShape = 100.0;
  const double d = kShape - 1.0 / 3.0;
  const double c = 1.0 / std::sqrt(9.0 * d);
  std::uint64_t state = key;
  double spare = 0.0;
  bool has_spare = false;
  auto normal = [&] {
    if (has_spare) {
      has_spare = false;
      return spare;
    }
    const double u1 = uniform01(state);
    const double u2 = uniform01(state);
    const double r = std::sqrt(-2.0 * std::log(u1));
    spare = r * std::sin(2.0 * M_PI * u2);
    has_spare = true;
    return r * std::cos(2.0 * M_PI * u2);
  };
  for (int i = 0; i < n; ++i) {
    for (;;) {
      const double x = normal();
      double v = 1.0 + c * x;
      if (v <= 0.0) continue;
      v = v * v * v;
      const double u = uniform01(state);
      const double x2 = x * x;
      if (u < 1.0 - 0.0331 * x2 * x2 || std::log(u) < 0.5 * x2 + d * (1.0 - v + std::log(v))) {
        out[i] = static_cast<float>(d * v / kShape);
        break;
      }
    }
  }
}

Eigen::MatrixXd initial_lambda(int num_topics, int num_words, std::uint64_t seed,
                               core::ThreadPool& pool) {
  const auto K = static_cast<std::size_t>(num_topics);
  Eigen::MatrixXd lambda(num_topics, num_words);
  std::vector<float> tmp(K * static_cast<std::size_t>(pool.size()));
  core::parallel_for(pool, static_cast<std::size_t>(num_words), [&](std::size_t w, int t) {
    float* g = tmp.data() + static_cast<std::size_t>(t) * K;
    random_gamma(core::stream_seed(seed, ~0ULL, w), num_topics, g);
    for (std::size_t k = 0; k < K; ++k) {
      lambda(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(w)) = g[k];
    }
  });
  return lambda;
}

void corpus_docs(const Corpus& corpus, std::uint64_t seed, std::uint64_t update, BatchDocs& docs,
                 std::span<const std::int32_t> weights) {
  assert(weights.empty() || std::ssize(weights) == corpus.num_words());
  docs.clear();
  docs.rows.reserve(corpus.num_entries());
  docs.counts.reserve(corpus.num_entries());
  for (std::size_t d = 0; d < corpus.num_documents(); ++d) {
    const auto doc = corpus.document(d);
    docs.rows.insert(docs.rows.end(), doc.words.begin(), doc.words.end());
    for (std::size_t i = 0; i < doc.size(); ++i) {
      const auto c = static_cast<float>(doc.counts[i]);
      docs.counts.push_back(
          weights.empty()
              ? c
              : c * static_cast<float>(weights[static_cast<std::size_t>(doc.words[i])]));
    }
    docs.offsets.push_back(docs.rows.size());
    docs.keys.push_back(core::stream_seed(seed, update, d));
  }
}

void run_estep(const Kernels& kern, core::ThreadPool& pool, const BatchDocs& docs,
               const float* beta, int num_topics, int stride, double alpha,
               const EStepOptions& options, BatchEStep& out) {
  const std::size_t D = docs.size();
  const auto S = static_cast<std::size_t>(stride);
  out.stride = stride;
  out.gamma.resize(D * S);
  out.exp_elog_theta.resize(D * S);
  out.weights.resize(docs.rows.size());
  out.iterations.assign(D, 0);
  out.converged.assign(D, 1);
  out.log_norm.assign(D, 0.0);
  std::vector<FloatBuffer> scratch(static_cast<std::size_t>(pool.size()), FloatBuffer(S));
  const bool random = options.init == GammaInit::kRandomGamma;
  // Longest documents first, so that no thread is left with a long one at the end (the order
  // changes nothing else: each document's result is its own).
  std::vector<std::size_t> order(D);
  for (std::size_t d = 0; d < D; ++d) order[d] = d;
  if (pool.size() > 1) {
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
      return docs.offsets[a + 1] - docs.offsets[a] > docs.offsets[b + 1] - docs.offsets[b];
    });
  }
  core::parallel_for(pool, D, [&](std::size_t task, int t) {
    const std::size_t d = order[task];
    float* gamma = out.gamma.data() + d * S;
    float* eth = out.exp_elog_theta.data() + d * S;
    const std::size_t b = docs.offsets[d];
    const int n = static_cast<int>(docs.offsets[d + 1] - b);
    if (n == 0) {
      // No evidence: gamma is the prior; nothing to accumulate.
      std::fill(gamma, gamma + S, static_cast<float>(alpha));
      std::fill(eth, eth + S, 0.0f);
      return;
    }
    if (random) {
      random_gamma(docs.keys[d], num_topics, gamma);
    } else {
      std::fill(gamma, gamma + num_topics, 1.0f);
    }
    DocEStepArgs a;
    a.ids = docs.rows.data() + b;
    a.counts = docs.counts.data() + b;
    a.n = n;
    a.beta = beta;
    a.num_topics = num_topics;
    a.stride = stride;
    a.alpha = static_cast<float>(alpha);
    a.max_iterations = options.max_iterations;
    a.tolerance = static_cast<float>(options.tolerance);
    a.gamma = gamma;
    a.exp_elog_theta = eth;
    a.weights = out.weights.data() + b;
    a.scratch = scratch[static_cast<std::size_t>(t)].data();
    const DocEStepOut r = kern.estep_doc(a);
    out.iterations[d] = r.iterations;
    out.converged[d] = r.converged ? 1 : 0;
    out.log_norm[d] = r.log_norm;
  });
}

CorpusEStep corpus_estep(const Kernels& kern, core::ThreadPool& pool, const LdaModel& model,
                         const Corpus& corpus, const EStepOptions& options, std::uint64_t seed) {
  CorpusEStep r;
  const int K = model.num_topics();
  r.stride = padded(K, kern.lanes);
  r.topic_sum = topic_sums(model.lambda, pool);
  std::vector<std::int32_t> all(static_cast<std::size_t>(model.num_words()));
  std::iota(all.begin(), all.end(), 0);
  FloatBuffer beta;
  exp_elog_beta(kern, model.lambda, r.topic_sum, all, r.stride, pool, beta);
  // A model trained on weighted documents reads documents weighted alike (LdaModel::word_weights).
  corpus_docs(corpus, seed, 0, r.docs, model.word_weights);
  run_estep(kern, pool, r.docs, beta.data(), K, r.stride, model.alpha, options, r.estep);
  return r;
}

void sufficient_statistics(const Kernels& kern, core::ThreadPool& pool, const BatchDocs& docs,
                           const BatchEStep& estep, std::size_t rows, FloatBuffer& sstats) {
  const int stride = estep.stride;
  const auto S = static_cast<std::size_t>(stride);
  sstats.assign(rows * S, 0.0f);
  // Each thread owns a range of topics and runs over all documents in order, so every entry is
  // summed in document order whatever the number of threads.
  const int vectors = stride / kern.lanes;
  const int parts = std::min(pool.size(), vectors);
  core::parallel_for(pool, static_cast<std::size_t>(parts), [&](std::size_t p, int) {
    const int v0 = static_cast<int>(p) * vectors / parts;
    const int v1 = (static_cast<int>(p) + 1) * vectors / parts;
    const int k0 = v0 * kern.lanes;
    const int len = (v1 - v0) * kern.lanes;
    for (std::size_t d = 0; d < docs.size(); ++d) {
      const float* eth = estep.exp_elog_theta.data() + d * S + k0;
      for (std::size_t e = docs.offsets[d]; e < docs.offsets[d + 1]; ++e) {
        float* row = sstats.data() + static_cast<std::size_t>(docs.rows[e]) * S + k0;
        kern.axpy(estep.weights[e], eth, row, len);
      }
    }
  });
}

double document_bound(const BatchEStep& estep, std::size_t d, int num_topics, double alpha) {
  const float* g = estep.gamma.data() + d * static_cast<std::size_t>(estep.stride);
  double sum = 0.0;
  for (int k = 0; k < num_topics; ++k) sum += g[k];
  const double psum = digamma(sum);
  double b = estep.log_norm[d];
  const double lga = std::lgamma(alpha);
  for (int k = 0; k < num_topics; ++k) {
    const double gk = g[k];
    b += (alpha - gk) * (digamma(gk) - psum) + std::lgamma(gk) - lga;
  }
  return b + std::lgamma(num_topics * alpha) - std::lgamma(sum);
}

double topic_bound(const Eigen::MatrixXd& lambda, const Eigen::VectorXd& topic_sum, double eta) {
  const Eigen::Index K = lambda.rows();
  const Eigen::Index W = lambda.cols();
  Eigen::VectorXd psum(K);
  for (Eigen::Index k = 0; k < K; ++k) psum(k) = digamma(topic_sum(k));
  const double lge = std::lgamma(eta);
  double b = 0.0;
  for (Eigen::Index w = 0; w < W; ++w) {
    for (Eigen::Index k = 0; k < K; ++k) {
      const double l = lambda(k, w);
      b += (eta - l) * (digamma(l) - psum(k)) + std::lgamma(l) - lge;
    }
  }
  for (Eigen::Index k = 0; k < K; ++k) {
    b += std::lgamma(static_cast<double>(W) * eta) - std::lgamma(topic_sum(k));
  }
  return b;
}

}  // namespace proprio::topics::detail
