#include "proprio/topics/online_lda.hpp"
#include "proprio/core/random.hpp"

#include <algorithm>
#include <cassert>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <numeric>
#include <optional>
#include <span>
#include <sstream>
#include <string_view>
#include <tuple>

#include "engine.hpp"
#include "proprio/core/binary_file.hpp"
#include "proprio/core/cpu_clock.hpp"
#include "proprio/core/error.hpp"
#include "proprio/core/fields.hpp"
#include "proprio/core/text.hpp"
#include "proprio/topics/lda_model_io.hpp"

namespace proprio::topics {

namespace {

using Clock = std::chrono::steady_clock;
using core::process_cpu_seconds;

double since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// Throws Error unless the held-out corpus (when there is one) has the training corpus's words.
void check_heldout_words(const Corpus* heldout, std::int32_t words) {
  if (heldout != nullptr && heldout->num_words() != words) {
    throw Error("online LDA: the held-out corpus has " + std::to_string(heldout->num_words()) +
                " words, the training corpus " + std::to_string(words));
  }
}

// The held-out perplexity trace (Fig 6-7) of one training run: the document-completion split is
// made once; each evaluation appends a point to the summary and counts its time.
class HeldoutTrace {
 public:
  HeldoutTrace(const Corpus* heldout, const OnlineLdaOptions& options)
      : heldout_(heldout),
        eval_(options.evaluation),
        active_(heldout != nullptr && heldout->num_tokens() > 0) {
    eval_.threads = options.threads;
    if (active_ && eval_.method == PerplexityMethod::kDocumentCompletion) {
      split_ = split_for_completion(*heldout, eval_.split_seed);
    }
  }
  [[nodiscard]] bool active() const { return active_; }
  void evaluate(const LdaModel& model, OnlineLdaSummary& s) const {
    const auto t0 = Clock::now();
    const PerplexityResult p = eval_.method == PerplexityMethod::kDocumentCompletion
                                   ? completion_perplexity(model, split_, eval_)
                                   : perplexity(model, *heldout_, eval_);
    s.trace.push_back({model.updates, s.documents, p.perplexity});
    s.evaluation_seconds += since(t0);
  }

 private:
  const Corpus* heldout_;
  PerplexityOptions eval_;
  bool active_;
  CompletionSplit split_;
};

void check_positive_finite(double v, const char* name) {
  if (!(std::isfinite(v) && v > 0)) {
    throw Error(std::string("online LDA: ") + name + " must be positive and finite, not " +
                std::to_string(v));
  }
}

}  // namespace

void OnlineLdaOptions::validate() const {
  if (num_topics < 1) throw Error("online LDA: the number of topics must be at least 1");
  if (num_topics > 100000) throw Error("online LDA: more than 100000 topics");
  if (batch_size < 1) throw Error("online LDA: the batch size must be at least 1");
  if (!(std::isfinite(tau0) && tau0 >= 0)) throw Error("online LDA: tau0 must be >= 0");
  if (!(kappa > 0.5 && kappa <= 1.0)) {
    throw Error("online LDA: kappa must be in (0.5, 1] for convergence, not " +
                std::to_string(kappa));
  }
  if (alpha != 0) check_positive_finite(alpha, "alpha");
  if (eta != 0) check_positive_finite(eta, "eta");
  if (alpha > kMaxLdaPrior || eta > kMaxLdaPrior) {
    throw Error("online LDA: alpha and eta must be at most " + core::num(kMaxLdaPrior) +
                " (larger priors overflow into NaN)");
  }
  if (passes < 1) throw Error("online LDA: passes must be at least 1");
  if (threads < 1 || threads > 256) throw Error("online LDA: threads must be in [1, 256]");
  if (total_documents < 0) throw Error("online LDA: total_documents must be >= 0");
  if (evaluate_every < 0) throw Error("online LDA: evaluate_every must be >= 0");
  estep.validate();
  evaluation.validate();
}

std::string OnlineLdaSummary::brief() const {
  std::ostringstream s;
  s << updates << " mini-batch updates over " << passes << " passes, " << documents
    << " documents (" << tokens << " tokens) in " << seconds << " s ("
    << static_cast<long long>(documents_per_second()) << " docs/s, "
    << static_cast<long long>(tokens_per_second()) << " tokens/s; " << threads << " thread(s), "
    << kernel << " kernel); mean E-step iterations " << mean_estep_iterations;
  if (capped > 0) s << ", " << capped << " hit the limit";
  if (!trace.empty()) s << "; held-out perplexity " << trace.back().perplexity;
  return s.str();
}

struct OnlineLda::Impl {
  OnlineLdaOptions options;
  LdaModel model;  // split by topic: lambda is K x W only after gather_topics on this rank
  int num_topics;
  std::int32_t num_words;
  Eigen::VectorXd topic_sum;
  const detail::Kernels* kern;
  int stride;
  core::ThreadPool pool;
  std::vector<std::int32_t> row_of_word;
  std::vector<std::int32_t> batch_words;
  detail::BatchDocs docs;
  detail::FloatBuffer beta;
  detail::BatchEStep estep;
  detail::FloatBuffer sstats;
  // The by-topic split (distribute_by_topic): this rank's rows [row0, row1) of lambda and their
  // sums over words; first_row[q] is rank q's first row (ranks + 1 entries).
  bool by_topic = false;
  int row0 = 0;
  int row1 = 0;
  std::vector<int> first_row;
  Eigen::MatrixXd own;
  Eigen::VectorXd own_sum;
  // The E-step's dealing to ranks: by cost (options.mpi.dealing) with the iterations each
  // document took in the previous pass, or d mod P.
  bool balance = options.mpi.dealing == MpiLdaDealing::kByCost;
  std::vector<std::uint16_t> last_iterations;
  OnlineLda::PhaseTimes times;
  // The data-parallel update's exchange (options.mpi.exchange) and its buffers, kept between
  // updates. `ahead`: a batch's documents from every rank (32-bit: per document its size, word ids
  // and counts), rank q's from starts[q] to starts[q + 1]; with the lean exchange they come with
  // the previous update's E-step output, for the range [begin, end) it predicted.
  bool lean = options.mpi.exchange == MpiLdaExchange::kLean;
  std::size_t widest = 0;  // the largest batch so far: the predicted next batch's size
  struct Ahead {
    std::vector<std::int32_t> words;
    std::vector<std::size_t> starts{0};
    std::size_t begin = 0;
    std::size_t end = 0;
    bool valid = false;
    void set(const std::vector<std::byte>& bytes, const std::vector<std::size_t>& sizes) {
      words.resize(bytes.size() / sizeof(std::int32_t));
      if (!bytes.empty()) std::memcpy(words.data(), bytes.data(), bytes.size());
      starts.assign(1, 0);
      for (const auto s : sizes) starts.push_back(starts.back() + s / sizeof(std::int32_t));
    }
  } ahead;
  // The byte counts every rank announced of its documents of the batch [begin, end) (lean).
  struct Announced {
    std::vector<std::size_t> bytes;
    std::size_t begin = 0;
    std::size_t end = 0;
    bool valid = false;
  } announced;
  std::vector<std::size_t> doc_at;  // each batch document's start in ahead.words
  detail::BatchDocs mine;           // this rank's documents of the batch
  detail::BatchEStep own_estep;     // their E-step
  detail::FloatBuffer beta_part;    // exp E[log beta] of the batch's words on this rank's rows
  std::vector<float> beta_rows;     // every rank's, gathered
  std::vector<std::byte> out;       // this rank's E-step output (and next documents)
  std::vector<std::byte> gathered;  // every rank's

  Impl(const OnlineLdaOptions& o, LdaModel m, int K, std::int32_t W)
      : options(o),
        model(std::move(m)),
        num_topics(K),
        num_words(W),
        kern(&detail::best_kernels()),
        stride(detail::padded(K, kern->lanes)),
        pool(o.threads),
        row_of_word(static_cast<std::size_t>(W), -1) {
    topic_sum = detail::topic_sums(model.lambda, pool);
  }
};

namespace {

// The checked options and the model's scalars, for both constructors; lambda is theirs to draw.
LdaModel model_without_topics(const OnlineLdaOptions& options, std::int32_t num_words,
                              std::int64_t total_documents, std::vector<std::string> vocabulary) {
  options.validate();
  if (num_words < 1) throw Error("online LDA: the vocabulary is empty");
  if (total_documents < 1) throw Error("online LDA: total_documents must be at least 1");
  LdaModel m;
  m.alpha = options.resolved_alpha();
  m.eta = options.resolved_eta();
  m.tau0 = options.tau0;
  m.kappa = options.kappa;
  m.total_documents = total_documents;
  m.vocabulary = std::move(vocabulary);
  return m;
}

}  // namespace

OnlineLda::OnlineLda(const OnlineLdaOptions& options, std::int32_t num_words,
                     std::int64_t total_documents, std::vector<std::string> vocabulary) {
  LdaModel m = model_without_topics(options, num_words, total_documents, std::move(vocabulary));
  const int K = options.num_topics;
  {
    core::ThreadPool pool(options.threads);
    m.lambda = detail::initial_lambda(K, num_words, options.seed, pool);
  }
  m.validate();
  impl_ = std::make_unique<Impl>(options, std::move(m), K, num_words);
}

namespace {

// The rows [k0, k1) of detail::initial_lambda(K, W, seed): the same random stream per word, the
// other rows drawn and dropped, so that a rank never holds K x W.
Eigen::MatrixXd initial_lambda_rows(int K, std::int32_t W, std::uint64_t seed, int k0, int k1,
                                    core::ThreadPool& pool) {
  Eigen::MatrixXd rows(k1 - k0, W);
  if (k1 <= k0) return rows;
  std::vector<float> tmp(static_cast<std::size_t>(K) * static_cast<std::size_t>(pool.size()));
  core::parallel_for(pool, static_cast<std::size_t>(W), [&](std::size_t w, int t) {
    float* g = tmp.data() + static_cast<std::size_t>(t) * static_cast<std::size_t>(K);
    detail::random_gamma(core::stream_seed(seed, ~0ULL, w), K, g);
    for (int k = k0; k < k1; ++k) {
      rows(k - k0, static_cast<Eigen::Index>(w)) = g[static_cast<std::size_t>(k)];
    }
  });
  return rows;
}

}  // namespace

OnlineLda::OnlineLda(const OnlineLdaOptions& options, std::int32_t num_words,
                     std::int64_t total_documents, std::vector<std::string> vocabulary,
                     core::Communicator& comm) {
  LdaModel m = model_without_topics(options, num_words, total_documents, std::move(vocabulary));
  const int K = options.num_topics;
  impl_ = std::make_unique<Impl>(options, std::move(m), K, num_words);
  Impl& s = *impl_;
  const int P = comm.size();
  s.first_row.resize(static_cast<std::size_t>(P) + 1);
  for (int q = 0; q <= P; ++q) {
    s.first_row[static_cast<std::size_t>(q)] = q < P ? mpi_topic_rows(K, P, q).first : K;
  }
  std::tie(s.row0, s.row1) = mpi_topic_rows(K, P, comm.rank());
  s.own = initial_lambda_rows(K, num_words, options.seed, s.row0, s.row1, s.pool);
  s.own_sum = detail::topic_sums(s.own, s.pool);
  s.by_topic = true;
}

OnlineLda::OnlineLda(LdaModel model, const OnlineLdaOptions& options) {
  model.validate();
  OnlineLdaOptions o = options;
  o.num_topics = model.num_topics();
  o.alpha = model.alpha;
  o.eta = model.eta;
  o.tau0 = model.tau0;
  o.kappa = model.kappa;
  o.validate();
  const int K = model.num_topics();
  const std::int32_t W = model.num_words();
  impl_ = std::make_unique<Impl>(o, std::move(model), K, W);
}

OnlineLda::OnlineLda(OnlineLda&&) noexcept = default;
OnlineLda& OnlineLda::operator=(OnlineLda&&) noexcept = default;
OnlineLda::~OnlineLda() = default;

const LdaModel& OnlineLda::model() const { return impl_->model; }
const char* OnlineLda::kernel() const { return impl_->kern->name; }
OnlineLda::PhaseTimes OnlineLda::phase_times() const { return impl_->times; }

namespace {

// Adds the processor time since the last lap to a phase.
class Lap {
 public:
  Lap() : t_(process_cpu_seconds()) {}
  void operator()(double& slot) {
    const double now = process_cpu_seconds();
    slot += now - t_;
    t_ = now;
  }

 private:
  double t_;
};

}  // namespace

std::pair<int, int> mpi_topic_rows(int num_topics, int ranks, int rank) {
  assert(ranks >= 1 && rank >= 0 && rank < ranks && num_topics >= 0);
  const auto at = [&](int r) {
    return static_cast<int>(static_cast<std::int64_t>(r) * num_topics / ranks);
  };
  return {at(rank), at(rank + 1)};
}

void OnlineLda::distribute_by_topic(core::Communicator& comm) {
  Impl& m = *impl_;
  const int K = m.num_topics;
  const int P = comm.size();
  ensure(!m.by_topic, "online LDA: already split by topic");
  m.first_row.resize(static_cast<std::size_t>(P) + 1);
  for (int q = 0; q <= P; ++q) {
    m.first_row[static_cast<std::size_t>(q)] = q < P ? mpi_topic_rows(K, P, q).first : K;
  }
  std::tie(m.row0, m.row1) = mpi_topic_rows(K, P, comm.rank());
  m.own = m.model.lambda.middleRows(m.row0, m.row1 - m.row0);
  m.own_sum = m.topic_sum.segment(m.row0, m.row1 - m.row0);
  m.by_topic = true;
  m.model.lambda.resize(0, 0);  // this rank keeps its rows only
  m.topic_sum.resize(0);
}

void OnlineLda::gather_topics(core::Communicator& comm, bool whole_here) {
  Impl& m = *impl_;
  if (!m.by_topic) return;
  const std::int32_t want[1] = {whole_here ? 1 : 0};
  const std::vector<std::int32_t> wants =
      core::allgather_values<std::int32_t>(comm, std::span<const std::int32_t>(want));
  const auto P = m.first_row.size() - 1;
  ensure(wants.size() == P, "online LDA: split by topic for another number of ranks");
  const Eigen::Index W = m.num_words;
  const auto me = static_cast<std::size_t>(comm.rank());
  // Point to point, in one order on every rank: for each rank that wants the model, each owner
  // of rows in rank order sends them, in blocks of columns of at most 64 MB.
  constexpr std::size_t kBlockBytes = std::size_t{64} << 20;
  const auto columns_per_block = [&](std::size_t rows) {
    return static_cast<Eigen::Index>(std::max<std::size_t>(1, kBlockBytes / (rows * 8)));
  };
  std::vector<double> buffer;
  for (std::size_t t = 0; t < P; ++t) {
    if (wants[t] == 0) continue;
    if (t == me) {
      m.model.lambda.resize(m.num_topics, W);
      for (std::size_t q = 0; q < P; ++q) {
        const int r0 = m.first_row[q];
        const int n = m.first_row[q + 1] - r0;
        if (n == 0) continue;
        if (q == me) {
          m.model.lambda.middleRows(r0, n) = m.own;
          continue;
        }
        const Eigen::Index step = columns_per_block(static_cast<std::size_t>(n));
        for (Eigen::Index c0 = 0; c0 < W; c0 += step) {
          const Eigen::Index c = std::min(step, W - c0);
          buffer.resize(static_cast<std::size_t>(n) * static_cast<std::size_t>(c));
          comm.receive(std::as_writable_bytes(std::span<double>(buffer)), static_cast<int>(q));
          m.model.lambda.block(r0, c0, n, c) =
              Eigen::Map<const Eigen::MatrixXd>(buffer.data(), n, c);
        }
      }
      m.topic_sum = detail::topic_sums(m.model.lambda, m.pool);
    } else if (m.own.rows() > 0) {
      const Eigen::Index step = columns_per_block(static_cast<std::size_t>(m.own.rows()));
      for (Eigen::Index c0 = 0; c0 < W; c0 += step) {
        const Eigen::Index c = std::min(step, W - c0);
        // Column-major: columns [c0, c0 + c) of this rank's rows are contiguous.
        const double* at = m.own.data() + c0 * m.own.rows();
        comm.send(std::as_bytes(std::span<const double>(
                      at, static_cast<std::size_t>(c) * static_cast<std::size_t>(m.own.rows()))),
                  static_cast<int>(t));
      }
    }
  }
  if (!whole_here) {
    m.model.lambda.resize(0, 0);
    m.topic_sum.resize(0);
  }
}

LdaModel OnlineLda::release_model() {
  Impl& m = *impl_;
  LdaModel out = std::move(m.model);
  m.model = LdaModel{};
  m.model.alpha = out.alpha;
  m.model.eta = out.eta;
  m.model.tau0 = out.tau0;
  m.model.kappa = out.kappa;
  m.model.total_documents = out.total_documents;
  m.model.updates = out.updates;
  return out;
}

MiniBatchStats OnlineLda::update(const Corpus& corpus, std::size_t begin, std::size_t end) {
  Impl& m = *impl_;
  LdaModel& model = m.model;
  ensure(!m.by_topic, "online LDA: a model split by topic updates with its communicator");
  if (corpus.num_words() != model.num_words()) {
    throw Error("online LDA: the corpus has " + std::to_string(corpus.num_words()) +
                " words, the model " + std::to_string(model.num_words()));
  }
  if (begin >= end || end > corpus.num_documents()) {
    throw Error("online LDA: empty or out-of-range mini-batch");
  }
  const int K = model.num_topics();
  Lap lap;
  MiniBatchStats stats;
  stats.documents = static_cast<std::int64_t>(end - begin);

  // The mini-batch's own vocabulary: rows of the beta cache in order of first appearance.
  m.docs.clear();
  m.batch_words.clear();
  for (std::size_t d = begin; d < end; ++d) {
    const auto doc = corpus.document(d);
    for (std::size_t i = 0; i < doc.size(); ++i) {
      const std::int32_t w = doc.words[i];
      std::int32_t& r = m.row_of_word[static_cast<std::size_t>(w)];
      if (r < 0) {
        r = static_cast<std::int32_t>(m.batch_words.size());
        m.batch_words.push_back(w);
      }
      m.docs.rows.push_back(r);
      m.docs.counts.push_back(static_cast<float>(doc.counts[i]));
      stats.tokens += doc.counts[i];
    }
    m.docs.offsets.push_back(m.docs.rows.size());
    m.docs.keys.push_back(
        core::stream_seed(m.options.seed, static_cast<std::uint64_t>(model.updates), d));
  }

  lap(m.times.communication);  // the batch's assembly
  detail::exp_elog_beta(*m.kern, model.lambda, m.topic_sum, m.batch_words, m.stride, m.pool,
                        m.beta);
  lap(m.times.beta);
  detail::run_estep(*m.kern, m.pool, m.docs, m.beta.data(), K, m.stride, model.alpha,
                    m.options.estep, m.estep);
  lap(m.times.estep);
  finish_update(stats);
  return stats;
}

namespace {

// sufficient_statistics (engine.hpp) on the topics [k0, k1) only: the whole vectors of lanes that
// hold them, each entry summed in document order, as there. Compact: a row holds only those
// lanes (`width` floats a row, lane `lane0` first), so a rank zeroes and walks its share of the
// V_B x stride block and not all of it; topic k of row r is at sstats[r * width + k - lane0].
void statistics_of_rows(const detail::Kernels& kern, core::ThreadPool& pool,
                        const detail::BatchDocs& docs, const detail::BatchEStep& estep,
                        std::size_t rows, int k0, int k1, detail::FloatBuffer& sstats, int& lane0,
                        int& width) {
  const auto S = static_cast<std::size_t>(estep.stride);
  const int first = k0 / kern.lanes;
  const int vectors = k1 > k0 ? (k1 + kern.lanes - 1) / kern.lanes - first : 0;
  lane0 = first * kern.lanes;
  width = vectors * kern.lanes;
  const auto L = static_cast<std::size_t>(width);
  sstats.assign(rows * L, 0.0f);
  if (vectors == 0) return;
  const int parts = std::min(pool.size(), vectors);
  core::parallel_for(pool, static_cast<std::size_t>(parts), [&](std::size_t p, int) {
    const int v0 = static_cast<int>(p) * vectors / parts;
    const int v1 = (static_cast<int>(p) + 1) * vectors / parts;
    const int a = v0 * kern.lanes;
    const int len = (v1 - v0) * kern.lanes;
    for (std::size_t d = 0; d < docs.size(); ++d) {
      const float* eth = estep.exp_elog_theta.data() + d * S + lane0 + a;
      for (std::size_t e = docs.offsets[d]; e < docs.offsets[d + 1]; ++e) {
        float* row = sstats.data() + static_cast<std::size_t>(docs.rows[e]) * L + a;
        kern.axpy(estep.weights[e], eth, row, len);
      }
    }
  });
}

// The M-step (eq B.23-B.24) on the rows [k0, k0 + n) of lambda held in `rows` (n x W): for every
// word, lambda = (1 - rho) lambda + rho eta + rho D/|B| sstats exp(E[log beta]) on the batch's
// words, the decay alone on the others. Row r's statistics of topic k are at
// sstats[r * sstride + k - lane0] (sufficient_statistics: sstride = S, lane0 = 0; compact:
// statistics_of_rows), its exp E[log beta] at beta[r * S + k].
void mstep_rows(Eigen::MatrixXd& rows, int k0, const std::vector<std::int32_t>& row_of_word,
                const float* sstats, std::size_t sstride, int lane0, const float* beta,
                std::size_t S, double rho, double scale, double eta, core::ThreadPool& pool) {
  const double keep = 1.0 - rho;
  const double prior = rho * eta;
  const auto W = static_cast<std::size_t>(rows.cols());
  const auto n = static_cast<int>(rows.rows());
  if (n == 0) return;
  constexpr std::size_t kBlock = 256;
  core::parallel_for(pool, (W + kBlock - 1) / kBlock, [&](std::size_t b, int) {
    const std::size_t w1 = std::min(W, (b + 1) * kBlock);
    for (std::size_t w = b * kBlock; w < w1; ++w) {
      double* col = rows.col(static_cast<Eigen::Index>(w)).data();
      const std::int32_t r = row_of_word[w];
      if (r >= 0) {
        const float* s = sstats + static_cast<std::size_t>(r) * sstride + (k0 - lane0);
        const float* e = beta + static_cast<std::size_t>(r) * S + k0;
        for (int k = 0; k < n; ++k) {
          col[k] = keep * col[k] + prior +
                   rho * scale * static_cast<double>(s[k]) * static_cast<double>(e[k]);
        }
      } else {
        for (int k = 0; k < n; ++k) col[k] = keep * col[k] + prior;
      }
    }
  });
}

}  // namespace

void OnlineLda::finish_update(MiniBatchStats& stats) {
  Impl& m = *impl_;
  LdaModel& model = m.model;
  const auto S = static_cast<std::size_t>(m.stride);
  Lap lap;
  int lane0 = 0;         // the statistics' first lane (compact when split by topic)
  int width = m.stride;  // and their floats a row
  if (m.by_topic) {
    statistics_of_rows(*m.kern, m.pool, m.docs, m.estep, m.batch_words.size(), m.row0, m.row1,
                       m.sstats, lane0, width);
  } else {
    detail::sufficient_statistics(*m.kern, m.pool, m.docs, m.estep, m.batch_words.size(), m.sstats);
  }
  for (std::size_t d = 0; d < m.docs.size(); ++d) {
    stats.estep_iterations += m.estep.iterations[d];
    if (m.docs.offsets[d + 1] > m.docs.offsets[d] && !m.estep.converged[d]) ++stats.capped;
  }
  lap(m.times.statistics);

  // M-step (eq B.23-B.24): lambda-hat = eta + D/|B| * sstats * exp(E[log beta]).
  // t counts this update from 1, as scikit-learn does (Hoffman's code counts from 0).
  const double rho = std::pow(model.tau0 + static_cast<double>(model.updates + 1), -model.kappa);
  const double scale =
      static_cast<double>(model.total_documents) / static_cast<double>(stats.documents);
  if (m.by_topic) {
    mstep_rows(m.own, m.row0, m.row_of_word, m.sstats.data(), static_cast<std::size_t>(width),
               lane0, m.beta.data(), S, rho, scale, model.eta, m.pool);
    m.own_sum = detail::topic_sums(m.own, m.pool);
  } else {
    mstep_rows(model.lambda, 0, m.row_of_word, m.sstats.data(), S, 0, m.beta.data(), S, rho, scale,
               model.eta, m.pool);
    m.topic_sum = detail::topic_sums(model.lambda, m.pool);
  }
  for (const auto w : m.batch_words) m.row_of_word[static_cast<std::size_t>(w)] = -1;
  ++model.updates;
  ++m.times.updates;
  stats.rho = rho;
  lap(m.times.mstep);
}

namespace {

// exp(E[log beta]) (eq B.19) of the listed words on the rows [k0, k0 + n) held in `rows`, packed:
// n floats a word; also written into lanes [k0, k0 + n) of word i's row of `cache` (rows of
// `stride` floats) when `cache` is given. The kernel runs on the whole vectors of lanes that hold
// those rows, so each value has the bits exp_elog_beta gives it.
void exp_elog_beta_rows(const detail::Kernels& kern, const Eigen::MatrixXd& rows, int k0,
                        const Eigen::VectorXd& row_sum, std::span<const std::int32_t> words,
                        core::ThreadPool& pool, detail::FloatBuffer& out, float* cache = nullptr,
                        std::size_t stride = 0) {
  const auto n = static_cast<int>(rows.rows());
  out.resize(words.size() * static_cast<std::size_t>(n));
  if (n == 0) return;
  const int a = k0 / kern.lanes * kern.lanes;
  const int len = detail::padded(k0 + n, kern.lanes) - a;
  const auto off = static_cast<std::size_t>(k0 - a);
  detail::FloatBuffer sub(static_cast<std::size_t>(len), 0.0f);
  for (int k = 0; k < n; ++k) {
    sub[off + static_cast<std::size_t>(k)] = static_cast<float>(detail::digamma(row_sum(k)));
  }
  const auto T = static_cast<std::size_t>(pool.size());
  std::vector<detail::FloatBuffer> x(T, detail::FloatBuffer(static_cast<std::size_t>(len), 1.0f));
  std::vector<detail::FloatBuffer> y(T, detail::FloatBuffer(static_cast<std::size_t>(len)));
  constexpr std::size_t kBlock = 64;
  const std::size_t blocks = (words.size() + kBlock - 1) / kBlock;
  core::parallel_for(pool, blocks, [&](std::size_t b, int t) {
    float* xt = x[static_cast<std::size_t>(t)].data();
    float* yt = y[static_cast<std::size_t>(t)].data();
    const std::size_t end = std::min(words.size(), (b + 1) * kBlock);
    for (std::size_t i = b * kBlock; i < end; ++i) {
      const double* col = rows.col(words[i]).data();
      for (int k = 0; k < n; ++k)
        xt[off + static_cast<std::size_t>(k)] = static_cast<float>(col[k]);
      kern.exp_digamma_minus(xt, sub.data(), yt, len);
      std::memcpy(out.data() + i * static_cast<std::size_t>(n), yt + off,
                  static_cast<std::size_t>(n) * sizeof(float));
      if (cache != nullptr) {
        std::memcpy(cache + i * stride + static_cast<std::size_t>(k0), yt + off,
                    static_cast<std::size_t>(n) * sizeof(float));
      }
    }
  });
}

// Documents [begin, end) dealt d mod P, as they are read (no balancing).
std::vector<int> deal_round_robin(std::size_t begin, std::size_t end, int ranks) {
  std::vector<int> owner(end - begin);
  for (std::size_t d = begin; d < end; ++d) {
    owner[d - begin] = static_cast<int>(d % static_cast<std::size_t>(ranks));
  }
  return owner;
}

// The batch's documents dealt by the expected cost of their E-step: (entries + 2) x the iterations
// the document took in the previous pass (1 in the first pass); an entry costs one pass over the
// topics a iteration, the exp(digamma) of gamma about two.
std::vector<int> deal_by_cost(const detail::BatchDocs& docs, std::size_t begin,
                              const std::vector<std::uint16_t>& last_iterations, int ranks) {
  std::vector<std::int64_t> cost(docs.size());
  for (std::size_t i = 0; i < docs.size(); ++i) {
    const auto entries = static_cast<std::int64_t>(docs.offsets[i + 1] - docs.offsets[i]);
    const std::size_t d = begin + i;
    const std::int64_t it =
        d < last_iterations.size() ? std::max<std::int64_t>(1, last_iterations[d]) : 1;
    cost[i] = entries == 0 ? 0 : (entries + 2) * it;
  }
  return mpi_deal_by_cost(cost, ranks);
}

// Keeps the E-step iterations of document d for the next pass's dealing.
void remember_iterations(std::vector<std::uint16_t>& last, std::size_t d, std::int32_t iterations) {
  if (d >= last.size()) last.resize(d + 1, 0);
  last[d] = static_cast<std::uint16_t>(std::clamp<std::int32_t>(iterations, 0, 65535));
}

}  // namespace

std::vector<int> mpi_deal_by_cost(std::span<const std::int64_t> costs, int ranks) {
  assert(ranks >= 1);
  std::vector<std::size_t> order(costs.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return costs[a] > costs[b]; });
  std::vector<std::int64_t> load(static_cast<std::size_t>(ranks), 0);
  std::vector<std::size_t> dealt(static_cast<std::size_t>(ranks), 0);
  std::vector<int> owner(costs.size(), 0);
  for (const std::size_t i : order) {
    // The least loaded rank; among equal loads the one with fewest documents, then the lowest.
    std::size_t best = 0;
    for (std::size_t q = 1; q < load.size(); ++q) {
      if (load[q] < load[best] || (load[q] == load[best] && dealt[q] < dealt[best])) best = q;
    }
    owner[i] = static_cast<int>(best);
    load[best] += costs[i];
    ++dealt[best];
  }
  return owner;
}

namespace {

// Appends this rank's documents of [begin, end) to `out`: per document its size n, its n word ids
// and its n counts (32-bit integers).
void pack_documents(const CorpusShard& shard, std::size_t begin, std::size_t end,
                    std::vector<std::byte>& out) {
  const Corpus& local = shard.documents;
  const std::size_t l0 = shard.first_local_at(begin);
  const std::size_t l1 = std::min(shard.first_local_at(end), local.num_documents());
  const auto append = [&out](const void* p, std::size_t bytes) {
    const auto* b = static_cast<const std::byte*>(p);
    out.insert(out.end(), b, b + bytes);
  };
  for (std::size_t j = l0; j < l1; ++j) {
    const auto doc = local.document(j);
    const auto n = static_cast<std::int32_t>(doc.size());
    append(&n, sizeof n);
    append(doc.words.data(), doc.words.size_bytes());
    append(doc.counts.data(), doc.counts.size_bytes());
  }
}

// The bytes pack_documents appends for [begin, end).
std::size_t packed_bytes(const CorpusShard& shard, std::size_t begin, std::size_t end) {
  const Corpus& local = shard.documents;
  const std::size_t l0 = shard.first_local_at(begin);
  const std::size_t l1 = std::min(shard.first_local_at(end), local.num_documents());
  std::size_t n = 0;
  for (std::size_t j = l0; j < l1; ++j) n += 1 + 2 * local.document(j).size();
  return n * sizeof(std::int32_t);
}

}  // namespace

MiniBatchStats OnlineLda::update(const CorpusShard& shard, std::size_t begin, std::size_t end,
                                 core::Communicator& comm) {
  Impl& m = *impl_;
  LdaModel& model = m.model;
  const Corpus& local = shard.documents;
  if (local.num_words() != m.num_words) {
    throw Error("online LDA: the corpus has " + std::to_string(local.num_words()) +
                " words, the model " + std::to_string(m.num_words));
  }
  const auto total = static_cast<std::size_t>(shard.total_documents);
  if (begin >= end || end > total) throw Error("online LDA: empty or out-of-range mini-batch");
  const int K = m.num_topics;
  const auto S = static_cast<std::size_t>(m.stride);
  const auto P = static_cast<std::size_t>(comm.size());
  ensure(!m.by_topic || m.first_row.size() == P + 1,
         "online LDA: split by topic for another number of ranks");
  Lap lap;
  MiniBatchStats stats;
  const std::size_t B = end - begin;
  stats.documents = static_cast<std::int64_t>(B);
  m.widest = std::max(m.widest, B);
  double collective_wall = 0;
  double collective_cpu = 0;
  const auto collective = [&](const auto& call) {
    const auto t0 = Clock::now();
    const double c0 = process_cpu_seconds();
    call();
    collective_cpu += process_cpu_seconds() - c0;
    collective_wall += since(t0);
  };

  // 1. Every rank's documents of the batch: per document its size, word ids and counts. The lean
  // exchange sent them with the previous batch's E-step output when that batch's prediction of
  // the next range was right; else they are gathered now (two collectives: sizes, then bytes).
  Impl::Ahead& docs_in = m.ahead;
  if (!(docs_in.valid && docs_in.begin == begin && docs_in.end == end)) {
    std::vector<std::byte> pack;
    pack_documents(shard, begin, end, pack);
    std::vector<std::byte> gathered;
    std::vector<std::size_t> sizes;
    collective([&] { comm.allgather(pack, gathered, sizes); });
    m.times.collectives += 2;
    docs_in.set(gathered, sizes);
  }
  docs_in.valid = false;
  const std::vector<std::int32_t>& all = docs_in.words;
  std::vector<std::size_t> cursor(docs_in.starts.begin(), docs_in.starts.end() - 1);

  // 2. The batch in corpus order, as one process builds it (document d came from rank d mod P):
  // the entries' rows in the beta cache for every document (the statistics sum over all of
  // them), counts and random keys for this rank's documents only (below).
  m.docs.clear();
  m.batch_words.clear();
  m.doc_at.resize(B);
  for (std::size_t d = begin; d < end; ++d) {
    std::size_t& c = cursor[d % P];
    ensure(c < docs_in.starts[d % P + 1], "online LDA: a rank sent too few documents");
    const auto n = static_cast<std::size_t>(all[c]);
    m.doc_at[d - begin] = c;
    const std::int32_t* words = all.data() + c + 1;
    const std::int32_t* cnt = words + n;
    c += 1 + 2 * n;
    ensure(c <= docs_in.starts[d % P + 1], "online LDA: a rank sent a truncated document");
    for (std::size_t i = 0; i < n; ++i) {
      std::int32_t& r = m.row_of_word[static_cast<std::size_t>(words[i])];
      if (r < 0) {
        r = static_cast<std::int32_t>(m.batch_words.size());
        m.batch_words.push_back(words[i]);
      }
      m.docs.rows.push_back(r);
      stats.tokens += cnt[i];
    }
    m.docs.offsets.push_back(m.docs.rows.size());
  }
  for (std::size_t q = 0; q < P; ++q) {
    ensure(cursor[q] == docs_in.starts[q + 1], "online LDA: a rank sent other documents");
  }
  // Which rank runs each document's E-step: dealt by its expected cost (every rank has every
  // document of the batch now, and computes the same dealing); this rank's documents in corpus
  // order. A document's E-step does not depend on the rank that runs it.
  const std::vector<int> owner =
      m.balance ? deal_by_cost(m.docs, begin, m.last_iterations, static_cast<int>(P))
                : deal_round_robin(begin, end, static_cast<int>(P));
  detail::BatchDocs& mine = m.mine;
  mine.clear();
  const int rank = comm.rank();
  for (std::size_t i = 0; i < B; ++i) {
    if (owner[i] != rank) continue;
    const std::size_t e0 = m.docs.offsets[i];
    const std::size_t e1 = m.docs.offsets[i + 1];
    const std::int32_t* cnt = all.data() + m.doc_at[i] + 1 + (e1 - e0);
    for (std::size_t e = e0; e < e1; ++e) {
      mine.rows.push_back(m.docs.rows[e]);
      mine.counts.push_back(static_cast<float>(cnt[e - e0]));
    }
    mine.offsets.push_back(mine.rows.size());
    mine.keys.push_back(
        core::stream_seed(m.options.seed, static_cast<std::uint64_t>(model.updates), begin + i));
  }

  lap(m.times.communication);

  // 3. exp(E[log beta]) of the batch's words: whole, or on this rank's topic rows and then
  // gathered (every rank knows every rank's V_B x rows floats: one collective); the E-step of
  // this rank's documents.
  const std::size_t V = m.batch_words.size();
  if (m.by_topic) {
    detail::FloatBuffer& part = m.beta_part;
    // This rank's rows go straight into the cache too (the others' are placed after the
    // allgather).
    m.beta.resize(m.batch_words.size() * S);
    exp_elog_beta_rows(*m.kern, m.own, m.row0, m.own_sum, m.batch_words, m.pool, part,
                       m.beta.data(), S);
    lap(m.times.beta);
    std::vector<std::size_t> part_sizes(P);
    for (std::size_t q = 0; q < P; ++q) {
      part_sizes[q] =
          V * static_cast<std::size_t>(m.first_row[q + 1] - m.first_row[q]) * sizeof(float);
    }
    const auto mine_bytes = std::as_bytes(std::span<const float>(part.data(), part.size()));
    if (m.lean) {
      m.beta_rows.resize(V * static_cast<std::size_t>(K));
      collective([&] {
        comm.allgather_sized(mine_bytes, std::as_writable_bytes(std::span<float>(m.beta_rows)),
                             part_sizes);
      });
      m.times.collectives += 1;
    } else {
      std::vector<std::byte> gathered;
      std::vector<std::size_t> sizes;
      collective([&] { comm.allgather(mine_bytes, gathered, sizes); });
      m.times.collectives += 2;
      ensure(sizes == part_sizes, "online LDA: a rank sent wrong beta rows");
      m.beta_rows.resize(gathered.size() / sizeof(float));
      if (!gathered.empty()) std::memcpy(m.beta_rows.data(), gathered.data(), gathered.size());
    }
    // Word by word, in one pass over the cache: each other rank's rows of the word (rank q's
    // block of V x n_q floats starts at from[q]), then zeros in the padding lanes [K, S).
    const auto me = static_cast<std::size_t>(comm.rank());
    std::vector<const float*> from(P);
    std::size_t at = 0;
    for (std::size_t q = 0; q < P; ++q) {
      from[q] = m.beta_rows.data() + at;
      at += V * static_cast<std::size_t>(m.first_row[q + 1] - m.first_row[q]);
    }
    for (std::size_t i = 0; i < V; ++i) {
      float* row = m.beta.data() + i * S;
      for (std::size_t q = 0; q < P; ++q) {
        const auto r0 = static_cast<std::size_t>(m.first_row[q]);
        const auto n = static_cast<std::size_t>(m.first_row[q + 1]) - r0;
        if (n > 0 && q != me) std::memcpy(row + r0, from[q] + i * n, n * sizeof(float));
      }
      std::fill(row + K, row + S, 0.0f);
    }
    lap(m.times.communication);
  } else {
    detail::exp_elog_beta(*m.kern, model.lambda, m.topic_sum, m.batch_words, m.stride, m.pool,
                          m.beta);
    lap(m.times.beta);
  }
  detail::BatchEStep& own = m.own_estep;
  const auto estep_t0 = Clock::now();
  const double estep_c0 = process_cpu_seconds();
  detail::run_estep(*m.kern, m.pool, mine, m.beta.data(), K, m.stride, model.alpha, m.options.estep,
                    own);
  m.times.estep_wall += since(estep_t0);
  const double estep_cpu = process_cpu_seconds() - estep_c0;
  lap(m.times.estep);

  // 4. What every rank's E-step left, in corpus order: exp E[log theta], the entries' weights,
  // the iterations and whether each converged. With the lean exchange, then the byte count of
  // this rank's documents of the batch after next, and its documents of the next batch (both
  // predicted: the next range of the widest width, from 0 after the corpus's end). Every rank
  // knows every rank's E-step bytes (the dealing), and the documents' bytes were announced one
  // batch before: then this is one collective of known sizes.
  std::vector<std::vector<std::size_t>> docs_of(P);
  for (std::size_t i = 0; i < B; ++i) docs_of[static_cast<std::size_t>(owner[i])].push_back(i);
  std::vector<std::size_t> estep_bytes(P);
  for (std::size_t q = 0; q < P; ++q) {
    std::size_t entries = 0;
    for (const std::size_t i : docs_of[q]) entries += m.docs.offsets[i + 1] - m.docs.offsets[i];
    estep_bytes[q] = docs_of[q].size() * (S * sizeof(float) + 2 * sizeof(std::int32_t)) +
                     entries * sizeof(float) + sizeof(double);
  }
  std::vector<std::byte>& out = m.out;
  out.clear();
  const auto append = [&out](const void* p, std::size_t bytes) {
    const auto* b = static_cast<const std::byte*>(p);
    out.insert(out.end(), b, b + bytes);
  };
  append(own.exp_elog_theta.data(), own.exp_elog_theta.size() * sizeof(float));
  append(own.weights.data(), own.weights.size() * sizeof(float));
  std::vector<std::int32_t> flags;
  for (std::size_t j = 0; j < mine.size(); ++j) {
    flags.push_back(own.iterations[j]);
    flags.push_back(own.converged[j]);
  }
  append(flags.data(), flags.size() * sizeof(std::int32_t));
  append(&estep_cpu, sizeof estep_cpu);  // for phase_times' imbalance only; not in the model
  const auto next_of = [&](std::size_t e) {
    const std::size_t b = e < total ? e : 0;
    return std::pair<std::size_t, std::size_t>{b, std::min(total, b + m.widest)};
  };
  const auto [next_begin, next_end] = next_of(end);
  const auto [after_begin, after_end] = next_of(next_end);
  Impl::Announced& told = m.announced;
  const bool known = m.lean && told.valid && told.begin == next_begin && told.end == next_end;
  if (m.lean) {
    const auto bytes = static_cast<std::uint64_t>(packed_bytes(shard, after_begin, after_end));
    append(&bytes, sizeof bytes);
    pack_documents(shard, next_begin, next_end, out);
  }
  std::vector<std::byte>& gathered = m.gathered;
  std::vector<std::size_t> sizes(P);
  const auto wait_t0 = Clock::now();
  if (known) {
    for (std::size_t q = 0; q < P; ++q) {
      sizes[q] = estep_bytes[q] + sizeof(std::uint64_t) + told.bytes[q];
    }
    gathered.resize(std::accumulate(sizes.begin(), sizes.end(), std::size_t{0}));
    collective([&] { comm.allgather_sized(out, gathered, sizes); });
    m.times.collectives += 1;
  } else {
    collective([&] { comm.allgather(out, gathered, sizes); });
    m.times.collectives += 2;
  }
  m.times.wait_wall += since(wait_t0);

  detail::BatchEStep& e = m.estep;
  e.stride = m.stride;
  e.exp_elog_theta.resize(B * S);
  e.weights.resize(m.docs.rows.size());
  e.iterations.assign(B, 0);
  e.converged.assign(B, 1);
  // Per rank: its documents' positions in the batch, then its three blocks.
  double slowest_cpu = 0;
  std::vector<std::size_t> next_bytes(P, 0);
  told.bytes.assign(P, 0);
  std::size_t at = 0;
  for (std::size_t q = 0; q < P; ++q) {
    const std::byte* base = gathered.data() + at;
    const std::size_t head = estep_bytes[q] + (m.lean ? sizeof(std::uint64_t) : 0);
    ensure(m.lean ? head <= sizes[q] && (sizes[q] - head) % sizeof(std::int32_t) == 0
                  : head == sizes[q],
           "online LDA: a rank sent a wrong E-step");
    next_bytes[q] = sizes[q] - head;
    if (m.lean) {
      std::uint64_t announced = 0;
      std::memcpy(&announced, base + estep_bytes[q], sizeof announced);
      told.bytes[q] = static_cast<std::size_t>(announced);
    }
    double their_cpu = 0;
    std::memcpy(&their_cpu, base + estep_bytes[q] - sizeof(double), sizeof their_cpu);
    slowest_cpu = std::max(slowest_cpu, their_cpu);
    const std::byte* w_at = base + docs_of[q].size() * S * sizeof(float);
    std::size_t entries = 0;
    for (const std::size_t i : docs_of[q]) entries += m.docs.offsets[i + 1] - m.docs.offsets[i];
    const std::byte* f_at = w_at + entries * sizeof(float);
    std::size_t n = 0;
    std::size_t k = 0;
    for (const std::size_t i : docs_of[q]) {
      std::memcpy(e.exp_elog_theta.data() + i * S, base + n * S * sizeof(float), S * sizeof(float));
      const std::size_t len = m.docs.offsets[i + 1] - m.docs.offsets[i];
      std::memcpy(e.weights.data() + m.docs.offsets[i], w_at + k * sizeof(float),
                  len * sizeof(float));
      std::int32_t f[2];
      std::memcpy(f, f_at + n * 2 * sizeof(std::int32_t), sizeof f);
      e.iterations[i] = f[0];
      e.converged[i] = static_cast<char>(f[1]);
      remember_iterations(m.last_iterations, begin + i, f[0]);
      k += len;
      ++n;
    }
    at += sizes[q];
  }
  if (m.lean) {
    // The next batch's documents: the tail of every rank's block, concatenated in rank order.
    docs_in.words.resize(std::accumulate(next_bytes.begin(), next_bytes.end(), std::size_t{0}) /
                         sizeof(std::int32_t));
    docs_in.starts.assign(1, 0);
    std::size_t from = 0;
    for (std::size_t q = 0; q < P; ++q) {
      from += sizes[q];
      const std::size_t n = next_bytes[q] / sizeof(std::int32_t);
      if (n > 0) {
        std::memcpy(docs_in.words.data() + docs_in.starts.back(),
                    gathered.data() + from - next_bytes[q], next_bytes[q]);
      }
      docs_in.starts.push_back(docs_in.starts.back() + n);
    }
    docs_in.begin = next_begin;
    docs_in.end = next_end;
    docs_in.valid = true;
    told.begin = after_begin;
    told.end = after_end;
    told.valid = true;
  }
  m.times.estep_imbalance += slowest_cpu - estep_cpu;
  m.times.collective_wall += collective_wall;
  m.times.collective_cpu += collective_cpu;
  lap(m.times.communication);
  finish_update(stats);
  return stats;
}

std::uint64_t corpus_checksum(const Corpus& corpus) {
  const auto bytes_of = [](const auto& span) {
    return std::string_view(reinterpret_cast<const char*>(span.data()), span.size_bytes());
  };
  std::uint64_t h = core::fnv1a("corpus");
  const std::int64_t head[2] = {corpus.num_words(),
                                static_cast<std::int64_t>(corpus.num_documents())};
  h = core::fnv1a(bytes_of(std::span(head)), h);
  for (std::size_t d = 0; d < corpus.num_documents(); ++d) {
    const auto doc = corpus.document(d);
    const auto n = static_cast<std::int64_t>(doc.size());
    h = core::fnv1a(std::string_view(reinterpret_cast<const char*>(&n), sizeof n), h);
    h = core::fnv1a(bytes_of(doc.words), h);
    h = core::fnv1a(bytes_of(doc.counts), h);
  }
  for (const auto& w : corpus.vocabulary()) {
    h = core::fnv1a(w, h);
    h = core::fnv1a(std::string_view("\n", 1), h);
  }
  return h;
}

namespace {

constexpr const char* kLdaCheckpointKind = "online_lda";

// Where training stands: what a checkpoint holds besides the model.
struct Progress {
  std::int32_t pass = 0;
  std::uint64_t next_begin = 0;  // the first document of the next mini-batch of this pass
  std::int64_t iterations = 0;   // E-step iterations summed so far
};

// The checkpoint's identity: the corpus (and held-out corpus), and every option the model or the
// trace depends on (threads change nothing).
core::Checkpoint lda_checkpoint_identity(const Corpus& corpus, const Corpus* heldout,
                                         const OnlineLdaOptions& options, std::int64_t D) {
  core::Checkpoint c;
  c.kind = kLdaCheckpointKind;
  c.input_checksum = corpus_checksum(corpus);
  OnlineLdaOptions o = options;
  o.alpha = o.resolved_alpha();
  o.eta = o.resolved_eta();
  const core::Json j = core::fields_to_json(o);
  for (const auto& [name, value] : j.items()) {
    if (name != "threads") c.options.emplace_back(name, value.dump());
  }
  c.options.emplace_back("total_documents", std::to_string(D));
  c.options.emplace_back("estep_init", std::to_string(static_cast<int>(o.estep.init)));
  c.options.emplace_back("heldout",
                         heldout != nullptr ? std::to_string(corpus_checksum(*heldout)) : "none");
  if (heldout != nullptr) {
    const PerplexityOptions& e = o.evaluation;
    c.options.emplace_back("evaluation", std::to_string(static_cast<int>(e.method)) + " " +
                                             std::to_string(e.estep.max_iterations) + " " +
                                             core::exact_text(e.estep.tolerance) + " " +
                                             std::to_string(static_cast<int>(e.estep.init)) + " " +
                                             std::to_string(e.split_seed));
  }
  return c;
}

std::string lda_state(const LdaModel& model, const Progress& p, const OnlineLdaSummary& s) {
  std::string out;
  core::put_binary<std::int32_t>(out, p.pass);
  core::put_binary<std::uint64_t>(out, p.next_begin);
  core::put_binary<std::int64_t>(out, p.iterations);
  core::put_binary<std::int64_t>(out, s.updates);
  core::put_binary<std::int32_t>(out, s.passes);
  core::put_binary<std::int64_t>(out, s.documents);
  core::put_binary<std::int64_t>(out, s.tokens);
  core::put_binary<std::int64_t>(out, s.capped);
  core::put_binary<double>(out, s.seconds);
  core::put_binary<double>(out, s.cpu_seconds);
  core::put_binary<double>(out, s.evaluation_seconds);
  core::put_binary<std::uint64_t>(out, s.trace.size());
  for (const auto& t : s.trace) {
    core::put_binary<std::int64_t>(out, t.updates);
    core::put_binary<std::int64_t>(out, t.documents_seen);
    core::put_binary<double>(out, t.perplexity);
  }
  const std::string m = serialize_lda_model(model);
  core::put_binary<std::uint64_t>(out, m.size());
  out += m;
  return out;
}

// Reads lda_state's layout; every count is checked against the bytes left before allocating, and
// the progress against the corpus.
LdaModel parse_lda_state(std::string_view state, const std::filesystem::path& source, Progress& p,
                         OnlineLdaSummary& s) {
  core::BinaryReader in(state, source, "checkpoint");
  p.pass = in.get<std::int32_t>("the pass");
  p.next_begin = in.get<std::uint64_t>("the next document");
  p.iterations = in.get<std::int64_t>("the E-step iterations");
  s.updates = in.get<std::int64_t>("the updates");
  s.passes = in.get<std::int32_t>("the passes");
  s.documents = in.get<std::int64_t>("the documents");
  s.tokens = in.get<std::int64_t>("the tokens");
  s.capped = in.get<std::int64_t>("the capped E-steps");
  s.seconds = in.get<double>("the seconds");
  s.cpu_seconds = in.get<double>("the processor seconds");
  s.evaluation_seconds = in.get<double>("the evaluation seconds");
  const auto n = in.get<std::uint64_t>("the trace's length");
  constexpr std::size_t kPointBytes = 24;
  if (n > in.left() / kPointBytes) {
    throw Error::in_file(source, "corrupt checkpoint file: a trace of " + std::to_string(n) +
                                     " points runs past the end");
  }
  s.trace.resize(n);
  for (auto& t : s.trace) {
    t.updates = in.get<std::int64_t>("a trace point");
    t.documents_seen = in.get<std::int64_t>("a trace point");
    t.perplexity = in.get<double>("a trace point");
  }
  const auto m = in.get<std::uint64_t>("the model's size");
  LdaModel model = parse_lda_model(in.take(m, "the model"), source);
  if (in.left() != 0)
    throw Error::in_file(source, "corrupt checkpoint file: bytes after the model");
  const bool finite = std::isfinite(s.seconds) && std::isfinite(s.cpu_seconds) &&
                      std::isfinite(s.evaluation_seconds);
  if (p.pass < 0 || s.passes != p.pass || s.updates != model.updates || s.updates < 0 ||
      s.documents < 0 || s.tokens < 0 || s.capped < 0 || p.iterations < 0 || !finite) {
    throw Error::in_file(source, "corrupt checkpoint file: inconsistent progress");
  }
  for (const auto& t : s.trace) {
    if (!std::isfinite(t.perplexity)) {
      throw Error::in_file(source, "corrupt checkpoint file: a perplexity that is not finite");
    }
  }
  return model;
}

OnlineLdaResult train(const Corpus& corpus, const Corpus* heldout, const OnlineLdaOptions& options,
                      const core::CheckpointOptions* checkpointing) {
  options.validate();
  if (checkpointing != nullptr) checkpointing->validate();
  if (corpus.num_documents() == 0) throw Error("online LDA: the training corpus is empty");
  if (corpus.num_words() < 1) throw Error("online LDA: the vocabulary is empty");
  check_heldout_words(heldout, corpus.num_words());
  const std::int64_t D = options.total_documents > 0
                             ? options.total_documents
                             : static_cast<std::int64_t>(corpus.num_documents());
  const bool saving = checkpointing != nullptr && !checkpointing->checkpoint.empty();
  const bool resuming = checkpointing != nullptr && !checkpointing->resume.empty();
  core::Checkpoint identity;
  if (saving || resuming) identity = lda_checkpoint_identity(corpus, heldout, options, D);

  OnlineLdaResult result;
  OnlineLdaSummary& s = result.summary;
  Progress progress;
  std::optional<OnlineLda> lda_holder;
  if (resuming) {
    const core::Checkpoint found = core::load_checkpoint(checkpointing->resume);
    core::check_checkpoint_matches(found, identity, checkpointing->resume, "corpus");
    LdaModel model = parse_lda_state(found.state, checkpointing->resume, progress, s);
    if (progress.pass > options.passes || progress.next_begin > corpus.num_documents() ||
        model.num_words() != corpus.num_words() || model.num_topics() != options.num_topics) {
      throw Error::in_file(checkpointing->resume,
                           "corrupt checkpoint file: its progress does not fit the corpus");
    }
    lda_holder.emplace(std::move(model), options);
  } else {
    lda_holder.emplace(options, corpus.num_words(), D, corpus.vocabulary());
  }
  OnlineLda& lda = *lda_holder;
  s.threads = options.threads;
  s.kernel = lda.kernel();

  const HeldoutTrace heldout_trace(heldout, options);
  const bool trace = heldout_trace.active();
  auto evaluate = [&] { heldout_trace.evaluate(lda.model(), s); };
  if (trace && !resuming) evaluate();

  std::int64_t nonempty = 0;
  for (std::size_t d = 0; d < corpus.num_documents(); ++d) nonempty += !corpus.document(d).empty();
  const auto B = static_cast<std::size_t>(options.batch_size);
  for (int pass = progress.pass; pass < options.passes; ++pass) {
    const std::size_t first = pass == progress.pass ? progress.next_begin : 0;
    for (std::size_t b = first; b < corpus.num_documents(); b += B) {
      const auto t0 = Clock::now();
      const double c0 = process_cpu_seconds();
      const MiniBatchStats st = lda.update(corpus, b, std::min(corpus.num_documents(), b + B));
      s.seconds += since(t0);
      s.cpu_seconds += process_cpu_seconds() - c0;
      ++s.updates;
      s.documents += st.documents;
      s.tokens += st.tokens;
      s.capped += st.capped;
      progress.iterations += st.estep_iterations;
      if (trace && options.evaluate_every > 0 && s.updates % options.evaluate_every == 0) {
        evaluate();
      }
      if (saving && s.updates % checkpointing->every == 0) {
        progress.pass = pass;
        progress.next_begin = std::min(corpus.num_documents(), b + B);
        core::Checkpoint c = identity;
        c.state = lda_state(lda.model(), progress, s);
        core::save_checkpoint(c, checkpointing->checkpoint);
      }
    }
    ++s.passes;
  }
  if (trace && (s.trace.empty() || s.trace.back().updates != lda.model().updates)) evaluate();
  const std::int64_t docs_run = nonempty * options.passes;
  s.mean_estep_iterations =
      docs_run > 0 ? static_cast<double>(progress.iterations) / static_cast<double>(docs_run) : 0.0;
  result.phase_times = lda.phase_times();
  result.model = lda.model();
  result.summary.message = core::first_line(result.summary.brief());
  return result;
}

}  // namespace

OnlineLdaResult train_online_lda(const Corpus& corpus, const OnlineLdaOptions& options) {
  return train(corpus, nullptr, options, nullptr);
}

OnlineLdaResult train_online_lda(const Corpus& corpus, const Corpus& heldout,
                                 const OnlineLdaOptions& options) {
  return train(corpus, &heldout, options, nullptr);
}

OnlineLdaResult train_online_lda(const Corpus& corpus, const Corpus* heldout,
                                 const OnlineLdaOptions& options,
                                 const core::CheckpointOptions& checkpointing) {
  return train(corpus, heldout, options, &checkpointing);
}

namespace {

// PROPRIO_MPI_TEST_FAIL="RANK:UPDATE": the update before which rank RANK aborts, or -1.
long test_failure_update(int rank) {
  const char* v = std::getenv("PROPRIO_MPI_TEST_FAIL");  // NOLINT(concurrency-mt-unsafe)
  if (v == nullptr) return -1;
  int r = -1;
  long u = -1;
  if (std::sscanf(v, "%d:%ld", &r, &u) != 2 || r != rank) return -1;
  return u;
}

// The ranks must run the same training: every option but the threads (which change no bit),
// the MPI choices included. A rank given another batch size, K or exchange would send other
// messages than the rest expect and desynchronise the collectives (a hang or garbage), so a
// library caller that gives ranks different options gets one error on every rank instead.
void check_same_options(const OnlineLdaOptions& options, core::Communicator& comm) {
  OnlineLdaOptions o = options;
  o.threads = 1;
  core::require_same_on_every_rank(
      comm, core::fields_to_json(o).dump() + core::fields_to_json(o.mpi).dump(),
      "online LDA: the " + std::to_string(comm.size()) +
          " MPI ranks were given different training options (every option but the threads "
          "must be the same on every rank)");
}

}  // namespace

OnlineLdaResult train_online_lda(const CorpusShard& shard, const Corpus* heldout,
                                 const OnlineLdaOptions& options, core::Communicator& comm) {
  const Corpus& local = shard.documents;
  // Bad options or a held-out corpus (given to some ranks only) that one rank finds must stop
  // every rank, not leave the others waiting in the first collective.
  core::agree(comm, [&] {
    options.validate();
    if (shard.total_documents == 0) throw Error("online LDA: the training corpus is empty");
    if (local.num_words() < 1) throw Error("online LDA: the vocabulary is empty");
    check_heldout_words(heldout, local.num_words());
  });
  check_same_options(options, comm);
  const std::int64_t D =
      options.total_documents > 0 ? options.total_documents : shard.total_documents;
  // Split by topic, each rank draws and holds only its rows of lambda.
  OnlineLda lda = comm.size() > 1 && options.mpi.design == MpiLdaDesign::kByTopic
                      ? OnlineLda(options, local.num_words(), D, local.vocabulary(), comm)
                      : OnlineLda(options, local.num_words(), D, local.vocabulary());
  OnlineLdaResult result;
  OnlineLdaSummary& s = result.summary;
  s.threads = options.threads;
  s.kernel = lda.kernel();

  const HeldoutTrace heldout_trace(heldout, options);
  const bool trace = heldout_trace.active();
  // Only the ranks given the held-out corpus (rank 0 in `lda train`) score it, but split by topic
  // every rank takes part in gathering the model for it: the points where it is scored are the
  // same on every rank.
  std::int64_t traced[1] = {trace ? 1 : 0};
  comm.allreduce_max(traced);
  std::int64_t scored_at = -1;
  auto evaluate = [&] {
    lda.gather_topics(comm, trace || comm.rank() == 0);
    scored_at = lda.model().updates;
    if (trace) heldout_trace.evaluate(lda.model(), s);
  };
  if (traced[0] != 0) evaluate();

  std::int64_t counts[1] = {0};
  for (std::size_t d = 0; d < local.num_documents(); ++d) counts[0] += !local.document(d).empty();
  comm.allreduce_sum(counts);
  const std::int64_t nonempty = counts[0];
  const long fail_at = test_failure_update(comm.rank());
  std::int64_t iterations = 0;
  const auto B = static_cast<std::size_t>(options.batch_size);
  const auto total = static_cast<std::size_t>(shard.total_documents);
  for (int pass = 0; pass < options.passes; ++pass) {
    for (std::size_t b = 0; b < total; b += B) {
      if (s.updates == fail_at) {
        std::fprintf(stderr, "rank %d: aborting before update %ld (PROPRIO_MPI_TEST_FAIL)\n",
                     comm.rank(), fail_at);
        std::fflush(stderr);
        std::abort();
      }
      const auto t0 = Clock::now();
      const double c0 = process_cpu_seconds();
      const MiniBatchStats st = lda.update(shard, b, std::min(total, b + B), comm);
      s.seconds += since(t0);
      s.cpu_seconds += process_cpu_seconds() - c0;
      ++s.updates;
      s.documents += st.documents;
      s.tokens += st.tokens;
      s.capped += st.capped;
      iterations += st.estep_iterations;
      if (traced[0] != 0 && options.evaluate_every > 0 && s.updates % options.evaluate_every == 0) {
        evaluate();
      }
    }
    ++s.passes;
  }
  if (traced[0] != 0 && scored_at != lda.model().updates) evaluate();
  if (scored_at != lda.model().updates) lda.gather_topics(comm, comm.rank() == 0);
  const std::int64_t docs_run = nonempty * options.passes;
  s.mean_estep_iterations =
      docs_run > 0 ? static_cast<double>(iterations) / static_cast<double>(docs_run) : 0.0;
  result.phase_times = lda.phase_times();
  result.phase_times.ranks = comm.size();
  result.phase_times.rank = comm.rank();
  result.model = lda.release_model();
  result.summary.message = core::first_line(result.summary.brief());
  return result;
}

}  // namespace proprio::topics
