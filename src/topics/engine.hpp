#pragma once
// The shared machinery of training, inference and scoring: exp(E[log beta]) for a set of words,
// the E-step over a set of documents on a thread pool, and the sufficient statistics, each
// summed in a fixed order so that the result does not depend on the number of threads.

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <new>
#include <span>
#include <vector>

#include "kernels.hpp"
#include "proprio/core/parallel.hpp"
#include "proprio/core/thread_pool.hpp"
#include "proprio/topics/corpus.hpp"
#include "proprio/topics/estep_options.hpp"
#include "proprio/topics/lda_model.hpp"
#include "special_functions.hpp"

namespace proprio::topics::detail {

/// Cache-line-aligned storage for the vector kernels.
template <typename T>
struct AlignedAllocator {
  using value_type = T;
  AlignedAllocator() = default;
  template <typename U>
  explicit AlignedAllocator(const AlignedAllocator<U>&) {}
  T* allocate(std::size_t n) {
    return static_cast<T*>(::operator new(n * sizeof(T), std::align_val_t(64)));
  }
  void deallocate(T* p, std::size_t) { ::operator delete(p, std::align_val_t(64)); }
  bool operator==(const AlignedAllocator&) const { return true; }
};
using FloatBuffer = std::vector<float, AlignedAllocator<float>>;

/// Row sums of lambda (sum over words for each topic), summed in fixed blocks of words.
Eigen::VectorXd topic_sums(const Eigen::MatrixXd& lambda, core::ThreadPool& pool);

/// exp(E[log beta_kw]) (eq B.19) for the listed words, one row of `stride` floats per word.
void exp_elog_beta(const Kernels& kern, const Eigen::MatrixXd& lambda,
                   const Eigen::VectorXd& topic_sum, std::span<const std::int32_t> words,
                   int stride, core::ThreadPool& pool, FloatBuffer& out);

/// The E-step's view of a set of documents: for each document its rows into the beta cache and
/// its counts, concatenated.
struct BatchDocs {
  std::vector<std::size_t> offsets{0};  ///< documents + 1
  std::vector<std::int32_t> rows;       ///< row in the beta cache of each entry
  FloatBuffer counts;                   ///< count of each entry
  std::vector<std::uint64_t> keys;      ///< per document, seeds its random gamma

  [[nodiscard]] std::size_t size() const { return offsets.size() - 1; }
  void clear() {
    offsets.assign(1, 0);
    rows.clear();
    counts.clear();
    keys.clear();
  }
};

/// Fills `docs` with every document of `corpus`, rows being word ids; random-gamma keys from
/// (seed, update, document index). Non-empty `weights` (one per word, a model's
/// LdaModel::word_weights) count each occurrence of word w weights[w] times, as weighted_by does,
/// without a copy of the corpus; the float counts are the same to the bit (both exact below 2^24).
void corpus_docs(const Corpus& corpus, std::uint64_t seed, std::uint64_t update, BatchDocs& docs,
                 std::span<const std::int32_t> weights = {});

/// What the E-step leaves per document.
struct BatchEStep {
  int stride = 0;
  FloatBuffer gamma;           ///< documents x stride
  FloatBuffer exp_elog_theta;  ///< documents x stride
  FloatBuffer weights;         ///< per entry
  std::vector<int> iterations;
  std::vector<char> converged;
  std::vector<double> log_norm;
};

/// Runs the E-step (eq B.16-B.18) on every document of `docs` against the beta cache.
void run_estep(const Kernels& kern, core::ThreadPool& pool, const BatchDocs& docs,
               const float* beta, int num_topics, int stride, double alpha,
               const EStepOptions& options, BatchEStep& out);

/// The E-step of a fixed model over a whole corpus (inference and the variational bound): the
/// model's topic sums, the beta cache of every word, the documents and what the E-step left.
struct CorpusEStep {
  int stride = 0;
  Eigen::VectorXd topic_sum;
  BatchDocs docs;
  BatchEStep estep;
};

/// Runs the E-step of `model` on every document of `corpus` (random-gamma keys from `seed`).
CorpusEStep corpus_estep(const Kernels& kern, core::ThreadPool& pool, const LdaModel& model,
                         const Corpus& corpus, const EStepOptions& options, std::uint64_t seed);

/// sstats[r] = sum over documents and their entries on row r of weight * exp(E[log theta]),
/// in document order; `rows` rows of `stride` floats.
void sufficient_statistics(const Kernels& kern, core::ThreadPool& pool, const BatchDocs& docs,
                           const BatchEStep& estep, std::size_t rows, FloatBuffer& sstats);

/// The document part of the variational bound (Hoffman et al. 2010, eq 3 with the terms of
/// one document): sum_j n_j log phinorm_j + sum_k (alpha - gamma_k) E[log theta_k]
/// + lgamma(gamma_k) - lgamma(alpha) + lgamma(K alpha) - lgamma(sum_k gamma_k).
double document_bound(const BatchEStep& estep, std::size_t d, int num_topics, double alpha);

/// The topic part of the bound: sum_k [ sum_w (eta - lambda_kw) E[log beta_kw] + lgamma(lambda_kw)
/// - lgamma(eta) ] + lgamma(W eta) - lgamma(sum_w lambda_kw).
double topic_bound(const Eigen::MatrixXd& lambda, const Eigen::VectorXd& topic_sum, double eta);

/// A stream of Gamma(100, 1/100) variates for the random gamma start, keyed by document (the key
/// is core::stream_seed(seed, update, document)).
void random_gamma(std::uint64_t key, int n, float* out);

/// K x W lambda drawn from Gamma(100, 1/100), the start of Hoffman's code, scikit-learn and
/// gensim; one seeded stream per word, so it does not depend on the thread count.
Eigen::MatrixXd initial_lambda(int num_topics, int num_words, std::uint64_t seed,
                               core::ThreadPool& pool);

/// Rounds K up to a multiple of the kernel's lanes.
inline int padded(int num_topics, int lanes) { return (num_topics + lanes - 1) / lanes * lanes; }

}  // namespace proprio::topics::detail
