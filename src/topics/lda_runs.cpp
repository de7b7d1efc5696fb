#include "proprio/topics/lda_runs.hpp"

#include <cstdio>
#include <cstring>
#include <optional>
#include <vector>

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

// The options as they were used: alpha and eta resolved (0 means 1/K).
core::Json used_options_json(OnlineLdaOptions o) {
  o.alpha = o.resolved_alpha();
  o.eta = o.resolved_eta();
  return core::fields_to_json(o);
}

core::Json trace_json(const std::vector<PerplexityPoint>& trace) {
  core::Json out = core::Json::array();
  for (const auto& p : trace) {
    out.push_back({{"updates", p.updates},
                   {"documents_seen", p.documents_seen},
                   {"perplexity", p.perplexity}});
  }
  return out;
}

void train_online(const LdaTrainingOptions& o, const Corpus& corpus, const Corpus* heldout,
                  LdaTrainingResult& r) {
  const OnlineLdaResult t = train_online_lda(corpus, heldout, o.online, o.checkpointing);
  const OnlineLdaSummary& s = t.summary;
  r.brief = s.brief();
  core::Json& doc = r.document;
  doc["seconds"] = s.seconds;
  doc["cpu_seconds"] = s.cpu_seconds;
  doc["docs_per_s"] = s.documents_per_second();
  doc["tokens_per_s"] = s.tokens_per_second();
  doc["documents"] = s.documents;
  doc["tokens"] = s.tokens;
  doc["updates"] = s.updates;
  doc["passes"] = s.passes;
  doc["threads"] = s.threads;
  doc["kernel"] = s.kernel;
  doc["mean_estep_iterations"] = s.mean_estep_iterations;
  doc["estep_capped"] = s.capped;
  doc["evaluation_seconds"] = s.evaluation_seconds;
  doc["perplexity_trace"] = trace_json(s.trace);
  if (!s.trace.empty()) doc["heldout_perplexity"] = s.trace.back().perplexity;
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
  r.brief = s.brief();
  core::Json& doc = r.document;
  doc["seconds"] = s.seconds;
  const double docs = static_cast<double>(corpus.num_documents()) * s.iterations;
  const double tokens = static_cast<double>(corpus.num_tokens()) * s.iterations;
  doc["docs_per_s"] = s.seconds > 0 ? docs / s.seconds : 0.0;
  doc["tokens_per_s"] = s.seconds > 0 ? tokens / s.seconds : 0.0;
  doc["iterations"] = s.iterations;
  doc["converged"] = s.converged;
  doc["stop_reason"] = s.stop_reason;
  doc["bound"] = s.bound;
  doc["perplexity_trace"] = core::Json::array();
  r.model = t.model;
  if (heldout != nullptr) {
    PerplexityOptions po;
    po.threads = b.threads;
    const double p = perplexity(r.model, *heldout, po).perplexity;
    char line[64];
    std::snprintf(line, sizeof line, "\nheld-out perplexity %g", p);
    r.brief += line;
    doc["heldout_perplexity"] = p;
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
  std::vector<fs::path> inputs = corpus_inputs(options.corpus, options.format);
  if (!options.heldout.empty()) {
    const auto more = corpus_inputs(options.heldout, options.format);
    inputs.insert(inputs.end(), more.begin(), more.end());
  }
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
    heldout = read_corpus(options.heldout, options.format);
    if (heldout->num_words() != corpus.num_words()) {
      throw Error::in_file(options.heldout, "has " + std::to_string(heldout->num_words()) +
                                                " words, the training corpus " +
                                                std::to_string(corpus.num_words()));
    }
  }
  LdaTrainingResult r;
  core::Json& doc = r.document;
  doc = core::result_document("proprio.lda.train", 1, provenance);
  doc["corpus"] = options.corpus.string();
  doc["method"] = core::choice_name(options.method, kLdaMethodNames);
  doc["model"] = options.model.string();
  doc["documents_in_corpus"] = corpus.num_documents();
  doc["words"] = corpus.num_words();
  doc["options"] = used_options_json(options.online);
  const Corpus* held = heldout ? &*heldout : nullptr;
  if (options.method == LdaMethod::kOnline) {
    train_online(options, corpus, held, r);
  } else {
    train_batch(options, corpus, held, r);
  }
  if (!options.model.empty()) save_lda_model(r.model, options.model);
  return r;
}

namespace {

// FNV-1a over the bytes of lambda: the ranks' models compared after training.
std::int64_t lambda_checksum(const Eigen::MatrixXd& lambda) {
  std::uint64_t h = 14695981039346656037ULL;
  const auto* p = reinterpret_cast<const unsigned char*>(lambda.data());
  const auto n = static_cast<std::size_t>(lambda.size()) * sizeof(double);
  for (std::size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 1099511628211ULL;
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
    std::vector<fs::path> inputs = corpus_inputs(options.corpus, options.format);
    if (!options.heldout.empty()) {
      const auto more = corpus_inputs(options.heldout, options.format);
      inputs.insert(inputs.end(), more.begin(), more.end());
    }
    core::require_output_not_input(options.model, inputs, "--model");
    shard = read_corpus_shard(options.corpus, options.format, rank, ranks);
    if (rank == 0 && !options.heldout.empty()) {
      heldout = read_corpus(options.heldout, options.format);
      if (heldout->num_words() != shard.documents.num_words()) {
        throw Error::in_file(options.heldout, "has " + std::to_string(heldout->num_words()) +
                                                  " words, the training corpus " +
                                                  std::to_string(shard.documents.num_words()));
      }
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
  core::Json& doc = r.document;
  doc = core::result_document("proprio.lda.train", 1, provenance);
  doc["corpus"] = options.corpus.string();
  doc["method"] = core::choice_name(options.method, kLdaMethodNames);
  doc["model"] = options.model.string();
  doc["documents_in_corpus"] = shard.total_documents;
  doc["words"] = shard.documents.num_words();
  doc["options"] = used_options_json(options.online);
  const OnlineLdaResult t =
      train_online_lda(shard, heldout ? &*heldout : nullptr, options.online, comm);
  const OnlineLdaSummary& s = t.summary;
  r.brief = s.brief();
  doc["seconds"] = s.seconds;
  doc["cpu_seconds"] = s.cpu_seconds;
  doc["docs_per_s"] = s.documents_per_second();
  doc["tokens_per_s"] = s.tokens_per_second();
  doc["documents"] = s.documents;
  doc["tokens"] = s.tokens;
  doc["updates"] = s.updates;
  doc["passes"] = s.passes;
  doc["threads"] = s.threads;
  doc["kernel"] = s.kernel;
  doc["mean_estep_iterations"] = s.mean_estep_iterations;
  doc["estep_capped"] = s.capped;
  doc["evaluation_seconds"] = s.evaluation_seconds;
  doc["perplexity_trace"] = trace_json(s.trace);
  if (!s.trace.empty()) doc["heldout_perplexity"] = s.trace.back().perplexity;
  doc["ranks"] = ranks;
  r.model = t.model;
  // The last collective step: every rank holds the same model, or the job stops here.
  std::vector<std::int64_t> mlo{lambda_checksum(r.model.lambda)};
  std::vector<std::int64_t> mhi = mlo;
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
  LdaInferenceResult out{r.summary, core::result_document("proprio.lda.infer", 1, provenance)};
  core::Json& doc = out.document;
  doc["model"] = options.model.string();
  doc["corpus"] = options.corpus.string();
  doc["out"] = options.out.string();
  doc["documents"] = r.summary.documents;
  doc["empty_documents"] = r.summary.empty_documents;
  doc["mean_estep_iterations"] = r.summary.mean_iterations;
  doc["estep_capped"] = r.summary.capped;
  doc["seconds"] = r.summary.seconds;
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
  LdaPerplexityResult out{perplexity(model, corpus, options.perplexity),
                          core::result_document("proprio.lda.perplexity", 1, provenance)};
  const PerplexityResult& r = out.perplexity;
  core::Json& doc = out.document;
  doc["model"] = (options.model.empty() ? options.lambda : options.model).string();
  doc["corpus"] = options.corpus.string();
  doc["method"] = to_string(r.method);
  doc["perplexity"] = r.perplexity;
  doc["log_likelihood"] = r.log_likelihood;
  doc["tokens"] = r.tokens;
  doc["documents"] = r.documents;
  doc["alpha"] = model.alpha;
  doc["seconds"] = r.seconds;
  return out;
}

LdaTopWords run_lda_top_words(const std::filesystem::path& model_file, int top,
                              const core::Provenance& provenance) {
  if (top < 1) throw Error("lda topics: --top must be >= 1");
  const LdaModel model = load_lda_model(model_file);
  const Eigen::MatrixXd beta = model.topic_word();
  LdaTopWords out{{}, core::result_document("proprio.lda.topics", 1, provenance)};
  core::Json topics = core::Json::array();
  for (int k = 0; k < model.num_topics(); ++k) {
    std::string line = "topic " + std::to_string(k) + ":";
    core::Json words = core::Json::array();
    for (const int w : model.top_words(k, top)) {
      const std::string name = model.vocabulary.empty()
                                   ? std::to_string(w)
                                   : model.vocabulary[static_cast<std::size_t>(w)];
      line += ' ';
      line += name;
      words.push_back({{"word", name}, {"id", w}, {"probability", beta(k, w)}});
    }
    out.lines.push_back(line);
    topics.push_back({{"topic", k}, {"words", words}});
  }
  out.document["model"] = model_file.string();
  out.document["topics"] = topics;
  return out;
}

}  // namespace proprio::topics
