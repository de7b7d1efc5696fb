#pragma once
// Corpora drawn from LDA's generative process (thesis eq B.10-B.12) with known topics, for
// checking that training recovers them.

#include <Eigen/Core>
#include <cstdint>

#include "proprio/topics/corpus.hpp"

namespace proprio::topics {

struct SyntheticCorpusOptions {
  int num_topics = 10;
  int num_words = 500;
  int num_documents = 1000;
  double mean_length = 100.0;  ///< document lengths ~ Poisson(mean_length), at least 1
  double alpha = 0.1;          ///< theta_d ~ Dir(alpha)
  double eta = 0.05;           ///< beta_k ~ Dir(eta)
  std::uint64_t seed = 1;

  void validate() const;
};

struct SyntheticCorpus {
  Corpus corpus;
  Eigen::MatrixXd topics;  ///< K x W, rows sum to 1: the beta_k that generated the words
  Eigen::MatrixXd theta;   ///< D x K, rows sum to 1
};

/// Draws theta_d ~ Dir(alpha), then each token's topic z ~ theta_d and word w ~ beta_z.
SyntheticCorpus make_synthetic_corpus(const SyntheticCorpusOptions& options);

}  // namespace proprio::topics
