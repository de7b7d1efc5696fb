#pragma once
// Online variational Bayes for LDA (Hoffman, Blei & Bach 2010; thesis B.1.2 "Online LDA",
// eq B.23-B.24): the corpus arrives in mini-batches; each mini-batch's E-step gives sufficient
// statistics that, scaled by D / |batch|, form lambda-hat, and
// lambda <- (1 - rho_t) lambda + rho_t lambda-hat with rho_t = (tau0 + t)^-kappa, t = 1, 2, ...
// counting this update, as scikit-learn does (Hoffman's reference code counts from t = 0: its
// tau0 is ours + 1). The thesis prints the exponent without its minus sign.

#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "proprio/core/checkpoint.hpp"
#include "proprio/core/communicator.hpp"
#include "proprio/core/fields.hpp"
#include "proprio/topics/corpus.hpp"
#include "proprio/topics/corpus_io.hpp"
#include "proprio/topics/estep_options.hpp"
#include "proprio/topics/lda_model.hpp"
#include "proprio/topics/perplexity.hpp"

namespace proprio::topics {

/// How a data-parallel run (issue 23; docs/results/mpi.md) shares its work among MPI ranks. Every
/// choice gives the one-process model bit for bit (tested): they exist so that the designs can be
/// measured against each other from the same binary. One process ignores them.
enum class MpiLdaDesign {
  kByTopic,     ///< rank r owns topic rows mpi_topic_rows(K, P, r) of lambda and their M-step
  kReplicated,  ///< every rank holds the whole lambda and runs the whole M-step
};
inline constexpr core::ChoiceNames<MpiLdaDesign, 2> kMpiLdaDesignNames{
    {{"by-topic", MpiLdaDesign::kByTopic}, {"replicated", MpiLdaDesign::kReplicated}}};
/// How a mini-batch's E-step is dealt to the ranks.
enum class MpiLdaDealing {
  kByCost,  ///< mpi_deal_by_cost of (distinct words + 2) x the previous pass's iterations
  kModulo,  ///< document d to rank d mod P
};
inline constexpr core::ChoiceNames<MpiLdaDealing, 2> kMpiLdaDealingNames{
    {{"cost", MpiLdaDealing::kByCost}, {"modulo", MpiLdaDealing::kModulo}}};
/// What the ranks exchange a mini-batch.
enum class MpiLdaExchange {
  /// 2 collectives a batch split by topic, 1 replicated: the next batch's documents travel with
  /// this batch's E-step output, and the sizes are known beforehand (docs/results/mpi.md, "The
  /// lean exchange").
  kLean,
  /// The earlier exchange: three allgathers a batch (documents, beta rows, E-step output), each
  /// with its exchange of sizes (6 collectives; replicated 4).
  kThree,
};
inline constexpr core::ChoiceNames<MpiLdaExchange, 2> kMpiLdaExchangeNames{
    {{"lean", MpiLdaExchange::kLean}, {"three", MpiLdaExchange::kThree}}};

/// The data-parallel choices (above), defaults the measured best. Not part of OnlineLdaOptions'
/// description (its JSON and a checkpoint's identity): like the thread count, they change no bit
/// of the model. `lda train` binds them as flags and records them with "ranks".
struct MpiLdaOptions {
  MpiLdaDesign design = MpiLdaDesign::kByTopic;
  MpiLdaDealing dealing = MpiLdaDealing::kByCost;
  MpiLdaExchange exchange = MpiLdaExchange::kLean;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v.choice(self.design,
             {"mpi_design", "Under mpirun: by-topic (each rank its topic rows) or replicated"},
             kMpiLdaDesignNames);
    v.choice(self.dealing,
             {"mpi_dealing", "Under mpirun: the E-step dealt to ranks by cost or by d mod ranks"},
             kMpiLdaDealingNames);
    v.choice(
        self.exchange,
        {"mpi_exchange", "Under mpirun: lean (2 collectives a batch) or three (the earlier 6)"},
        kMpiLdaExchangeNames);
  }
};

struct OnlineLdaOptions {
  int num_topics = 100;    ///< K
  int batch_size = 256;    ///< documents per mini-batch (the thesis uses 50 frames in 6.3.3)
  double tau0 = 1.0;       ///< >= 0; down-weights the first updates
  double kappa = 0.7;      ///< in (0.5, 1] for convergence
  double alpha = 0.0;      ///< prior on theta; 0 means 1/K
  double eta = 0.0;        ///< prior on beta; 0 means 1/K
  int passes = 1;          ///< times through the corpus
  int threads = 1;         ///< the result does not depend on it
  std::uint64_t seed = 1;  ///< lambda's start, Gamma(100, 1/100), and the E-step's random gamma
  /// D of eq B.23; 0 means the training corpus's size.
  std::int64_t total_documents = 0;
  /// gamma starts at random, Gamma(100, 1/100), as scikit-learn and gensim train.
  EStepOptions estep{100, 1e-3, GammaInit::kRandomGamma};
  /// Data-parallel runs only (not in describe(): it changes no bit of the model).
  MpiLdaOptions mpi;
  /// With a held-out corpus: its perplexity every this many mini-batches (and at the start and
  /// end); 0 = only at the start and the end.
  int evaluate_every = 0;
  PerplexityOptions evaluation;  ///< how the held-out perplexity is measured

  /// Throws Error naming the first bad option.
  void validate() const;
  [[nodiscard]] double resolved_alpha() const { return alpha > 0 ? alpha : 1.0 / num_topics; }
  [[nodiscard]] double resolved_eta() const { return eta > 0 ? eta : 1.0 / num_topics; }

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.num_topics, {"topics", "Number of topics K", core::between(1, 100000), "k"});
    v(self.batch_size, {"batch", "Documents per mini-batch", core::at_least(1)});
    v(self.tau0,
      {"tau0", "Learning-rate offset: rho_t = (tau0 + t)^-kappa", core::finite_at_least(0)});
    v(self.kappa, {"kappa", "Learning-rate decay", core::Bounds{0.5, 1.0, true}});
    v(self.alpha, {"alpha", "Prior on topic proportions (0: 1/K)", core::between(0, kMaxLdaPrior)});
    v(self.eta, {"eta", "Prior on topic words (0: 1/K)", core::between(0, kMaxLdaPrior)});
    v(self.passes, {"passes", "Passes over the corpus (online)", core::at_least(1)});
    v(self.threads,
      {"threads", "Threads (the model does not depend on it)", core::between(1, 256)});
    v(self.seed, {"seed", "Random seed"});
    v(self.evaluate_every,
      {"evaluate_every",
       "With a held-out corpus: its perplexity every this many mini-batches (0: start and end)",
       core::at_least(0)});
    v(self.estep.max_iterations,
      {"estep_max_iterations", "E-step: updates of a document's gamma at most", core::at_least(1)});
    v(self.estep.tolerance,
      {"estep_tolerance", "E-step: mean absolute change of gamma that stops it",
       core::finite_at_least(0)});
  }
};

/// What one mini-batch update did.
struct MiniBatchStats {
  std::int64_t documents = 0;
  std::int64_t tokens = 0;
  double rho = 0.0;
  std::int64_t estep_iterations = 0;  ///< summed over the documents
  std::int64_t capped = 0;            ///< documents that hit max_iterations
};

/// A point of the perplexity trace (thesis Fig 6-7).
struct PerplexityPoint {
  std::int64_t updates = 0;
  std::int64_t documents_seen = 0;
  double perplexity = 0.0;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.updates, {"updates", "Mini-batch updates so far"});
    v(self.documents_seen, {"documents_seen", "Documents processed so far"});
    v(self.perplexity, {"perplexity", "Held-out perplexity"});
  }
};

struct OnlineLdaSummary {
  std::int64_t updates = 0;
  int passes = 0;
  std::int64_t documents = 0;  ///< documents processed, over all passes
  std::int64_t tokens = 0;     ///< tokens processed, over all passes
  double seconds = 0.0;        ///< training time (wall clock), evaluations excluded
  double cpu_seconds = 0.0;    ///< processor time of all threads during training
  double evaluation_seconds = 0.0;
  double mean_estep_iterations = 0.0;  ///< per non-empty document
  std::int64_t capped = 0;             ///< document E-steps that hit max_iterations
  int threads = 1;
  std::string kernel;                  ///< the instruction set the E-step ran on
  std::vector<PerplexityPoint> trace;  ///< empty without a held-out corpus

  [[nodiscard]] double documents_per_second() const {
    return seconds > 0 ? documents / seconds : 0;
  }
  [[nodiscard]] double tokens_per_second() const { return seconds > 0 ? tokens / seconds : 0; }
  /// The last point's perplexity; none without a held-out corpus.
  [[nodiscard]] std::optional<double> heldout_perplexity() const {
    if (trace.empty()) return std::nullopt;
    return trace.back().perplexity;
  }
  std::string message;  ///< one line: what happened (brief()'s first line)
  [[nodiscard]] std::string brief() const;

  /// Output only: speeds and the held-out perplexity are derived.
  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.seconds, {"seconds", "Training time (wall clock), evaluations excluded"});
    v(self.cpu_seconds, {"cpu_seconds", "Processor time of all threads during training"});
    v(self.documents_per_second(), {"docs_per_s", "Documents processed per second"});
    v(self.tokens_per_second(), {"tokens_per_s", "Tokens processed per second"});
    v(self.documents, {"documents", "Documents processed, over all passes"});
    v(self.tokens, {"tokens", "Tokens processed, over all passes"});
    v(self.updates, {"updates", "Mini-batch updates"});
    v(self.passes, {"passes", "Passes over the corpus"});
    v(self.threads, {"threads", "Threads of the E-step"});
    v(self.kernel, {"kernel", "The instruction set the E-step ran on"});
    v(self.mean_estep_iterations,
      {"mean_estep_iterations", "E-step iterations per non-empty document"});
    v(self.capped, {"estep_capped", "Document E-steps that hit max_iterations"});
    v(self.evaluation_seconds, {"evaluation_seconds", "Time spent scoring the held-out corpus"});
    v(self.trace, {"perplexity_trace", "Held-out perplexity after updates (Fig 6-7)"});
    v(self.heldout_perplexity(), {"heldout_perplexity", "The trace's last perplexity"});
  }
};

/// Where an OnlineLda's time went (per process): processor seconds in each phase of its updates:
/// E-step, exp(E[log beta]), sufficient statistics, M-step (with the topic sums) and communication
/// (with the batch's assembly), and the number of updates. Beside them, wall seconds: the E-step,
/// and the wait in the collective that follows it (the other ranks' longer E-steps); and the
/// E-step's imbalance: summed over the updates, the slowest rank's E-step processor time minus
/// this rank's (the wait an idle machine would see). A diagnostic of the benchmarks
/// (bench/bench_mpi.py reads it from `lda train --phase-times`), not part of the record.
struct LdaPhaseTimes {
  int ranks = 1;  ///< the processes of the run
  int rank = 0;   ///< this one's rank
  std::int64_t updates = 0;
  double estep = 0, beta = 0, statistics = 0, mstep = 0, communication = 0;
  double estep_wall = 0, wait_wall = 0, estep_imbalance = 0;
  /// Wall and processor seconds in the data-parallel update's collectives (all of them, waiting
  /// included: `communication` minus collective_cpu is the batch's assembly, packing and
  /// unpacking alone), and the number of MPI collective calls they made (an allgather of unknown
  /// sizes is two).
  double collective_wall = 0;
  double collective_cpu = 0;
  std::int64_t collectives = 0;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.ranks, {"ranks", "Processes of the run"});
    v(self.updates, {"updates", "Mini-batch updates"});
    v(self.estep, {"estep", "E-step, processor s"});
    v(self.beta, {"beta", "exp(E[log beta]) of the batches' words, processor s"});
    v(self.statistics, {"statistics", "Sufficient statistics, processor s"});
    v(self.mstep, {"mstep", "M-step with the topic sums, processor s"});
    v(self.communication, {"communication", "Exchange and batch assembly, processor s"});
    v(self.rank, {"rank", "This process's rank"});
    v(self.estep_wall, {"estep_wall", "E-step, wall s"});
    v(self.wait_wall, {"wait_wall", "Wait at the collective after the E-step, wall s"});
    v(self.estep_imbalance,
      {"estep_imbalance", "Slowest rank's E-step minus this rank's, processor s"});
    v(self.collective_wall, {"collective_wall", "Inside the collectives, wall s"});
    v(self.collective_cpu, {"collective_cpu", "Inside the collectives, processor s"});
    v(self.collectives, {"collectives", "MPI collective calls"});
  }
};

struct OnlineLdaResult {
  LdaModel model;
  OnlineLdaSummary summary;
  LdaPhaseTimes phase_times;  ///< where this process's time went (a diagnostic)
};

/// The online learner as a stream consumer: a robot feeds it mini-batches as they come.
class OnlineLda {
 public:
  /// A fresh model over `num_words` words for a stream of about `total_documents` documents.
  OnlineLda(const OnlineLdaOptions& options, std::int32_t num_words, std::int64_t total_documents,
            std::vector<std::string> vocabulary = {});
  /// Continues training `model` (its priors, tau0, kappa and update count are kept).
  OnlineLda(LdaModel model, const OnlineLdaOptions& options);
  /// A fresh model split by topic over the ranks of `comm` (issue 23; the updates with `comm` run
  /// as after distribute_by_topic): this rank draws and holds only its rows mpi_topic_rows(K,
  /// size, rank) of the starting lambda (the one-process draws, bit for bit), never K x W;
  /// model() has no lambda until gather_topics().
  OnlineLda(const OnlineLdaOptions& options, std::int32_t num_words, std::int64_t total_documents,
            std::vector<std::string> vocabulary, core::Communicator& comm);
  OnlineLda(OnlineLda&&) noexcept;
  OnlineLda& operator=(OnlineLda&&) noexcept;
  ~OnlineLda();

  /// One update with documents [begin, end) of `corpus` as the mini-batch (eq B.23-B.24).
  /// Throws Error when the corpus's W differs from the model's.
  MiniBatchStats update(const Corpus& corpus, std::size_t begin, std::size_t end);

  /// The same update as one rank of a data-parallel job (issue 23), collective: the mini-batch is
  /// documents [begin, end) of the whole corpus, of which this rank holds `shard`'s. The ranks
  /// exchange their documents' word ids, each runs the E-step on its share of the batch (dealt by
  /// cost, options.mpi.dealing) with its threads, they exchange what the E-step leaves (exp E[log
  /// theta] per document and the weight of each entry) and every rank sums the sufficient
  /// statistics in document order and applies the M-step: every rank's model is the one-process
  /// model, bit for bit. With the lean exchange (options.mpi.exchange, the default) the word ids
  /// of the next batch, predicted as [end, end + the widest batch so far) or from 0 after the
  /// corpus's end, travel with this batch's E-step output; a call with another range gathers its
  /// documents first (the same model, one collective more).
  ///
  /// After distribute_by_topic(), the update is split by topic instead: rank r owns the
  /// contiguous block of topic rows mpi_topic_rows(K, size, r) of lambda; it computes exp(E[log
  /// beta]) of the batch's words on its rows, the ranks allgather that V_B x K block for their
  /// E-steps, then (after the same exchange of the E-step's output) each rank sums the sufficient
  /// statistics and applies the M-step (eq B.23-B.24) on its own rows only. Same bits as one
  /// process; the E-step needs only the V_B x K block of the batch's words. model() has no lambda
  /// (0 x 0), or a stale one, until gather_topics().
  MiniBatchStats update(const CorpusShard& shard, std::size_t begin, std::size_t end,
                        core::Communicator& comm);

  /// Switches the updates with a communicator to the by-topic split above (collective; keeps
  /// this rank's rows of the current model and drops the others).
  void distribute_by_topic(core::Communicator& comm);
  /// Gathers the ranks' topic rows to the ranks that pass `whole_here` (point to point, blocks of
  /// at most 64 MB), so that model() is whole there; the others keep their rows only and model()
  /// has no lambda on them (collective; a no-op when the updates are not split by topic).
  void gather_topics(core::Communicator& comm, bool whole_here = true);
  /// Moves the model out (to be called once, after training: the learner keeps no lambda).
  LdaModel release_model();
  /// Processor seconds this process spent in each phase of its updates so far (LdaPhaseTimes).
  using PhaseTimes = LdaPhaseTimes;
  [[nodiscard]] PhaseTimes phase_times() const;

  [[nodiscard]] const LdaModel& model() const;
  [[nodiscard]] const char* kernel() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  void finish_update(MiniBatchStats& stats);
};

/// Rank r's topic rows [first, second) of K split into `ranks` contiguous blocks (rows r K / ranks
/// to (r + 1) K / ranks; empty for some ranks when K < ranks).
std::pair<int, int> mpi_topic_rows(int num_topics, int ranks, int rank);

/// Deals documents of the given E-step costs to `ranks` ranks, deterministically (every rank
/// computes the same): largest cost first, each to the least loaded rank so far (ties: fewer
/// documents, then the lower rank). Returns each document's rank.
std::vector<int> mpi_deal_by_cost(std::span<const std::int64_t> costs, int ranks);

/// Trains on `corpus` in order, `passes` times, mini-batch by mini-batch.
OnlineLdaResult train_online_lda(const Corpus& corpus, const OnlineLdaOptions& options);
/// The same, tracing the held-out perplexity of `heldout` (thesis Fig 6-7).
OnlineLdaResult train_online_lda(const Corpus& corpus, const Corpus& heldout,
                                 const OnlineLdaOptions& options);

/// The same, checkpointing and resuming (issue 16): with `checkpointing.checkpoint`, the state
/// (lambda, the update count, where the pass is, the summary and trace so far) is written
/// atomically every `checkpointing.every` mini-batches (core/checkpoint.hpp, kind "online_lda");
/// with `checkpointing.resume`, training continues from that state. A run killed at any moment and
/// resumed from its last checkpoint ends with the model of the uninterrupted run, bit for bit (the
/// summary's times aside). Throws Error naming the checkpoint when it was written over another
/// corpus (or held-out corpus) or with other options (threads aside: they change nothing).
/// `heldout` may be null.
OnlineLdaResult train_online_lda(const Corpus& corpus, const Corpus* heldout,
                                 const OnlineLdaOptions& options,
                                 const core::CheckpointOptions& checkpointing);

/// A checksum (FNV-1a, 64 bits) of the corpus's documents and vocabulary: a checkpoint's input.
std::uint64_t corpus_checksum(const Corpus& corpus);

/// Data-parallel training (issue 23), collective: every rank of `comm` passes its shard of the
/// same corpus (read_corpus_shard(..., comm.rank(), comm.size())); the mini-batches are the
/// one-process run's, and rank 0 (and every rank given `heldout`) returns the model
/// train_online_lda gives on the whole corpus, bit for bit. Split by topic (options.mpi.design, the
/// default, with 2 ranks or more) the other ranks hold only their topic rows while training and
/// return the model without lambda (0 x 0); replicated, every rank returns the whole model.
/// `heldout` (may be null, and given on some ranks only) is scored on the ranks that have it, out
/// of the training time. The summary's documents and tokens count the whole corpus. Environment
/// PROPRIO_MPI_TEST_FAIL="RANK:UPDATE" (tests only) makes rank RANK abort before mini-batch UPDATE
/// (from 0), as a crashed process would.
OnlineLdaResult train_online_lda(const CorpusShard& shard, const Corpus* heldout,
                                 const OnlineLdaOptions& options, core::Communicator& comm);

}  // namespace proprio::topics
