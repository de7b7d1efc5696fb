// proprio lda ...: topic models of bag-of-words corpora (thesis Ch 6, Appendix B;
// docs/formats/corpus.md, docs/formats/lda-model.md). Each command binds its options, makes one
// library call (topics/lda_runs.hpp) and prints.
#include <cstdio>
#include <memory>

#include "cli.hpp"
#include "option_binder.hpp"
#include "proprio/core/fields.hpp"
#include "proprio/core/files.hpp"
#include "proprio/core/json_io.hpp"
#include "proprio/topics/lda_model_io.hpp"
#include "proprio/topics/lda_runs.hpp"
#include "world.hpp"

namespace proprio::app {
namespace {
using namespace topics;

void add_corpus_options(CLI::App* cmd, std::filesystem::path& corpus, CorpusFormat& format,
                        const char* what) {
  cmd->add_option("--corpus", corpus, what)->required();
  bind_choice(cmd, format, {"format", "Corpus format (docs/formats/corpus.md)"},
              kCorpusFormatNames);
}

struct TrainArgs {
  LdaTrainingOptions options;
  JsonFlag json;
  bool phase_times = false;
};
struct InferArgs {
  LdaInferenceOptions options;
  JsonFlag json;
};
struct PerplexityArgs {
  LdaPerplexityOptions options;
  std::string method = "completion";
  JsonFlag json;
};
struct TopicsArgs {
  std::string model;
  int top = 10;
  JsonFlag json;
};
struct ExportArgs {
  std::string model;
  std::string out;
  bool normalize = false;
};

void register_train(CLI::App* lda, const Invocation& inv) {
  auto t = std::make_shared<TrainArgs>();
  auto* cmd = lda->add_subcommand("train", "Train an LDA model on a bag-of-words corpus");
  cmd->add_option("--corpus", t->options.corpus, "Training corpus: directory or file")->required();
  cmd->add_option("--model", t->options.model, "Model file to write")->required();
  bind_options(cmd, t->options);
  bind_options(cmd, t->options.online);
  bind_options(cmd, t->options.online.mpi);
  cmd->add_flag("--phase-times", t->phase_times,
                "Online: print this process's time per phase as a JSON line on stderr (every "
                "rank its own; bench/bench_mpi.py reads it)");
  cmd->add_option("--heldout", t->options.heldout,
                  "Held-out corpus (same format): trace its perplexity (document completion)");
  t->json.add_to(cmd, "seconds, docs_per_s, tokens_per_s and the trace");
  cmd->add_option("--checkpoint", t->options.checkpointing.checkpoint,
                  "Online: write a checkpoint here (atomically) every --checkpoint-every "
                  "mini-batches");
  bind_options(cmd, t->options.checkpointing);
  cmd->add_option("--resume", t->options.checkpointing.resume,
                  "Online: continue from this checkpoint (same corpus and options; refused "
                  "otherwise)");
  // Under mpirun, data-parallel over the ranks (topics/lda_runs.hpp); rank 0 prints and writes.
  cmd->callback([t, &inv] {
    run_on_world([&](core::Communicator& comm) {
      core::agree(comm, [&] {
        const CorpusFiles files = find_corpus_files(t->options.corpus, t->options.format);
        t->json.refuse({t->options.model, t->options.corpus, files.file, files.vocabulary,
                        t->options.heldout, t->options.checkpointing.checkpoint,
                        t->options.checkpointing.resume});
      });
      const LdaTrainingResult r =
          run_lda_training(t->options, inv.provenance(t->options.online.seed), comm);
      if (t->phase_times) {
        const core::Json line = {{"phase_times", core::fields_to_json(r.phase_times)}};
        std::fprintf(stderr, "%s\n", line.dump().c_str());
      }
      if (comm.rank() != 0) return;
      std::printf("%s\n", r.brief().c_str());
      t->json.write(r.document);
    });
  });
}

void register_infer(CLI::App* lda, const Invocation& inv) {
  auto i = std::make_shared<InferArgs>();
  auto* cmd = lda->add_subcommand(
      "infer", "Topic proportions theta and class (argmax, thesis 6.1.4) of each document");
  add_corpus_options(cmd, i->options.corpus, i->options.format, "Corpus of documents to infer");
  cmd->add_option("--model", i->options.model, "Model file")->required();
  cmd->add_option("--out", i->options.out, "CSV to write: document, class, theta_0..theta_{K-1}")
      ->required();
  cmd->add_option("--threads", i->options.inference.threads, "Threads")->capture_default_str();
  i->json.add_to(cmd, "a summary");
  cmd->callback([i, &inv] {
    i->json.refuse({i->options.out, i->options.model, i->options.corpus});
    const LdaInferenceResult r = run_lda_inference(i->options, inv.provenance());
    std::printf("%s\n", r.summary.brief().c_str());
    i->json.write(r.document);
  });
}

void register_perplexity(CLI::App* lda, const Invocation& inv) {
  auto p = std::make_shared<PerplexityArgs>();
  auto* cmd = lda->add_subcommand("perplexity", "Held-out perplexity of a model");
  LdaPerplexityOptions& o = p->options;
  add_corpus_options(cmd, o.corpus, o.format, "Held-out corpus");
  cmd->add_option("--model", o.model, "Model file");
  cmd->add_option("--lambda", o.lambda,
                  "Or a K x W lambda CSV from another tool (lda export's layout)");
  cmd->add_option("--alpha", o.alpha, "With --lambda: the prior on topic proportions");
  cmd->add_option("--eta", o.eta, "With --lambda: the prior on topic words (default alpha)");
  cmd->add_option("--method", p->method,
                  "completion (theta from half of each document, the other half scored) or bound")
      ->check(CLI::IsMember({"completion", "bound"}))
      ->capture_default_str();
  cmd->add_option("--split-seed", o.perplexity.split_seed, "Seed of the token split")
      ->capture_default_str();
  cmd->add_option("--threads", o.perplexity.threads, "Threads")->capture_default_str();
  p->json.add_to(cmd, "the perplexity");
  cmd->callback([p, &inv] {
    p->options.perplexity.method = p->method == "bound" ? PerplexityMethod::kVariationalBound
                                                        : PerplexityMethod::kDocumentCompletion;
    p->json.refuse({p->options.corpus, p->options.model, p->options.lambda});
    const LdaPerplexityResult r =
        run_lda_perplexity(p->options, inv.provenance(p->options.perplexity.split_seed));
    std::printf("%s\n", r.brief().c_str());
    p->json.write(r.document);
  });
}

}  // namespace

void register_lda_commands(CLI::App& root, const Invocation& inv) {
  auto* lda = root.add_subcommand("lda", "Topic models: online and batch LDA (thesis Ch 6, App B)");
  lda->require_subcommand(1);
  register_train(lda, inv);
  register_infer(lda, inv);
  register_perplexity(lda, inv);

  auto tp = std::make_shared<TopicsArgs>();
  auto* top = lda->add_subcommand("topics", "The most probable words of each topic");
  top->add_option("--model", tp->model, "Model file")->required();
  top->add_option("--top", tp->top, "Words per topic")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000000));
  tp->json.add_to(top, "the words and probabilities");
  top->callback([tp, &inv] {
    tp->json.refuse({tp->model});
    const LdaTopWords r = run_lda_top_words(tp->model, tp->top, inv.provenance());
    std::fputs(r.brief().c_str(), stdout);
    tp->json.write(r.document);
  });

  auto e = std::make_shared<ExportArgs>();
  auto* exp = lda->add_subcommand("export", "Write lambda (K x W, a topic per row) as CSV");
  exp->add_option("--model", e->model, "Model file")->required();
  exp->add_option("--out", e->out, "CSV file to write")->required();
  exp->add_flag("--normalize", e->normalize, "Write each topic's word probabilities instead");
  exp->callback([e] {
    const LdaModel model = load_lda_model(e->model);
    write_lambda_csv(model, e->out, e->normalize);
    std::printf("%s: %d topics x %d words%s\n", e->out.c_str(), model.num_topics(),
                model.num_words(), e->normalize ? " (probabilities)" : " (lambda)");
  });
}

}  // namespace proprio::app
