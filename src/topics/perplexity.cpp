#include "proprio/topics/perplexity.hpp"

#include <chrono>
#include <cmath>

#include "engine.hpp"
#include "proprio/core/error.hpp"
#include "proprio/core/random.hpp"
#include "proprio/topics/inference.hpp"

namespace proprio::topics {

namespace {

void check_corpus(const LdaModel& model, const Corpus& corpus) {
  if (corpus.num_words() != model.num_words()) {
    throw Error("perplexity: the corpus has " + std::to_string(corpus.num_words()) +
                " words, the model " + std::to_string(model.num_words()));
  }
}

// A count of word w as the model reads it: times its weight (LdaModel::word_weights), so that a
// weighted model's perplexity is per token of the weighted documents it models.
std::int64_t weighted_count(const LdaModel& model, std::int32_t w, std::int32_t count) {
  const std::int64_t n = count;
  return model.word_weights.empty() ? n : n * model.word_weights[static_cast<std::size_t>(w)];
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

void PerplexityOptions::validate() const {
  estep.validate();
  if (threads < 1 || threads > 256) throw Error("perplexity: threads must be in [1, 256]");
}

std::string_view to_string(PerplexityMethod method) {
  return method == PerplexityMethod::kDocumentCompletion ? "document_completion"
                                                         : "variational_bound";
}

CompletionSplit split_for_completion(const Corpus& corpus, std::uint64_t seed) {
  CompletionSplit split{Corpus(corpus.num_words(), corpus.vocabulary()),
                        Corpus(corpus.num_words(), corpus.vocabulary())};
  std::vector<std::int32_t> tokens;
  for (std::size_t d = 0; d < corpus.num_documents(); ++d) {
    const auto doc = corpus.document(d);
    tokens.clear();
    for (std::size_t i = 0; i < doc.size(); ++i)
      tokens.insert(tokens.end(), doc.counts[i], doc.words[i]);
    const std::size_t n = tokens.size();
    const std::size_t half = n / 2;
    core::Rng rng(core::stream_seed(seed, 0x636f6d706c657465ULL, d));
    for (std::size_t i = 0; i < half; ++i) std::swap(tokens[i], tokens[i + rng.index(n - i)]);
    split.observed.add_tokens(std::span<const std::int32_t>(tokens.data(), half));
    split.scored.add_tokens(std::span<const std::int32_t>(tokens.data() + half, n - half));
  }
  return split;
}

PerplexityResult completion_perplexity(const LdaModel& model, const CompletionSplit& split,
                                       const PerplexityOptions& options) {
  options.validate();
  check_corpus(model, split.observed);
  check_corpus(model, split.scored);
  ensure(split.observed.num_documents() == split.scored.num_documents(),
         "perplexity: the two halves have different numbers of documents");
  if (split.scored.num_tokens() == 0) throw Error("perplexity: no tokens to score");
  const auto t0 = std::chrono::steady_clock::now();
  InferenceOptions io;
  io.estep = options.estep;
  io.threads = options.threads;
  const Eigen::MatrixXd theta = infer_topics(model, split.observed, io).theta();
  const Eigen::MatrixXd beta = model.topic_word();
  PerplexityResult r;
  r.method = PerplexityMethod::kDocumentCompletion;
  for (std::size_t d = 0; d < split.scored.num_documents(); ++d) {
    const auto doc = split.scored.document(d);
    if (doc.empty()) continue;
    ++r.documents;
    const auto th = theta.row(static_cast<Eigen::Index>(d));
    for (std::size_t i = 0; i < doc.size(); ++i) {
      const double p = th.dot(beta.col(doc.words[i]));
      const std::int64_t n = weighted_count(model, doc.words[i], doc.counts[i]);
      r.log_likelihood += static_cast<double>(n) * std::log(p);
      r.tokens += n;
    }
  }
  r.perplexity = std::exp(-r.log_likelihood / static_cast<double>(r.tokens));
  r.seconds = seconds_since(t0);
  return r;
}

PerplexityResult perplexity(const LdaModel& model, const Corpus& heldout,
                            const PerplexityOptions& options) {
  options.validate();
  check_corpus(model, heldout);
  if (heldout.num_tokens() == 0) throw Error("perplexity: the corpus has no tokens");
  if (options.method == PerplexityMethod::kDocumentCompletion) {
    return completion_perplexity(model, split_for_completion(heldout, options.split_seed), options);
  }
  const auto t0 = std::chrono::steady_clock::now();
  const auto& kern = detail::best_kernels();
  const int K = model.num_topics();
  core::ThreadPool pool(options.threads);
  const detail::CorpusEStep run =
      detail::corpus_estep(kern, pool, model, heldout, options.estep, options.split_seed);
  PerplexityResult r;
  r.method = PerplexityMethod::kVariationalBound;
  double bound = 0.0;
  for (std::size_t d = 0; d < run.docs.size(); ++d) {
    bound += detail::document_bound(run.estep, d, K, model.alpha);
    if (run.docs.offsets[d + 1] > run.docs.offsets[d]) ++r.documents;
  }
  bound += detail::topic_bound(model.lambda, run.topic_sum, model.eta);
  r.log_likelihood = bound;
  r.tokens = 0;
  for (std::size_t d = 0; d < heldout.num_documents(); ++d) {
    const auto doc = heldout.document(d);
    for (std::size_t i = 0; i < doc.size(); ++i) {
      r.tokens += weighted_count(model, doc.words[i], doc.counts[i]);
    }
  }
  r.perplexity = std::exp(-bound / static_cast<double>(r.tokens));
  r.seconds = seconds_since(t0);
  return r;
}

}  // namespace proprio::topics
