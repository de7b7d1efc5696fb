// proprio lda ...: topic models of bag-of-words corpora (thesis Ch 6, Appendix B;
// docs/formats/corpus.md, docs/formats/lda-model.md).
#include <cstdio>
#include <memory>

#include "cli.hpp"
#include "proprio/core/csv.hpp"
#include "proprio/core/error.hpp"
#include "proprio/core/files.hpp"
#include "proprio/topics/batch_lda.hpp"
#include "proprio/topics/corpus_io.hpp"
#include "proprio/topics/inference.hpp"
#include "proprio/topics/lda_model_io.hpp"
#include "proprio/topics/online_lda.hpp"
#include "proprio/topics/perplexity.hpp"

namespace proprio::app {
namespace {
using namespace topics;

struct CorpusArgs {
  std::string dir;
  std::string format = "uci";
  [[nodiscard]] Corpus read() const { return read_corpus(dir, parse_corpus_format(format)); }
};

void add_corpus_options(CLI::App* cmd, CorpusArgs& c, const char* what) {
  cmd->add_option("--corpus", c.dir, what)->required();
  cmd->add_option("--format", c.format, "Corpus format: uci, ldac or mm (docs/formats/corpus.md)")
      ->check(CLI::IsMember({"uci", "ldac", "mm"}))
      ->capture_default_str();
}

struct TrainArgs {
  CorpusArgs corpus;
  std::string heldout;
  std::string model;
  std::string json;
  std::string method = "online";
  OnlineLdaOptions online;
  int max_iterations = 100;
  double tolerance = 1e-4;
};

struct InferArgs {
  CorpusArgs corpus;
  std::string model;
  std::string out;
  std::string json;
  InferenceOptions options;
};

struct PerplexityArgs {
  CorpusArgs corpus;
  std::string model;
  std::string lambda;
  double alpha = 0.0;
  double eta = 0.0;
  std::string method = "completion";
  std::string json;
  PerplexityOptions options;
};

struct TopicsArgs {
  std::string model;
  int top = 10;
  std::string json;
};

struct ExportArgs {
  std::string model;
  std::string out;
  bool normalize = false;
};

core::Json options_json(const OnlineLdaOptions& o) {
  return {{"topics", o.num_topics},
          {"batch", o.batch_size},
          {"tau0", o.tau0},
          {"kappa", o.kappa},
          {"alpha", o.resolved_alpha()},
          {"eta", o.resolved_eta()},
          {"passes", o.passes},
          {"threads", o.threads},
          {"seed", o.seed},
          {"estep_max_iterations", o.estep.max_iterations},
          {"estep_tolerance", o.estep.tolerance}};
}

void check_vocabularies(const LdaModel& model, const Corpus& corpus, const std::string& where) {
  if (corpus.num_words() != model.num_words()) {
    throw Error::in_file(where, "has " + std::to_string(corpus.num_words()) +
                                    " words but the model has " +
                                    std::to_string(model.num_words()));
  }
  if (!model.vocabulary.empty() && !corpus.vocabulary().empty() &&
      model.vocabulary != corpus.vocabulary()) {
    for (std::size_t w = 0; w < model.vocabulary.size(); ++w) {
      if (model.vocabulary[w] != corpus.vocabulary()[w]) {
        throw Error::in_file(where, "word " + std::to_string(w + 1) + " is '" +
                                        corpus.vocabulary()[w] + "' but the model's is '" +
                                        model.vocabulary[w] + "'");
      }
    }
  }
}

void run_train(TrainArgs a, const Invocation& inv) {
  const Corpus corpus = a.corpus.read();
  Corpus heldout;
  const bool has_heldout = !a.heldout.empty();
  if (has_heldout) {
    heldout = read_corpus(a.heldout, parse_corpus_format(a.corpus.format));
    if (heldout.num_words() != corpus.num_words()) {
      throw Error::in_file(a.heldout, "has " + std::to_string(heldout.num_words()) +
                                          " words, the training corpus " +
                                          std::to_string(corpus.num_words()));
    }
  }
  core::Json doc = core::result_document("proprio.lda.train", 1, inv.provenance(a.online.seed));
  doc["corpus"] = a.corpus.dir;
  doc["method"] = a.method;
  doc["model"] = a.model;
  doc["documents_in_corpus"] = corpus.num_documents();
  doc["words"] = corpus.num_words();
  doc["options"] = options_json(a.online);
  LdaModel model;
  if (a.method == "online") {
    a.online.validate();
    const OnlineLdaResult r = has_heldout ? train_online_lda(corpus, heldout, a.online)
                                          : train_online_lda(corpus, a.online);
    const OnlineLdaSummary& s = r.summary;
    std::printf("%s\n", s.brief().c_str());
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
    core::Json trace = core::Json::array();
    for (const auto& p : s.trace) {
      trace.push_back({{"updates", p.updates},
                       {"documents_seen", p.documents_seen},
                       {"perplexity", p.perplexity}});
    }
    doc["perplexity_trace"] = trace;
    if (!s.trace.empty()) doc["heldout_perplexity"] = s.trace.back().perplexity;
    model = r.model;
  } else {
    BatchLdaOptions b;
    b.num_topics = a.online.num_topics;
    b.alpha = a.online.alpha;
    b.eta = a.online.eta;
    b.max_iterations = a.max_iterations;
    b.tolerance = a.tolerance;
    b.threads = a.online.threads;
    b.seed = a.online.seed;
    b.estep = a.online.estep;
    const BatchLdaResult r = train_batch_lda(corpus, b);
    std::printf("%s\n", r.summary.brief().c_str());
    doc["seconds"] = r.summary.seconds;
    const double docs = static_cast<double>(corpus.num_documents()) * r.summary.iterations;
    const double tokens = static_cast<double>(corpus.num_tokens()) * r.summary.iterations;
    doc["docs_per_s"] = r.summary.seconds > 0 ? docs / r.summary.seconds : 0.0;
    doc["tokens_per_s"] = r.summary.seconds > 0 ? tokens / r.summary.seconds : 0.0;
    doc["iterations"] = r.summary.iterations;
    doc["converged"] = r.summary.converged;
    doc["stop_reason"] = r.summary.stop_reason;
    doc["bound"] = r.summary.bound;
    doc["perplexity_trace"] = core::Json::array();
    model = r.model;
    if (has_heldout) {
      PerplexityOptions po;
      po.threads = b.threads;
      const double p = perplexity(model, heldout, po).perplexity;
      std::printf("held-out perplexity %g\n", p);
      doc["heldout_perplexity"] = p;
    }
  }
  save_lda_model(model, a.model);
  write_json_result(a.json, doc);
}

void run_infer(const InferArgs& a, const Invocation& inv) {
  const LdaModel model = load_lda_model(a.model);
  const Corpus corpus = a.corpus.read();
  check_vocabularies(model, corpus, a.corpus.dir);
  const InferenceResult r = infer_topics(model, corpus, a.options);
  const Eigen::MatrixXd theta = r.theta();
  const auto cls = r.classify();
  std::vector<std::string> header{"document", "class"};
  for (int k = 0; k < model.num_topics(); ++k) {
    std::string h = std::to_string(k);
    h.insert(0, "theta_");
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
  core::write_file_atomic(a.out, core::format_csv(header, rows));
  std::printf("%s\n", r.summary.brief().c_str());
  core::Json doc = core::result_document("proprio.lda.infer", 1, inv.provenance());
  doc["model"] = a.model;
  doc["corpus"] = a.corpus.dir;
  doc["out"] = a.out;
  doc["documents"] = r.summary.documents;
  doc["empty_documents"] = r.summary.empty_documents;
  doc["mean_estep_iterations"] = r.summary.mean_iterations;
  doc["estep_capped"] = r.summary.capped;
  doc["seconds"] = r.summary.seconds;
  write_json_result(a.json, doc);
}

void run_perplexity(PerplexityArgs a, const Invocation& inv) {
  if (a.model.empty() == a.lambda.empty()) {
    throw Error("lda perplexity: give exactly one of --model and --lambda");
  }
  LdaModel model;
  if (!a.model.empty()) {
    model = load_lda_model(a.model);
  } else {
    if (!(a.alpha > 0)) throw Error("lda perplexity: --lambda needs --alpha > 0");
    model = read_lambda_csv(a.lambda, a.alpha, a.eta > 0 ? a.eta : a.alpha);
  }
  const Corpus corpus = a.corpus.read();
  check_vocabularies(model, corpus, a.corpus.dir);
  a.options.method = a.method == "bound" ? PerplexityMethod::kVariationalBound
                                         : PerplexityMethod::kDocumentCompletion;
  const PerplexityResult r = perplexity(model, corpus, a.options);
  std::printf("perplexity %.6g (%s, %lld tokens scored in %lld documents)\n", r.perplexity,
              std::string(to_string(r.method)).c_str(), static_cast<long long>(r.tokens),
              static_cast<long long>(r.documents));
  core::Json doc =
      core::result_document("proprio.lda.perplexity", 1, inv.provenance(a.options.split_seed));
  doc["model"] = a.model.empty() ? a.lambda : a.model;
  doc["corpus"] = a.corpus.dir;
  doc["method"] = to_string(r.method);
  doc["perplexity"] = r.perplexity;
  doc["log_likelihood"] = r.log_likelihood;
  doc["tokens"] = r.tokens;
  doc["documents"] = r.documents;
  doc["alpha"] = model.alpha;
  doc["seconds"] = r.seconds;
  write_json_result(a.json, doc);
}

void run_topics(const TopicsArgs& a, const Invocation& inv) {
  const LdaModel model = load_lda_model(a.model);
  const Eigen::MatrixXd beta = model.topic_word();
  core::Json topics = core::Json::array();
  for (int k = 0; k < model.num_topics(); ++k) {
    const auto top = model.top_words(k, a.top);
    std::string line = "topic " + std::to_string(k) + ":";
    core::Json words = core::Json::array();
    for (const int w : top) {
      const std::string name = model.vocabulary.empty()
                                   ? std::to_string(w)
                                   : model.vocabulary[static_cast<std::size_t>(w)];
      line += ' ';
      line += name;
      words.push_back({{"word", name}, {"id", w}, {"probability", beta(k, w)}});
    }
    std::printf("%s\n", line.c_str());
    topics.push_back({{"topic", k}, {"words", words}});
  }
  core::Json doc = core::result_document("proprio.lda.topics", 1, inv.provenance());
  doc["model"] = a.model;
  doc["topics"] = topics;
  write_json_result(a.json, doc);
}

void run_export(const ExportArgs& a) {
  const LdaModel model = load_lda_model(a.model);
  write_lambda_csv(model, a.out, a.normalize);
  std::printf("%s: %d topics x %d words%s\n", a.out.c_str(), model.num_topics(), model.num_words(),
              a.normalize ? " (probabilities)" : " (lambda)");
}

}  // namespace

void register_lda_commands(CLI::App& root, const Invocation& inv) {
  auto* lda = root.add_subcommand("lda", "Topic models: online and batch LDA (thesis Ch 6, App B)");
  lda->require_subcommand(1);

  auto t = std::make_shared<TrainArgs>();
  auto* train = lda->add_subcommand("train", "Train an LDA model on a bag-of-words corpus");
  add_corpus_options(train, t->corpus, "Training corpus: directory or file");
  train->add_option("--model", t->model, "Model file to write")->required();
  train
      ->add_option("--method", t->method,
                   "online (Hoffman et al. 2010) or batch (Blei et al. 2003)")
      ->check(CLI::IsMember({"online", "batch"}))
      ->capture_default_str();
  train->add_option("-k,--topics", t->online.num_topics, "Number of topics K")
      ->capture_default_str();
  train->add_option("--batch", t->online.batch_size, "Documents per mini-batch")
      ->capture_default_str();
  train->add_option("--tau0", t->online.tau0, "Learning-rate offset: rho_t = (tau0 + t)^-kappa")
      ->capture_default_str();
  train->add_option("--kappa", t->online.kappa, "Learning-rate decay, in (0.5, 1]")
      ->capture_default_str();
  train->add_option("--alpha", t->online.alpha, "Prior on topic proportions (default 1/K)");
  train->add_option("--eta", t->online.eta, "Prior on topic words (default 1/K)");
  train->add_option("--passes", t->online.passes, "Passes over the corpus (online)")
      ->capture_default_str();
  train->add_option("--max-iterations", t->max_iterations, "EM iterations (batch)")
      ->capture_default_str();
  train->add_option("--tolerance", t->tolerance, "Relative change of the bound that stops batch EM")
      ->capture_default_str();
  train->add_option("--threads", t->online.threads, "Threads (the model does not depend on it)")
      ->capture_default_str();
  train->add_option("--seed", t->online.seed, "Random seed")->capture_default_str();
  train->add_option("--heldout", t->heldout,
                    "Held-out corpus (same format): trace its perplexity (document completion)");
  train
      ->add_option("--evaluate-every", t->online.evaluate_every,
                   "With --heldout: perplexity every this many mini-batches (0: start and end)")
      ->capture_default_str();
  train->add_option("--json", t->json,
                    "Also write seconds, docs_per_s, tokens_per_s and the trace as JSON");
  train->callback([t, &inv] { run_train(*t, inv); });

  auto i = std::make_shared<InferArgs>();
  auto* infer = lda->add_subcommand(
      "infer", "Topic proportions theta and class (argmax, thesis 6.1.4) of each document");
  add_corpus_options(infer, i->corpus, "Corpus of documents to infer");
  infer->add_option("--model", i->model, "Model file")->required();
  infer->add_option("--out", i->out, "CSV to write: document, class, theta_0..theta_{K-1}")
      ->required();
  infer->add_option("--threads", i->options.threads, "Threads")->capture_default_str();
  infer->add_option("--json", i->json, "Also write a summary as JSON");
  infer->callback([i, &inv] { run_infer(*i, inv); });

  auto p = std::make_shared<PerplexityArgs>();
  auto* perp = lda->add_subcommand("perplexity", "Held-out perplexity of a model");
  add_corpus_options(perp, p->corpus, "Held-out corpus");
  perp->add_option("--model", p->model, "Model file");
  perp->add_option("--lambda", p->lambda,
                   "Or a K x W lambda CSV from another tool (lda export's layout)");
  perp->add_option("--alpha", p->alpha, "With --lambda: the prior on topic proportions");
  perp->add_option("--eta", p->eta, "With --lambda: the prior on topic words (default alpha)");
  perp->add_option("--method", p->method,
                   "completion (theta from half of each document, the other half scored) or bound")
      ->check(CLI::IsMember({"completion", "bound"}))
      ->capture_default_str();
  perp->add_option("--split-seed", p->options.split_seed, "Seed of the token split")
      ->capture_default_str();
  perp->add_option("--threads", p->options.threads, "Threads")->capture_default_str();
  perp->add_option("--json", p->json, "Also write the perplexity as JSON");
  perp->callback([p, &inv] { run_perplexity(*p, inv); });

  auto tp = std::make_shared<TopicsArgs>();
  auto* top = lda->add_subcommand("topics", "The most probable words of each topic");
  top->add_option("--model", tp->model, "Model file")->required();
  top->add_option("--top", tp->top, "Words per topic")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000000));
  top->add_option("--json", tp->json, "Also write the words and probabilities as JSON");
  top->callback([tp, &inv] { run_topics(*tp, inv); });

  auto e = std::make_shared<ExportArgs>();
  auto* exp = lda->add_subcommand("export", "Write lambda (K x W, a topic per row) as CSV");
  exp->add_option("--model", e->model, "Model file")->required();
  exp->add_option("--out", e->out, "CSV file to write")->required();
  exp->add_flag("--normalize", e->normalize, "Write each topic's word probabilities instead");
  exp->callback([e] { run_export(*e); });
}

}  // namespace proprio::app
