#pragma once
// A trained LDA model (thesis B.1.2; Blei, Ng & Jordan 2003; Hoffman, Blei & Bach 2010): the
// variational Dirichlet parameters lambda of the K topics over the W words and the priors. The
// model is a constant value; training and inference keep their scratch space elsewhere.

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "proprio/topics/corpus.hpp"

namespace proprio::topics {

/// The largest alpha or eta a model or a training run accepts. Far above any useful prior
/// (1/K is the default), and low enough that the E-step's sums stay finite.
inline constexpr double kMaxLdaPrior = 1e6;
/// The largest lambda entry a model may hold; a sum of W of them stays finite.
inline constexpr double kMaxLdaLambda = 1e100;

struct LdaModel {
  /// K x W variational parameters of q(beta_k) = Dir(lambda_k) (eq B.20, B.23-B.24). Stored
  /// column-major, so the K values of one word are contiguous.
  Eigen::MatrixXd lambda;
  double alpha = 0.0;  ///< symmetric Dirichlet prior on each document's topic proportions theta
  double eta = 0.0;    ///< symmetric Dirichlet prior on each topic's word distribution beta
  double tau0 = 1.0;   ///< learning-rate offset of online training, rho_t = (tau0 + t)^-kappa
  double kappa = 0.7;  ///< learning-rate decay of online training
  std::int64_t updates = 0;             ///< mini-batch updates applied so far (t)
  std::int64_t total_documents = 0;     ///< D, the corpus size that scales a mini-batch (eq B.23)
  std::vector<std::string> vocabulary;  ///< empty, or one word per column of lambda
  /// Empty (every word counts once), or W weights in [1, kMaxWordWeight]: each occurrence of
  /// word w in a document counts word_weights[w] times. The model was trained on documents so
  /// weighted (the trainer weighs them, topics::weighted_by, and records the weights here), and
  /// infer_topics weighs the documents it is given the same way, so that a reader of the model
  /// never has to know: proprio's colour words weigh more than the SIFT words (`recognize train
  /// --colour-weight`, `learn --colour-weight`). Saved from format version 2 on.
  std::vector<std::int32_t> word_weights;

  [[nodiscard]] int num_topics() const { return static_cast<int>(lambda.rows()); }
  [[nodiscard]] int num_words() const { return static_cast<int>(lambda.cols()); }

  /// The posterior mean of beta: K x W, each row lambda_k / sum_w lambda_kw (sums to 1).
  [[nodiscard]] Eigen::MatrixXd topic_word() const;

  /// The `n` most probable words of topic k, most probable first.
  [[nodiscard]] std::vector<int> top_words(int k, int n) const;

  /// Throws Error when the model is not usable: K or W zero, alpha or eta outside
  /// (0, kMaxLdaPrior], lambda outside (0, kMaxLdaLambda] anywhere, or a vocabulary of the wrong
  /// size. Models that would give NaN are refused here, when read.
  void validate() const;

  bool operator==(const LdaModel& other) const;
};

}  // namespace proprio::topics
