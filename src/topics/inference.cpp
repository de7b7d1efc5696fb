#include "proprio/topics/inference.hpp"

#include "proprio/core/fields.hpp"

#include <chrono>
#include <sstream>

#include "engine.hpp"
#include "proprio/core/error.hpp"

namespace proprio::topics {

void InferenceOptions::validate() const {
  estep.validate();
  if (threads < 1 || threads > 256) throw Error("inference: threads must be in [1, 256]");
}

std::string InferenceSummary::brief() const {
  std::ostringstream s;
  s << documents << " documents (" << empty_documents << " empty), mean E-step iterations "
    << mean_iterations << ", " << capped << " hit the limit, " << seconds << " s";
  return s.str();
}

Eigen::MatrixXd InferenceResult::theta() const {
  Eigen::MatrixXd t = gamma;
  for (Eigen::Index d = 0; d < t.rows(); ++d) t.row(d) /= t.row(d).sum();
  return t;
}

std::vector<int> InferenceResult::classify() const {
  std::vector<int> c(static_cast<std::size_t>(gamma.rows()), -1);
  for (Eigen::Index d = 0; d < gamma.rows(); ++d) {
    if (tokens[static_cast<std::size_t>(d)] == 0) continue;  // the prior alone: no class
    Eigen::Index k = 0;
    gamma.row(d).maxCoeff(&k);
    c[static_cast<std::size_t>(d)] = static_cast<int>(k);
  }
  return c;
}

InferenceResult infer_topics(const LdaModel& model, const Corpus& corpus,
                             const InferenceOptions& options) {
  options.validate();
  if (corpus.num_words() != model.num_words()) {
    throw Error("inference: the corpus has " + std::to_string(corpus.num_words()) +
                " words, the model " + std::to_string(model.num_words()));
  }
  const auto t0 = std::chrono::steady_clock::now();
  const auto& kern = detail::best_kernels();
  const int K = model.num_topics();
  core::ThreadPool pool(options.threads);
  // corpus_estep weighs the documents by the model's word weights, if it has them.
  const detail::CorpusEStep run =
      detail::corpus_estep(kern, pool, model, corpus, options.estep, options.seed);
  const detail::BatchEStep& estep = run.estep;
  const int stride = run.stride;

  InferenceResult r;
  const auto D = static_cast<Eigen::Index>(corpus.num_documents());
  r.gamma.resize(D, K);
  r.tokens.resize(static_cast<std::size_t>(D));
  std::int64_t iterations = 0;
  for (Eigen::Index d = 0; d < D; ++d) {
    const float* g =
        estep.gamma.data() + static_cast<std::size_t>(d) * static_cast<std::size_t>(stride);
    for (int k = 0; k < K; ++k) r.gamma(d, k) = g[k];
    r.tokens[static_cast<std::size_t>(d)] = corpus.document(static_cast<std::size_t>(d)).tokens();
    if (r.tokens[static_cast<std::size_t>(d)] == 0) {
      ++r.summary.empty_documents;
    } else {
      iterations += estep.iterations[static_cast<std::size_t>(d)];
      r.summary.capped += estep.converged[static_cast<std::size_t>(d)] ? 0 : 1;
    }
  }
  r.summary.documents = D;
  const std::int64_t nonempty = D - r.summary.empty_documents;
  r.summary.mean_iterations = nonempty > 0 ? static_cast<double>(iterations) / nonempty : 0.0;
  r.summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.summary.message = core::first_line(r.summary.brief());
  return r;
}

}  // namespace proprio::topics
