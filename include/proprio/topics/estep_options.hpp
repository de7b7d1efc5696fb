#pragma once
// Options of the per-document variational E-step (eq B.16-B.18), shared by training, inference
// and perplexity. The defaults are those of scikit-learn and gensim.

#include <cstdint>

namespace proprio::topics {

/// How the document's gamma starts.
enum class GammaInit {
  kOnes,         ///< gamma = 1 (scikit-learn's transform, gensim's inference of new documents)
  kRandomGamma,  ///< gamma ~ Gamma(100, 1/100) per topic (scikit-learn's and gensim's training)
};

struct EStepOptions {
  /// At most this many updates of (phi, gamma) per document.
  int max_iterations = 100;
  /// Stop when the mean absolute change of gamma over the topics falls below this.
  double tolerance = 1e-3;
  GammaInit init = GammaInit::kOnes;

  /// Throws Error when max_iterations < 1 or tolerance is negative or not finite.
  void validate() const;
};

}  // namespace proprio::topics
