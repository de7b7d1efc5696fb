#pragma once
// Topic proportions of new documents by the variational E-step (eq B.16-B.18) with the topics
// held fixed, and classification by the most probable topic (thesis 6.1.4).

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "proprio/topics/corpus.hpp"
#include "proprio/topics/estep_options.hpp"
#include "proprio/topics/lda_model.hpp"

namespace proprio::topics {

struct InferenceOptions {
  EStepOptions estep;  ///< gamma starts at 1 by default
  int threads = 1;  ///< documents are shared among this many threads; results do not depend on it
  std::uint64_t seed = 1;  ///< only used with GammaInit::kRandomGamma

  void validate() const;
};

struct InferenceSummary {
  std::int64_t documents = 0;
  std::int64_t empty_documents = 0;  ///< their gamma is alpha: theta uniform, class -1
  double mean_iterations = 0.0;      ///< E-step iterations per non-empty document
  std::int64_t capped = 0;           ///< documents that reached max_iterations before converging
  double seconds = 0.0;

  std::string message;  ///< one line: what happened (brief()'s first line)
  [[nodiscard]] std::string brief() const;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.documents, {"documents", "Documents inferred"});
    v(self.empty_documents, {"empty_documents", "Documents without tokens (theta uniform)"});
    v(self.mean_iterations, {"mean_estep_iterations", "E-step iterations per non-empty document"});
    v(self.capped, {"estep_capped", "Documents that reached max_iterations"});
    v(self.seconds, {"seconds", "Inference time (wall clock)"});
  }
};

struct InferenceResult {
  /// D x K variational Dirichlet parameters of each document's theta (eq B.17).
  Eigen::MatrixXd gamma;
  std::vector<std::int64_t> tokens;  ///< tokens of each document
  InferenceSummary summary;

  /// D x K expected topic proportions E[theta_d] = gamma_d / sum_k gamma_dk (rows sum to 1).
  [[nodiscard]] Eigen::MatrixXd theta() const;
  /// Class of each document: argmax_k gamma_dk (thesis 6.1.4); -1 for an empty document,
  /// about which the model knows nothing.
  [[nodiscard]] std::vector<int> classify() const;
};

/// E-step for every document of `corpus` (which must have the model's W words).
/// Throws Error when the corpus and model disagree on W.
InferenceResult infer_topics(const LdaModel& model, const Corpus& corpus,
                             const InferenceOptions& options = {});

}  // namespace proprio::topics
