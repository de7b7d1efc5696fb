// proprio segment / proprio evaluate segmentation: bind the options, make the one library call
// (eval::run_segment_episode, eval::run_dataset_evaluation), print (thesis Ch 4-5;
// docs/results/segmentation-eval.md).
#include <cstdio>
#include <memory>

#include "cli.hpp"
#include "option_binder.hpp"
#include "proprio/eval/dataset_evaluation.hpp"
#include "proprio/eval/segment_episode.hpp"

namespace proprio::app {
namespace {

// The methods' options both commands take, bound from the options' own descriptions (--fraction,
// --depth-fraction: segmentation::MlOptions; --threshold, --touch: segmentation::FmOptions), so
// that they are named, documented and bounded as everywhere else.
void add_method_options(CLI::App* cmd, eval::EvalOptions& o) {
  bind_options(cmd, o.ml, FieldFilter{{"mask_fraction", "depth_mask_fraction"}, {}});
  // 0 ("the M-L fraction") is the library's, not a flag value: --fraction already sets that.
  cmd->get_option("--depth-fraction")->check(CLI::Range(0.01, 1.0));
  bind_options(cmd, o.fm, FieldFilter{{"difference_threshold", "touch"}, {}});
}

// --fraction is every M-L variant's mask fraction: ml-sparse and ml-graphcut take M-L's.
void share_mask_fraction(eval::EvalOptions& o) {
  o.sparse.mask_fraction = o.ml.mask_fraction;
  o.ml_graph_cut.mask_fraction = o.ml.mask_fraction;
}

struct SegmentArgs {
  eval::SegmentEpisodeOptions options;
  std::string method = "ml";
  JsonFlag json;
};

struct EvaluateArgs {
  eval::DatasetEvaluationOptions options;
  std::string methods = "ml,fm,ml-graphcut";
  JsonFlag json;
};

void run_segment(SegmentArgs& a, const Invocation& inv) {
  a.options.method = eval::parse_method(a.method);
  share_mask_fraction(a.options.eval);
  a.json.refuse({a.options.episode, a.options.out});
  const eval::SegmentEpisodeResult r = eval::run_segment_episode(a.options, inv.provenance());
  a.json.write(r.document);
  std::fputs(r.brief().c_str(), stdout);
  std::printf("wrote %s\n", a.options.out.c_str());
}

void run_evaluate(EvaluateArgs& a, const Invocation& inv) {
  a.options.methods = eval::parse_methods(a.methods);
  share_mask_fraction(a.options.eval);
  a.options.progress = true;
  a.json.refuse({a.options.dataset, a.options.out});
  const eval::DatasetEvaluationResult r =
      eval::run_dataset_evaluation(a.options, inv.provenance(a.options.eval.seed));
  a.json.write(r.document);
  std::fputs(r.brief().c_str(), stdout);
  std::printf("wrote %s (summary.json, episodes.csv, plots)\n", a.options.out.c_str());
}

}  // namespace

void register_segment_commands(CLI::App& root, const Invocation& inv) {
  auto seg = std::make_shared<SegmentArgs>();
  auto* cmd = root.add_subcommand(
      "segment",
      "Segment the pushed object of an episode (thesis Ch 4-5): Motion-Likelihood, its homography "
      "and sparse variants, the Fitzpatrick & Metta baseline, or M-L + graph cuts");
  cmd->add_option("episode", seg->options.episode, "Episode directory")->required();
  cmd->add_option("--method", seg->method,
                  "ml, ml-homography, ml-sparse, fm, ml-graphcut or ml-depth (needs depth)")
      ->check(CLI::IsMember({"ml", "ml-homography", "ml-sparse", "fm", "ml-graphcut", "ml-depth"}));
  cmd->add_option("--out", seg->options.out,
                  "Directory to write: map.png (16-bit), mask.png, overlay.png, frame.png, "
                  "truth.png, segment.json")
      ->required();
  seg->json.add_to(cmd, "the result");
  cmd->add_flag("--overwrite", seg->options.overwrite, "Replace --out if it exists");
  add_method_options(cmd, seg->options.eval);
  cmd->callback([seg, &inv] { run_segment(*seg, inv); });

  auto* evaluate = root.add_subcommand("evaluate", "Evaluations over datasets");
  evaluate->require_subcommand(1);
  auto ev = std::make_shared<EvaluateArgs>();
  auto* es = evaluate->add_subcommand(
      "segmentation",
      "Score segmentation methods on every episode of a dataset at the first-touch frame "
      "(thesis 5.1-5.2): P-R curves, Jaccard, L2, KS tests, CSV, plots and a JSON summary");
  es->add_option("dataset", ev->options.dataset, "Directory of episode directories")->required();
  es->add_option("--methods", ev->methods,
                 "Comma-separated: ml, ml-homography, ml-sparse, fm, ml-graphcut, ml-depth");
  es->add_option("--out", ev->options.out, "Directory to write")->required();
  ev->json.add_to(es, "the summary");
  es->add_option("--threads", ev->options.threads, "Episodes evaluated at once")
      ->check(CLI::Range(1, 256));
  es->add_flag("--overwrite", ev->options.overwrite, "Replace --out if it exists");
  es->add_flag("!--no-all-frames", ev->options.eval.all_frames,
               "Skip M-L's mean over every frame from the first touch on (faster)");
  es->add_option("--seed", ev->options.eval.seed, "Seed of the bootstrap");
  add_method_options(es, ev->options.eval);
  es->callback([ev, &inv] { run_evaluate(*ev, inv); });
}

}  // namespace proprio::app
