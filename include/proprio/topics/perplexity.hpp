#pragma once
// Held-out perplexity of an LDA model, the convergence signal of thesis Fig 6-7.
//
// Document completion (the default; Wallach et al. 2009, Hoffman et al. 2010 sec 4): each
// held-out document's tokens are split at random (seeded) into two halves; theta is inferred from
// the first half by the E-step, and the second half is scored under the posterior means,
// p(w) = sum_k E[theta_k] E[beta_kw]. Perplexity = exp(-sum log p(w) / scored tokens).
// The variational bound (on request): perplexity = exp(-bound / tokens), the bound of all the
// documents' tokens and the topics (Hoffman et al. 2010 eq 3; scikit-learn's perplexity()).
// Both work on any lambda, so models trained elsewhere are scored the same way. A model with
// word weights (LdaModel::word_weights) models weighted documents, so it is scored on them: each
// token of word w counts word_weights[w] times, in theta's half, the scored half, the bound and
// `tokens` alike (the split itself is of the documents' own tokens).

#include <cstdint>
#include <string>

#include "proprio/topics/corpus.hpp"
#include "proprio/topics/estep_options.hpp"
#include "proprio/topics/lda_model.hpp"

namespace proprio::topics {

enum class PerplexityMethod { kDocumentCompletion, kVariationalBound };

struct PerplexityOptions {
  PerplexityMethod method = PerplexityMethod::kDocumentCompletion;
  EStepOptions estep;  ///< gamma starts at 1
  int threads = 1;
  std::uint64_t split_seed = 1;  ///< which tokens of each document are observed

  void validate() const;
};

struct PerplexityResult {
  double perplexity = 0.0;
  /// Sum of log p over the scored tokens (completion) or the bound (variational bound), nats.
  double log_likelihood = 0.0;
  std::int64_t tokens = 0;     ///< tokens scored (weighted, for a model with word weights)
  std::int64_t documents = 0;  ///< documents with at least one scored token
  PerplexityMethod method = PerplexityMethod::kDocumentCompletion;
  double seconds = 0.0;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v);
};

/// The two halves of each document for document completion.
struct CompletionSplit {
  Corpus observed;  ///< floor(n/2) of each document's n tokens: theta is inferred from these
  Corpus scored;    ///< the other ceil(n/2): these are scored
};

/// Splits every document's tokens at random (seeded per document, so a document's split does not
/// depend on the others).
CompletionSplit split_for_completion(const Corpus& corpus, std::uint64_t seed);

/// Document-completion perplexity on a prepared split.
PerplexityResult completion_perplexity(const LdaModel& model, const CompletionSplit& split,
                                       const PerplexityOptions& options = {});

/// Held-out perplexity by options.method. Throws Error when the corpus has no tokens or its
/// number of words differs from the model's.
PerplexityResult perplexity(const LdaModel& model, const Corpus& heldout,
                            const PerplexityOptions& options = {});

std::string_view to_string(PerplexityMethod method);

template <class Self, class Visitor>
void PerplexityResult::describe(Self& self, Visitor& v) {
  v(std::string(to_string(self.method)), {"method", "document_completion or bound"});
  v(self.perplexity, {"perplexity", "exp(-log likelihood / tokens)"});
  v(self.log_likelihood, {"log_likelihood", "Sum of log p over the scored tokens, nats"});
  v(self.tokens, {"tokens", "Tokens scored, each counted by its word's weight in the model"});
  v(self.documents, {"documents", "Documents with at least one scored token"});
  v(self.seconds, {"seconds", "Scoring time (wall clock)"});
}

}  // namespace proprio::topics
