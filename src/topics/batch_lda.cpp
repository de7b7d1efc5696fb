#include "proprio/topics/batch_lda.hpp"

#include "proprio/core/fields.hpp"

#include <chrono>
#include <cmath>
#include <numeric>
#include <sstream>

#include "engine.hpp"
#include "proprio/core/error.hpp"

namespace proprio::topics {

void BatchLdaOptions::validate() const {
  if (num_topics < 1 || num_topics > 100000)
    throw Error("batch LDA: topics must be in [1, 100000]");
  if (alpha != 0 && !(std::isfinite(alpha) && alpha > 0))
    throw Error("batch LDA: alpha must be positive");
  if (eta != 0 && !(std::isfinite(eta) && eta > 0)) throw Error("batch LDA: eta must be positive");
  if (max_iterations < 1) throw Error("batch LDA: max_iterations must be at least 1");
  if (!(std::isfinite(tolerance) && tolerance >= 0))
    throw Error("batch LDA: tolerance must be >= 0");
  if (threads < 1 || threads > 256) throw Error("batch LDA: threads must be in [1, 256]");
  estep.validate();
}

std::string BatchLdaSummary::brief() const {
  std::ostringstream s;
  s << iterations << " iterations, " << stop_reason << ", bound "
    << (bound.empty() ? 0.0 : bound.back()) << ", " << seconds << " s";
  return s.str();
}

BatchLdaResult train_batch_lda(const Corpus& corpus, const BatchLdaOptions& options) {
  options.validate();
  if (corpus.num_documents() == 0) throw Error("batch LDA: the corpus is empty");
  if (corpus.num_words() < 1) throw Error("batch LDA: the vocabulary is empty");
  const auto t0 = std::chrono::steady_clock::now();
  const auto& kern = detail::best_kernels();
  const int K = options.num_topics;
  const int W = corpus.num_words();
  const int stride = detail::padded(K, kern.lanes);
  const auto S = static_cast<std::size_t>(stride);
  core::ThreadPool pool(options.threads);

  BatchLdaResult result;
  LdaModel& model = result.model;
  model.alpha = options.resolved_alpha();
  model.eta = options.resolved_eta();
  model.tau0 = 0.0;
  model.kappa = 1.0;
  model.total_documents = static_cast<std::int64_t>(corpus.num_documents());
  model.vocabulary = corpus.vocabulary();
  model.lambda = detail::initial_lambda(K, W, options.seed, pool);

  std::vector<std::int32_t> all(static_cast<std::size_t>(W));
  std::iota(all.begin(), all.end(), 0);
  detail::FloatBuffer beta;
  detail::BatchDocs docs;
  detail::BatchEStep estep;
  detail::FloatBuffer sstats;
  BatchLdaSummary& s = result.summary;
  s.stop_reason = "reached max_iterations";
  for (int it = 0; it < options.max_iterations; ++it) {
    const Eigen::VectorXd topic_sum = detail::topic_sums(model.lambda, pool);
    detail::exp_elog_beta(kern, model.lambda, topic_sum, all, stride, pool, beta);
    detail::corpus_docs(corpus, options.seed, static_cast<std::uint64_t>(it), docs);
    detail::run_estep(kern, pool, docs, beta.data(), K, stride, model.alpha, options.estep, estep);
    double bound = detail::topic_bound(model.lambda, topic_sum, model.eta);
    for (std::size_t d = 0; d < docs.size(); ++d) {
      bound += detail::document_bound(estep, d, K, model.alpha);
    }
    detail::sufficient_statistics(kern, pool, docs, estep, static_cast<std::size_t>(W), sstats);
    // M-step (eq B.20): lambda = eta + sum_d n_dw phi_dwk.
    for (int w = 0; w < W; ++w) {
      const float* st = sstats.data() + static_cast<std::size_t>(w) * S;
      const float* e = beta.data() + static_cast<std::size_t>(w) * S;
      for (int k = 0; k < K; ++k) {
        model.lambda(k, w) = model.eta + static_cast<double>(st[k]) * static_cast<double>(e[k]);
      }
    }
    ++model.updates;
    s.iterations = it + 1;
    s.bound.push_back(bound);
    if (s.bound.size() >= 2) {
      const double prev = s.bound[s.bound.size() - 2];
      if (std::abs(bound - prev) <= options.tolerance * std::abs(prev)) {
        s.converged = true;
        s.stop_reason = "the bound's relative change fell below the tolerance";
        break;
      }
    }
  }
  s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  result.summary.message = core::first_line(result.summary.brief());
  return result;
}

}  // namespace proprio::topics
