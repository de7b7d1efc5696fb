#include "proprio/topics/lda_runs.hpp"

#include <cstdio>
#include <cstring>
#include <limits>
#include <optional>
#include <string_view>
#include <vector>

#include "proprio/core/checkpoint.hpp"
#include "proprio/core/csv.hpp"
#include "proprio/core/error.hpp"
#include "proprio/core/files.hpp"
#include "proprio/topics/batch_lda.hpp"
#include "proprio/topics/lda_model_io.hpp"

namespace proprio::topics {
namespace fs = std::filesystem;
namespace {

// What reading this corpus reads (the directory or file named, the corpus file, the vocabulary):
// none of it may be an output of the run.
std::vector<fs::path> corpus_inputs(const fs::path& corpus, CorpusFormat format) {
  const CorpusFiles files = find_corpus_files(corpus, format);
  return {corpus, files.file, files.vocabulary};
}

// What training reads: the corpus's files and the held-out corpus's.
std::vector<fs::path> training_inputs(const LdaTrainingOptions& options) {
  std::vector<fs::path> inputs = corpus_inputs(options.corpus, options.format);
  if (!options.heldout.empty()) {
    const auto more = corpus_inputs(options.heldout, options.format);
    inputs.insert(inputs.end(), more.begin(), more.end());
  }
  return inputs;
}

// The held-out corpus; Error naming it unless it has the training corpus's `words`.
Corpus read_heldout(const LdaTrainingOptions& options, std::int32_t words) {
  Corpus heldout = read_corpus(options.heldout, options.format);
  if (heldout.num_words() != words) {
    throw Error::in_file(options.heldout, "has " + std::to_string(heldout.num_words()) +
                                              " words, the training corpus " +
                                              std::to_string(words));
  }
  return heldout;
}

// The options as they were used: alpha and eta resolved (0 means 1/K).
OnlineLdaOptions used_options(OnlineLdaOptions o) {
  o.alpha = o.resolved_alpha();
  o.eta = o.resolved_eta();
  return o;
}

// The record's fields every method shares.
void describe_run(const LdaTrainingOptions& options, std::int64_t documents, std::int64_t words,
                  LdaTrainingResult& r) {
  r.corpus = options.corpus;
  r.method = options.method;
  r.model_file = options.model;
  r.documents_in_corpus = documents;
  r.words = words;
  r.options = used_options(options.online);
}

void train_online(const LdaTrainingOptions& o, const Corpus& corpus, const Corpus* heldout,
                  LdaTrainingResult& r) {
  const OnlineLdaResult t = train_online_lda(corpus, heldout, o.online, o.checkpointing);
  const OnlineLdaSummary& s = t.summary;
  r.text = s.brief();
  r.online = s;
  r.phase_times = t.phase_times;
  r.model = t.model;
}

void train_batch(const LdaTrainingOptions& o, const Corpus& corpus, const Corpus* heldout,
                 LdaTrainingResult& r) {
  BatchLdaOptions b;
  b.num_topics = o.online.num_topics;
  b.alpha = o.online.alpha;
  b.eta = o.online.eta;
  b.max_iterations = o.max_iterations;
  b.tolerance = o.tolerance;
  b.threads = o.online.threads;
  b.seed = o.online.seed;
  b.estep = o.online.estep;
  const BatchLdaResult t = train_batch_lda(corpus, b);
  const BatchLdaSummary& s = t.summary;
  r.text = s.brief();
  LdaBatchRecord& rec = r.batch.emplace();
  rec.summary = s;
  const double docs = static_cast<double>(corpus.num_documents()) * s.iterations;
  const double tokens = static_cast<double>(corpus.num_tokens()) * s.iterations;
  rec.docs_per_s = s.seconds > 0 ? docs / s.seconds : 0.0;
  rec.tokens_per_s = s.seconds > 0 ? tokens / s.seconds : 0.0;
  r.model = t.model;
  if (heldout != nullptr) {
    PerplexityOptions po;
    po.threads = b.threads;
    const double p = perplexity(r.model, *heldout, po).perplexity;
    char line[64];
    std::snprintf(line, sizeof line, "\nheld-out perplexity %g", p);
    r.text += line;
    rec.heldout_perplexity = p;
  }
}

}  // namespace

void check_corpus_matches_model(const LdaModel& model, const Corpus& corpus,
                                const std::filesystem::path& where) {
  if (corpus.num_words() != model.num_words()) {
    throw Error::in_file(where, "has " + std::to_string(corpus.num_words()) +
                                    " words but the model has " +
                                    std::to_string(model.num_words()));
  }
  if (model.vocabulary.empty() || corpus.vocabulary().empty() ||
      model.vocabulary == corpus.vocabulary())
    return;
  for (std::size_t w = 0; w < model.vocabulary.size(); ++w) {
    if (model.vocabulary[w] != corpus.vocabulary()[w]) {
      throw Error::in_file(where, "word " + std::to_string(w + 1) + " is '" +
                                      corpus.vocabulary()[w] + "' but the model's is '" +
                                      model.vocabulary[w] + "'");
    }
  }
}

void LdaTrainingOptions::validate() const {
  if (corpus.empty()) throw Error("lda train: the corpus is required");
  core::check_field_bounds(*this, "lda train");
  core::check_field_bounds(online, "lda train");
  if (method == LdaMethod::kOnline) online.validate();
  checkpointing.validate();
  const bool checkpoints = !checkpointing.checkpoint.empty() || !checkpointing.resume.empty();
  if (checkpoints && method != LdaMethod::kOnline) {
    throw Error("lda train: --checkpoint and --resume are for the online method");
  }
}

LdaTrainingResult run_lda_training(const LdaTrainingOptions& options,
                                   const core::Provenance& provenance) {
  options.validate();
  const std::vector<fs::path> inputs = training_inputs(options);
  core::require_output_not_input(options.model, inputs, "--model");
  if (!options.checkpointing.checkpoint.empty()) {
    std::vector<fs::path> not_checkpoint = inputs;
    not_checkpoint.push_back(options.model);
    core::require_output_not_input(options.checkpointing.checkpoint, not_checkpoint,
                                   "--checkpoint");
  }
  if (!options.checkpointing.resume.empty()) {
    core::require_output_not_input(options.model, {options.checkpointing.resume}, "--model");
  }
  const Corpus corpus = read_corpus(options.corpus, options.format);
  std::optional<Corpus> heldout;
  if (!options.heldout.empty()) {
    heldout = read_heldout(options, corpus.num_words());
  }
  LdaTrainingResult r;
  describe_run(options, static_cast<std::int64_t>(corpus.num_documents()), corpus.num_words(), r);
  const Corpus* held = heldout ? &*heldout : nullptr;
  if (options.method == LdaMethod::kOnline) {
    train_online(options, corpus, held, r);
  } else {
    train_batch(options, corpus, held, r);
  }
  r.document = core::result_document("proprio.lda.train", 1, provenance);
  r.message = core::first_line(r.text);
  core::fields_into_json(r, r.document);
  if (!options.model.empty()) save_lda_model(r.model, options.model);
  return r;
}

namespace {

// FNV-1a over the bytes of lambda: the ranks' models compared after training.
std::int64_t lambda_checksum(const Eigen::MatrixXd& lambda) {
  const std::uint64_t h =
      core::fnv1a(std::string_view(reinterpret_cast<const char*>(lambda.data()),
                                   static_cast<std::size_t>(lambda.size()) * sizeof(double)));
  std::int64_t out = 0;
  std::memcpy(&out, &h, sizeof out);
  return out;
}

}  // namespace

LdaTrainingResult run_lda_training(const LdaTrainingOptions& options,
                                   const core::Provenance& provenance, core::Communicator& comm) {
  if (comm.size() == 1) {
    LdaTrainingResult r;
    core::agree(comm, [&] { r = run_lda_training(options, provenance); });
    return r;
  }
  const int rank = comm.rank();
  const int ranks = comm.size();
  CorpusShard shard;
  std::optional<Corpus> heldout;
  core::agree(comm, [&] {
    options.validate();
    if (options.method != LdaMethod::kOnline) {
      throw Error("lda train: only the online method runs on several MPI ranks (--method online)");
    }
    if (!options.checkpointing.checkpoint.empty() || !options.checkpointing.resume.empty()) {
      throw Error("lda train: --checkpoint and --resume run in one process, not under mpirun");
    }
    core::require_output_not_input(options.model, training_inputs(options), "--model");
    shard = read_corpus_shard(options.corpus, options.format, rank, ranks);
    if (rank == 0 && !options.heldout.empty()) {
      heldout = read_heldout(options, shard.documents.num_words());
    }
  });
  // The ranks must have read the same corpus: its size, checksum, D, W and tokens.
  std::int64_t checksum = 0;
  std::memcpy(&checksum, &shard.checksum, sizeof checksum);
  std::vector<std::int64_t> lo{static_cast<std::int64_t>(shard.bytes), checksum,
                               shard.total_documents, shard.documents.num_words(),
                               shard.total_tokens};
  std::vector<std::int64_t> hi = lo;
  comm.allreduce_min(lo);
  comm.allreduce_max(hi);
  if (lo != hi) {
    throw core::CollectiveError(
        options.corpus.string() + ": the " + std::to_string(ranks) +
        " MPI ranks read different corpora (sizes " + std::to_string(lo[0]) + " to " +
        std::to_string(hi[0]) + " bytes, " + std::to_string(lo[2]) + " to " +
        std::to_string(hi[2]) + " documents" + (lo[1] != hi[1] ? ", checksums differ" : "") +
        "): give every rank the same file");
  }
  if (shard.total_documents < ranks) {
    throw core::CollectiveError(
        options.corpus.string() + ": " + std::to_string(shard.total_documents) + " documents for " +
        std::to_string(ranks) + " MPI ranks: run at most one rank per document");
  }
  LdaTrainingResult r;
  describe_run(options, shard.total_documents, shard.documents.num_words(), r);
  OnlineLdaResult t = train_online_lda(shard, heldout ? &*heldout : nullptr, options.online, comm);
  r.text = t.summary.brief();
  r.online = t.summary;
  r.ranks = ranks;
  r.phase_times = t.phase_times;
  if (ranks > 1) r.mpi = options.online.mpi;
  r.model = std::move(t.model);
  r.document = core::result_document("proprio.lda.train", 1, provenance);
  r.message = core::first_line(r.text);
  core::fields_into_json(r, r.document);
  // The last collective step: the ranks that hold the whole model (rank 0; every rank when the
  // M-step is replicated; split by topic the others hold none) hold the same one, or the job
  // stops here.
  ensure(rank != 0 || r.model.lambda.size() > 0, "lda train: rank 0 ended without the model");
  const bool whole = r.model.lambda.size() > 0;
  const std::int64_t sum = whole ? lambda_checksum(r.model.lambda) : 0;
  std::vector<std::int64_t> mlo{whole ? sum : std::numeric_limits<std::int64_t>::max()};
  std::vector<std::int64_t> mhi{whole ? sum : std::numeric_limits<std::int64_t>::min()};
  comm.allreduce_min(mlo);
  comm.allreduce_max(mhi);
  ensure(mlo == mhi, "lda train: the MPI ranks ended with different models");
  core::agree(comm, [&] {
    if (rank == 0 && !options.model.empty()) save_lda_model(r.model, options.model);
  });
  return r;
}

void LdaInferenceOptions::validate() const {
  if (model.empty() || corpus.empty() || out.empty())
    throw Error("lda infer: the model, the corpus and the output CSV are required");
  inference.validate();
}

LdaInferenceResult run_lda_inference(const LdaInferenceOptions& options,
                                     const core::Provenance& provenance) {
  options.validate();
  std::vector<fs::path> inputs = corpus_inputs(options.corpus, options.format);
  inputs.push_back(options.model);
  core::require_output_not_input(options.out, inputs, "--out");
  const LdaModel model = load_lda_model(options.model);
  const Corpus corpus = read_corpus(options.corpus, options.format);
  check_corpus_matches_model(model, corpus, options.corpus);
  const InferenceResult r = infer_topics(model, corpus, options.inference);
  const Eigen::MatrixXd theta = r.theta();
  const auto cls = r.classify();
  std::vector<std::string> header{"document", "class"};
  for (int k = 0; k < model.num_topics(); ++k) {
    std::string h = "theta_";
    h += std::to_string(k);
    header.push_back(h);
  }
  std::vector<std::vector<std::optional<double>>> rows(corpus.num_documents());
  for (std::size_t d = 0; d < rows.size(); ++d) {
    auto& row = rows[d];
    row.push_back(static_cast<double>(d));
    row.push_back(static_cast<double>(cls[d]));
    for (int k = 0; k < model.num_topics(); ++k)
      row.push_back(theta(static_cast<Eigen::Index>(d), k));
  }
  core::write_file_atomic(options.out, core::format_csv(header, rows));
  LdaInferenceResult out;
  out.model = options.model;
  out.corpus = options.corpus;
  out.out = options.out;
  out.summary = r.summary;
  out.document = core::result_document("proprio.lda.infer", 1, provenance);
  core::fields_into_json(out, out.document);
  return out;
}

void LdaPerplexityOptions::validate() const {
  if (corpus.empty()) throw Error("lda perplexity: the corpus is required");
  if (model.empty() == lambda.empty())
    throw Error("lda perplexity: give exactly one of --model and --lambda");
  if (!lambda.empty() && !(alpha > 0 && std::isfinite(alpha)))
    throw Error("lda perplexity: --lambda needs --alpha > 0");
  if (!(eta >= 0 && std::isfinite(eta))) throw Error("lda perplexity: --eta must be >= 0");
  perplexity.validate();
}

std::string LdaPerplexityResult::brief() const {
  char line[160];
  std::snprintf(line, sizeof line, "perplexity %.6g (%s, %lld tokens scored in %lld documents)",
                perplexity.perplexity, std::string(to_string(perplexity.method)).c_str(),
                static_cast<long long>(perplexity.tokens),
                static_cast<long long>(perplexity.documents));
  return line;
}

LdaPerplexityResult run_lda_perplexity(const LdaPerplexityOptions& options,
                                       const core::Provenance& provenance) {
  options.validate();
  const LdaModel model = !options.model.empty()
                             ? load_lda_model(options.model)
                             : read_lambda_csv(options.lambda, options.alpha,
                                               options.eta > 0 ? options.eta : options.alpha);
  const Corpus corpus = read_corpus(options.corpus, options.format);
  check_corpus_matches_model(model, corpus, options.corpus);
  LdaPerplexityResult out;
  out.perplexity = perplexity(model, corpus, options.perplexity);
  out.model = options.model.empty() ? options.lambda : options.model;
  out.corpus = options.corpus;
  out.alpha = model.alpha;
  out.document = core::result_document("proprio.lda.perplexity", 1, provenance);
  core::fields_into_json(out, out.document);
  out.message = core::first_line(out.brief());
  return out;
}

LdaTopWords run_lda_top_words(const std::filesystem::path& model_file, int top,
                              const core::Provenance& provenance) {
  if (top < 1) throw Error("lda topics: --top must be >= 1");
  const LdaModel model = load_lda_model(model_file);
  const Eigen::MatrixXd beta = model.topic_word();
  LdaTopWords out;
  out.model = model_file;
  for (int k = 0; k < model.num_topics(); ++k) {
    std::string line = "topic " + std::to_string(k) + ":";
    LdaTopWords::Topic& topic = out.topics.emplace_back();
    topic.topic = k;
    for (const int w : model.top_words(k, top)) {
      const std::string name = model.vocabulary.empty()
                                   ? std::to_string(w)
                                   : model.vocabulary[static_cast<std::size_t>(w)];
      line += ' ';
      line += name;
      topic.words.push_back({name, w, beta(k, w)});
    }
    out.lines.push_back(line);
  }
  out.document = core::result_document("proprio.lda.topics", 1, provenance);
  core::fields_into_json(out, out.document);
  out.message = core::first_line(out.brief());
  return out;
}

}  // namespace proprio::topics
