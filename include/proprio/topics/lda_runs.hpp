#pragma once
// The library calls behind `proprio lda ...` (thesis Ch 6, Appendix B): train a model on a corpus
// file, infer the topic proportions of a corpus into CSV, measure held-out perplexity, list each
// topic's words. Each reads its inputs, does the one job, writes its outputs and returns what it
// did with the record the CLI writes for --json (docs/formats/schemas/lda_*.schema.json).

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "proprio/core/fields.hpp"
#include "proprio/core/json_io.hpp"
#include "proprio/core/provenance.hpp"
#include "proprio/topics/batch_lda.hpp"
#include "proprio/topics/corpus.hpp"
#include "proprio/topics/corpus_io.hpp"
#include "proprio/topics/inference.hpp"
#include "proprio/topics/lda_model.hpp"
#include "proprio/topics/online_lda.hpp"
#include "proprio/topics/perplexity.hpp"

namespace proprio::topics {

inline constexpr core::ChoiceNames<CorpusFormat, 3> kCorpusFormatNames{
    {{"uci", CorpusFormat::kUci},
     {"ldac", CorpusFormat::kLdac},
     {"mm", CorpusFormat::kMatrixMarket}}};

/// Throws Error naming `where` when `corpus` is not over the model's words: another number of
/// words, or (when both name their words) another word at some index.
void check_corpus_matches_model(const LdaModel& model, const Corpus& corpus,
                                const std::filesystem::path& where);

enum class LdaMethod { kOnline, kBatch };
inline constexpr core::ChoiceNames<LdaMethod, 2> kLdaMethodNames{
    {{"online", LdaMethod::kOnline}, {"batch", LdaMethod::kBatch}}};

struct LdaTrainingOptions {
  std::filesystem::path corpus;  ///< training corpus, a directory or file (required)
  CorpusFormat format = CorpusFormat::kUci;
  std::filesystem::path heldout;  ///< held-out corpus in the same format, or none
  std::filesystem::path model;    ///< model file to write (docs/formats/lda-model.md), or none
  /// online (Hoffman et al. 2010; its perplexity traced on `heldout`) or batch (Blei et al. 2003;
  /// `heldout` scored once at the end).
  LdaMethod method = LdaMethod::kOnline;
  /// K, priors, threads and seed of both methods; batch size, learning rate and passes of online.
  OnlineLdaOptions online;
  /// online: checkpoint every N mini-batches to a file, resume from one (issue 16;
  /// train_online_lda). The checkpoint may be the file resumed from; it may be no input and not
  /// the model. One process only (not under mpirun).
  core::CheckpointOptions checkpointing;
  int max_iterations = 100;  ///< batch: EM iterations at most
  double tolerance = 1e-4;   ///< batch: relative change of the bound that stops EM

  /// Throws Error naming the first bad option.
  void validate() const;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v.choice(self.format, {"format", "Corpus format (docs/formats/corpus.md)"}, kCorpusFormatNames);
    v.choice(self.method, {"method", "online (Hoffman et al. 2010) or batch (Blei et al. 2003)"},
             kLdaMethodNames);
    v(self.max_iterations, {"max_iterations", "EM iterations (batch)", core::at_least(1)});
    v(self.tolerance,
      {"tolerance", "Relative change of the bound that stops batch EM", core::between(0, 1)});
  }
};

/// What batch training records: its summary, its speed over the corpus, the held-out perplexity.
struct LdaBatchRecord {
  BatchLdaSummary summary;
  double docs_per_s = 0.0;    ///< documents x iterations per second
  double tokens_per_s = 0.0;  ///< tokens x iterations per second
  std::optional<double> heldout_perplexity;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    BatchLdaSummary::describe(self.summary, v);
    v(self.docs_per_s, {"docs_per_s", "Documents x iterations per second"});
    v(self.tokens_per_s, {"tokens_per_s", "Tokens x iterations per second"});
    v(std::vector<PerplexityPoint>{}, {"perplexity_trace", "Empty: batch has no trace"});
    v(self.heldout_perplexity, {"heldout_perplexity", "Perplexity of the held-out corpus"});
  }
};

// NOLINTNEXTLINE(bugprone-exception-escape)
struct LdaTrainingResult {
  LdaModel model;
  /// The training summary's line (and the held-out perplexity of batch): what brief() returns.
  std::string text;
  std::string message;  ///< one line: what happened (the text's first line)
  [[nodiscard]] std::string brief() const { return text; }
  std::filesystem::path corpus;
  LdaMethod method = LdaMethod::kOnline;
  std::filesystem::path model_file;  ///< where the model was written ("" when not)
  std::int64_t documents_in_corpus = 0;
  std::int64_t words = 0;
  OnlineLdaOptions options;  ///< as used: alpha and eta resolved
  std::optional<OnlineLdaSummary> online;
  std::optional<LdaBatchRecord> batch;
  std::optional<int> ranks;          ///< MPI ranks, when more than one
  std::optional<MpiLdaOptions> mpi;  ///< how the ranks shared the work, when more than one
  /// Where this process's time went (online; each rank its own): a diagnostic that `lda train
  /// --phase-times` prints, not part of the record.
  LdaPhaseTimes phase_times;
  /// format "proprio.lda.train": the fields described below, from describe().
  core::Json document;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.corpus, {"corpus", "The training corpus"});
    v.choice(self.method, {"method", "online or batch"}, kLdaMethodNames);
    v(self.model_file, {"model", "The model file written"});
    v(self.documents_in_corpus, {"documents_in_corpus", "Documents in the corpus"});
    v(self.words, {"words", "Words of the vocabulary"});
    v(self.options, {"options", "The options used, alpha and eta resolved"});
    if (self.online) OnlineLdaSummary::describe(*self.online, v);
    if (self.batch) LdaBatchRecord::describe(*self.batch, v);
    v(self.ranks, {"ranks", "MPI ranks (with more than one)"});
    v(self.mpi, {"mpi", "How the MPI ranks shared the work (with more than one)"});
  }
};

/// Reads the corpora, trains (checkpointing and resuming as `checkpointing` says), writes the
/// model (when `model` is given).
LdaTrainingResult run_lda_training(const LdaTrainingOptions& options,
                                   const core::Provenance& provenance);

/// The same as one rank of a data-parallel job (issue 23), collective over `comm` (with one rank,
/// the call above). Online only. Every rank reads its shard of the corpus (read_corpus_shard);
/// the ranks compare the corpus's size and checksum, and every rank throws core::CollectiveError
/// (one message, the same everywhere) when they differ, when there are more ranks than documents,
/// or when any rank meets bad input. Rank 0 ends with the one-process model; split by topic (the
/// default) the other ranks' `model` has no lambda, replicated they all hold it (checked by a
/// checksum of lambda across them); rank 0 alone reads the held-out corpus, scores it and
/// writes the model file, atomically, after the last collective step, so that a job whose rank
/// dies leaves no model. The record adds "ranks" (with more than one).
LdaTrainingResult run_lda_training(const LdaTrainingOptions& options,
                                   const core::Provenance& provenance, core::Communicator& comm);

struct LdaInferenceOptions {
  std::filesystem::path model;   ///< model file (required)
  std::filesystem::path corpus;  ///< corpus of documents (required)
  CorpusFormat format = CorpusFormat::kUci;
  /// CSV to write (required): document (from 0), class (argmax theta, 6.1.4; -1 when empty),
  /// theta_0 .. theta_{K-1}.
  std::filesystem::path out;
  InferenceOptions inference;

  void validate() const;
};

// NOLINTNEXTLINE(bugprone-exception-escape)
struct LdaInferenceResult {
  std::filesystem::path model;
  std::filesystem::path corpus;
  std::filesystem::path out;
  InferenceSummary summary;
  core::Json document;  ///< format "proprio.lda.infer": the fields described below

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.model, {"model", "The model file"});
    v(self.corpus, {"corpus", "The corpus inferred"});
    v(self.out, {"out", "The CSV written"});
    InferenceSummary::describe(self.summary, v);
  }
};

LdaInferenceResult run_lda_inference(const LdaInferenceOptions& options,
                                     const core::Provenance& provenance);

struct LdaPerplexityOptions {
  std::filesystem::path corpus;  ///< held-out corpus (required)
  CorpusFormat format = CorpusFormat::kUci;
  std::filesystem::path model;   ///< a model file, or
  std::filesystem::path lambda;  ///< a K x W lambda CSV from another tool (lda export's layout)
  double alpha = 0.0;            ///< with `lambda`: the prior on topic proportions (> 0)
  double eta = 0.0;              ///< with `lambda`: the prior on topic words (0: alpha)
  PerplexityOptions perplexity;

  /// Throws Error unless exactly one of model and lambda is given, and alpha > 0 with lambda.
  void validate() const;
};

// NOLINTNEXTLINE(bugprone-exception-escape)
struct LdaPerplexityResult {
  PerplexityResult perplexity;
  std::filesystem::path model;  ///< the model file, or the lambda CSV
  std::filesystem::path corpus;
  double alpha = 0.0;   ///< the model's prior on topic proportions
  core::Json document;  ///< format "proprio.lda.perplexity": the fields described below
  std::string message;  ///< one line: what happened (brief()'s first line)
  [[nodiscard]] std::string brief() const;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.model, {"model", "The model file, or the lambda CSV"});
    v(self.corpus, {"corpus", "The held-out corpus"});
    PerplexityResult::describe(self.perplexity, v);
    v(self.alpha, {"alpha", "The model's prior on topic proportions"});
  }
};

LdaPerplexityResult run_lda_perplexity(const LdaPerplexityOptions& options,
                                       const core::Provenance& provenance);

/// The `top` most probable words of each topic: the listing's lines ("topic k: w w ...") and the
/// record (format "proprio.lda.topics"), under the Summary convention (core::Summary): brief() is
/// what the CLI prints (`lines`, each ended by '\n'), `message` its first line.
// NOLINTNEXTLINE(bugprone-exception-escape)
struct LdaTopWords {
  struct Word {
    std::string word;  ///< its name, or its id when the model has no vocabulary
    int id = 0;
    double probability = 0.0;  ///< beta_kw
    template <class Self, class Visitor>
    static void describe(Self& self, Visitor& v) {
      v(self.word, {"word", "The word"});
      v(self.id, {"id", "Its index in the vocabulary"});
      v(self.probability, {"probability", "beta_kw"});
    }
  };
  struct Topic {
    int topic = 0;
    std::vector<Word> words;  ///< most probable first
    template <class Self, class Visitor>
    static void describe(Self& self, Visitor& v) {
      v(self.topic, {"topic", "The topic's index"});
      v(self.words, {"words", "Its most probable words"});
    }
  };
  std::vector<std::string> lines;
  std::filesystem::path model;
  std::vector<Topic> topics;
  core::Json document;  ///< format "proprio.lda.topics": the fields described below
  std::string message;  ///< one line: brief()'s first
  [[nodiscard]] std::string brief() const {
    std::string text;
    for (const std::string& line : lines) text += line + '\n';
    return text;
  }

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.model, {"model", "The model file"});
    v(self.topics, {"topics", "Each topic's most probable words"});
  }
};
LdaTopWords run_lda_top_words(const std::filesystem::path& model, int top,
                              const core::Provenance& provenance);

}  // namespace proprio::topics
