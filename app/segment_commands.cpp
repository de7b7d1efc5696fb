// proprio segment / proprio evaluate segmentation: bind the options, make the one library call
// (eval::run_segment_episode, eval::run_dataset_evaluation), print (thesis Ch 4-5;
// docs/results/segmentation-eval.md).
#include <cstdio>
#include <memory>

#include "cli.hpp"
#include "proprio/eval/dataset_evaluation.hpp"
#include "proprio/eval/segment_episode.hpp"

namespace proprio::app {
namespace {

// The methods' options that both commands take.
struct MethodArgs {
  double fraction = 0.75;
  double depth_fraction = segmentation::MlOptions{}.depth_mask_fraction;
  double threshold = 5.0;
  std::string touch = "robot";
};

void add_method_options(CLI::App* cmd, MethodArgs& a) {
  cmd->add_option("--fraction", a.fraction,
                  "M-L mask = map >= fraction * max (thesis 5.1.1: 0.75); also ml-graphcut's")
      ->check(CLI::Range(0.01, 1.0));
  cmd->add_option("--depth-fraction", a.depth_fraction,
                  "ml-depth's mask = map >= depth-fraction * max (tuned on the tuning recording; "
                  "docs/results/segmentation-eval.md)")
      ->capture_default_str()
      ->check(CLI::Range(0.01, 1.0));
  cmd->add_option("--threshold", a.threshold,
                  "Baseline's frame-difference threshold, 0-255 (thesis 5.1.1: 5)")
      ->check(CLI::Range(0.0, 254.0));
  cmd->add_option("--touch", a.touch,
                  "Baseline's touch frame: robot (its touching flag, as M-L) or differencing")
      ->check(CLI::IsMember({"robot", "differencing"}));
}

eval::EvalOptions eval_options(const MethodArgs& a) {
  eval::EvalOptions o;
  o.ml.mask_fraction = a.fraction;
  o.ml.depth_mask_fraction = a.depth_fraction;
  o.sparse.mask_fraction = a.fraction;
  o.ml_graph_cut.mask_fraction = a.fraction;
  o.fm.difference_threshold = a.threshold;
  o.fm.touch = a.touch == "robot" ? segmentation::TouchSource::kRobot
                                  : segmentation::TouchSource::kDifferencing;
  return o;
}

struct SegmentArgs {
  eval::SegmentEpisodeOptions options;
  std::string method = "ml";
  std::string json;
  MethodArgs m;
};

struct EvaluateArgs {
  eval::DatasetEvaluationOptions options;
  std::string methods = "ml,fm,ml-graphcut";
  std::string json;
  bool all_frames = true;
  std::uint64_t seed = 1;
  MethodArgs m;
};

void run_segment(SegmentArgs& a, const Invocation& inv) {
  a.options.method = eval::parse_method(a.method);
  a.options.eval = eval_options(a.m);
  const eval::SegmentEpisodeResult r = eval::run_segment_episode(a.options, inv.provenance());
  write_json_result(a.json, r.document);
  std::fputs(r.brief().c_str(), stdout);
  std::printf("wrote %s\n", a.options.out.c_str());
}

void run_evaluate(EvaluateArgs& a, const Invocation& inv) {
  a.options.methods = eval::parse_methods(a.methods);
  a.options.eval = eval_options(a.m);
  a.options.eval.all_frames = a.all_frames;
  a.options.eval.seed = a.seed;
  a.options.progress = true;
  const eval::DatasetEvaluationResult r =
      eval::run_dataset_evaluation(a.options, inv.provenance(a.seed));
  write_json_result(a.json, r.document);
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
  cmd->add_option("--json", seg->json, "Also write the result as JSON to this file");
  cmd->add_flag("--overwrite", seg->options.overwrite, "Replace --out if it exists");
  add_method_options(cmd, seg->m);
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
  es->add_option("--json", ev->json, "Also write the summary to this file");
  es->add_option("--threads", ev->options.threads, "Episodes evaluated at once")
      ->check(CLI::Range(1, 256));
  es->add_flag("--overwrite", ev->options.overwrite, "Replace --out if it exists");
  es->add_flag("!--no-all-frames", ev->all_frames,
               "Skip M-L's mean over every frame from the first touch on (faster)");
  es->add_option("--seed", ev->seed, "Seed of the bootstrap");
  add_method_options(es, ev->m);
  es->callback([ev, &inv] { run_evaluate(*ev, inv); });
}

}  // namespace proprio::app
