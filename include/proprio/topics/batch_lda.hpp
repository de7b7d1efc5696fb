#pragma once
// Batch variational Bayes for LDA (Blei, Ng & Jordan 2003, with the smoothed topics of their
// sec 5.4; thesis B.1.2, eq B.16-B.20): every iteration runs the E-step on the whole corpus and
// sets lambda = eta + the sufficient statistics. For comparison with online LDA (thesis 6.3.2).

#include <cstdint>
#include <string>
#include <vector>

#include "proprio/topics/corpus.hpp"
#include "proprio/topics/estep_options.hpp"
#include "proprio/topics/lda_model.hpp"

namespace proprio::topics {

struct BatchLdaOptions {
  int num_topics = 100;
  double alpha = 0.0;        ///< 0 means 1/K
  double eta = 0.0;          ///< 0 means 1/K
  int max_iterations = 100;  ///< EM iterations (passes over the corpus)
  /// Stop when the variational bound's relative change falls below this.
  double tolerance = 1e-4;
  int threads = 1;
  std::uint64_t seed = 1;
  EStepOptions estep{100, 1e-3, GammaInit::kRandomGamma};

  void validate() const;
  [[nodiscard]] double resolved_alpha() const { return alpha > 0 ? alpha : 1.0 / num_topics; }
  [[nodiscard]] double resolved_eta() const { return eta > 0 ? eta : 1.0 / num_topics; }
};

struct BatchLdaSummary {
  int iterations = 0;
  bool converged = false;
  std::string stop_reason;
  std::vector<double> bound;  ///< the variational bound after each iteration's E-step, nats
  double seconds = 0.0;

  std::string message;  ///< one line: what happened (brief()'s first line)
  [[nodiscard]] std::string brief() const;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.seconds, {"seconds", "Training time (wall clock)"});
    v(self.iterations, {"iterations", "EM iterations run"});
    v(self.converged, {"converged", "Whether the bound's relative change fell below tolerance"});
    v(self.stop_reason, {"stop_reason", "Why EM stopped"});
    v(self.bound, {"bound", "The variational bound after each iteration's E-step, nats"});
  }
};

struct BatchLdaResult {
  LdaModel model;
  BatchLdaSummary summary;
};

BatchLdaResult train_batch_lda(const Corpus& corpus, const BatchLdaOptions& options);

}  // namespace proprio::topics
