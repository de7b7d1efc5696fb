// proprio segment / proprio evaluate segmentation: Motion-Likelihood segmentation, the
// Fitzpatrick & Metta baseline and M-L + graph cuts on one episode, and the Chapter 5 evaluation
// over a dataset (thesis Ch 4-5; docs/results/segmentation-eval.md).
#include <atomic>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <mutex>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <thread>

#include "cli.hpp"
#include "proprio/core/error.hpp"
#include "proprio/core/files.hpp"
#include "proprio/core/progress.hpp"
#include "proprio/episode/episode.hpp"
#include "proprio/eval/segmentation_eval.hpp"

namespace proprio::app {
namespace {
namespace fs = std::filesystem;
using eval::Method;

// Options shared by both commands.
struct MethodArgs {
  double fraction = 0.75;
  double threshold = 5.0;
  std::string touch = "robot";
};

void add_method_options(CLI::App* cmd, MethodArgs& a) {
  cmd->add_option("--fraction", a.fraction,
                  "M-L mask = map >= fraction * max (thesis 5.1.1: 0.75); also ml-graphcut's")
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
  o.sparse.mask_fraction = a.fraction;
  o.ml_graph_cut.mask_fraction = a.fraction;
  o.fm.difference_threshold = a.threshold;
  o.fm.touch = a.touch == "robot" ? segmentation::TouchSource::kRobot
                                  : segmentation::TouchSource::kDifferencing;
  return o;
}

core::Json options_json(const eval::EvalOptions& o) {
  return {{"mask_fraction", o.ml.mask_fraction},
          {"difference_threshold", o.fm.difference_threshold},
          {"fm_touch", segmentation::to_string(o.fm.touch)},
          {"ml_graphcut_unary_weight", o.ml_graph_cut.unary_weight},
          {"graph_cut_smoothness", o.ml_graph_cut.graph_cut.smoothness},
          {"graph_cut_max_side", o.ml_graph_cut.graph_cut.max_side},
          {"fraction_sweep", o.fraction_sweep},
          {"threshold_sweep", o.threshold_sweep}};
}

core::Json metrics_json(const eval::MaskMetrics& m) {
  return {{"precision", m.precision},
          {"recall", m.recall},
          {"jaccard", m.jaccard},
          {"tanimoto", m.tanimoto()},
          {"l2", m.l2},
          {"true_positives", m.true_positives},
          {"false_positives", m.false_positives},
          {"false_negatives", m.false_negatives}};
}

void save_image(const fs::path& stage, const fs::path& final_dir, const std::string& name,
                const cv::Mat& img) {
  if (!cv::imwrite((stage / name).string(), img)) {
    throw Error::in_file(final_dir / name, "cannot write the image");
  }
}

// The frame with the mask tinted green, its outline red, and the ground truth's outline yellow.
cv::Mat overlay(const cv::Mat& frame, const cv::Mat1b& mask, const cv::Mat1b& truth) {
  cv::Mat out = frame.clone();
  cv::Mat green(frame.size(), frame.type(), cv::Scalar(0, 200, 0));
  cv::Mat blended;
  cv::addWeighted(frame, 0.55, green, 0.45, 0, blended);
  blended.copyTo(out, mask);
  std::vector<std::vector<cv::Point>> contours;
  if (!truth.empty()) {
    cv::findContours(truth.clone(), contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE);
    cv::drawContours(out, contours, -1, cv::Scalar(0, 230, 255), 1, cv::LINE_AA);
  }
  contours.clear();
  cv::findContours(mask.clone(), contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE);
  cv::drawContours(out, contours, -1, cv::Scalar(0, 0, 255), 1, cv::LINE_AA);
  return out;
}

// ---- segment ------------------------------------------------------------------------------------

struct SegmentArgs {
  std::string episode;
  std::string method = "ml";
  std::string out;
  std::string json;
  bool overwrite = false;
  MethodArgs m;
};

void run_segment(const SegmentArgs& a, const Invocation& inv) {
  const Method method = eval::parse_method(a.method);
  eval::EvalOptions o = eval_options(a.m);
  o.all_frames = false;
  const episode::Episode ep = episode::read_episode(a.episode);
  core::StagedDirectory dir(a.out, a.overwrite);
  const fs::path stage = dir.staging_path();
  const eval::EpisodeEvaluation e = eval::evaluate_episode(ep, {method}, o, true);
  const eval::MethodOutcome& oc = e.outcomes.front();
  if (oc.status == "failed")
    throw Error::in_file(a.episode, oc.method == Method::kFm ? "fm: " + oc.message : oc.message);
  std::vector<std::string> files;
  if (!oc.mask.empty()) {
    cv::Mat1b truth;
    if (ep.info().has_masks && ep.info().target && oc.scored_frame >= 0) {
      truth = ep.mask(oc.scored_frame) == *ep.info().target;
    }
    if (!oc.map.empty()) {
      // 16-bit PNG: 65535 = probability 1 (for fm: 1 = moving, 0.375 = arm model).
      cv::Mat map16;
      oc.map.convertTo(map16, CV_16U, 65535.0);
      save_image(stage, a.out, "map.png", map16);
      files.push_back("map.png");
    }
    save_image(stage, a.out, "mask.png", oc.mask);
    save_image(stage, a.out, "overlay.png", overlay(oc.frame, oc.mask, truth));
    save_image(stage, a.out, "frame.png", oc.frame);
    files.insert(files.end(), {"mask.png", "overlay.png", "frame.png"});
    if (!truth.empty()) {
      save_image(stage, a.out, "truth.png", truth);
      files.push_back("truth.png");
    }
  }
  core::Json doc = core::result_document("proprio.segment", 1, inv.provenance());
  doc["episode"] = fs::path(a.episode).string();
  doc["method"] = eval::to_string(method);
  doc["status"] = oc.status;
  doc["message"] = oc.message;
  doc["scored_frame"] = oc.scored_frame;
  doc["first_touch_frame"] =
      e.first_touch_frame ? core::Json(*e.first_touch_frame) : core::Json(nullptr);
  doc["background"] = e.background;
  doc["object"] = e.object;
  doc["seconds"] = oc.seconds;
  doc["options"] = options_json(o);
  doc["metrics"] = oc.status == "ok" ? metrics_json(oc.metrics) : core::Json(nullptr);
  doc["files"] = files;
  write_json_result((stage / "segment.json").string(), doc);
  dir.commit();
  write_json_result(a.json, doc);
  if (oc.status == "no touch") {
    std::printf("%s: no touch (%s); nothing segmented\n", a.episode.c_str(), oc.message.c_str());
  } else {
    std::printf("%s: %s at frame %d in %.2f s\n", eval::to_string(method).c_str(),
                oc.message.c_str(), oc.scored_frame, oc.seconds);
    if (oc.status == "ok") {
      std::printf("precision %.3f, recall %.3f, Jaccard %.3f, L2 %.4f\n", oc.metrics.precision,
                  oc.metrics.recall, oc.metrics.jaccard, oc.metrics.l2);
    } else {
      std::printf("%s: not scored\n", oc.status.c_str());
    }
  }
  std::printf("wrote %s\n", a.out.c_str());
}

// ---- evaluate segmentation ----------------------------------------------------------------------

struct EvaluateArgs {
  std::string dataset;
  std::string methods = "ml,fm,ml-graphcut";
  std::string out;
  std::string json;
  int threads = 1;
  bool overwrite = false;
  bool all_frames = true;
  std::uint64_t seed = 1;
  MethodArgs m;
};

void run_evaluate(const EvaluateArgs& a, const Invocation& inv) {
  const std::vector<Method> methods = eval::parse_methods(a.methods);
  eval::EvalOptions o = eval_options(a.m);
  o.all_frames = a.all_frames;
  o.seed = a.seed;
  o.validate();
  const std::vector<fs::path> dirs = eval::list_episodes(a.dataset);
  core::StagedDirectory dir(a.out, a.overwrite);
  const fs::path stage = dir.staging_path();

  std::vector<eval::EpisodeEvaluation> results(dirs.size());
  std::atomic<std::size_t> next{0};
  std::mutex bar_mutex;
  core::ProgressBar bar(dirs.size(), "evaluate", true);
  auto worker = [&] {
    for (std::size_t i = next++; i < dirs.size(); i = next++) {
      eval::EpisodeEvaluation e;
      try {
        e = eval::evaluate_episode(episode::read_episode(dirs[i]), methods, o);
      } catch (const Error& err) {
        // An unreadable episode is reported, not fatal: every method "failed".
        e.dir = dirs[i];
        e.name = dirs[i].filename().string();
        e.background = "unknown";
        for (Method m : methods) {
          eval::MethodOutcome oc;
          oc.method = m;
          oc.status = "failed";
          oc.message = err.what();
          e.outcomes.push_back(oc);
        }
      }
      results[i] = std::move(e);
      const std::lock_guard<std::mutex> lock(bar_mutex);
      bar.tick();
    }
  };
  const int n = std::max(1, std::min<int>(a.threads, static_cast<int>(dirs.size())));
  std::vector<std::thread> pool;
  for (int k = 1; k < n; ++k) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();
  bar.finish();

  core::write_file_atomic(stage / "episodes.csv", eval::episodes_csv(results));
  const std::vector<std::string> plots = eval::write_plots(stage, results, methods, o);
  core::Json doc =
      core::result_document("proprio.evaluate.segmentation", 1, inv.provenance(a.seed));
  doc["dataset"] = fs::path(a.dataset).string();
  core::Json names = core::Json::array();
  for (Method m : methods) names.push_back(eval::to_string(m));
  doc["method_names"] = names;
  doc["options"] = options_json(o);
  doc.update(eval::dataset_summary_json(results, methods, o));
  core::Json per = core::Json::array();
  for (const auto& e : results) {
    core::Json j = {{"episode", e.name},
                    {"background", e.background},
                    {"object", e.object},
                    {"scenario", e.scenario}};
    for (const auto& oc : e.outcomes) {
      core::Json r = {{"status", oc.status}, {"scored_frame", oc.scored_frame}};
      r["jaccard"] = oc.status == "ok" ? core::Json(oc.metrics.jaccard) : core::Json(nullptr);
      j[eval::to_string(oc.method)] = std::move(r);
    }
    per.push_back(std::move(j));
  }
  doc["episode_results"] = std::move(per);
  doc["files"] = plots;
  write_json_result((stage / "summary.json").string(), doc);
  dir.commit();
  write_json_result(a.json, doc);

  std::printf("%zu episodes; mean Jaccard at the scored frame [95%% bootstrap interval]:\n",
              results.size());
  for (Method m : methods) {
    const auto& mj = doc["methods"][eval::to_string(m)];
    std::printf("  %-14s", eval::to_string(m).c_str());
    for (const char* g : {"static", "moving", "all"}) {
      const auto& s = mj[g];
      std::printf("  %s %.3f [%.3f, %.3f] (%d)", g, s["mean_jaccard"].get<double>(),
                  s["mean_jaccard_ci95"][0].get<double>(), s["mean_jaccard_ci95"][1].get<double>(),
                  s["episodes"].get<int>());
    }
    const auto& all = mj["all"];
    std::printf("; no touch %d, failed %d\n", all["no_touch"].get<int>(), all["failed"].get<int>());
  }
  std::printf("wrote %s (summary.json, episodes.csv, plots)\n", a.out.c_str());
}

}  // namespace

void register_segment_commands(CLI::App& root, const Invocation& inv) {
  auto seg = std::make_shared<SegmentArgs>();
  auto* cmd = root.add_subcommand(
      "segment",
      "Segment the pushed object of an episode (thesis Ch 4-5): Motion-Likelihood, its homography "
      "and sparse variants, the Fitzpatrick & Metta baseline, or M-L + graph cuts");
  cmd->add_option("episode", seg->episode, "Episode directory")->required();
  cmd->add_option("--method", seg->method, "ml, ml-homography, ml-sparse, fm or ml-graphcut")
      ->check(CLI::IsMember({"ml", "ml-homography", "ml-sparse", "fm", "ml-graphcut"}));
  cmd->add_option("--out", seg->out,
                  "Directory to write: map.png (16-bit), mask.png, overlay.png, frame.png, "
                  "truth.png, segment.json")
      ->required();
  cmd->add_option("--json", seg->json, "Also write the result as JSON to this file");
  cmd->add_flag("--overwrite", seg->overwrite, "Replace --out if it exists");
  add_method_options(cmd, seg->m);
  cmd->callback([seg, &inv] { run_segment(*seg, inv); });

  auto* evaluate = root.add_subcommand("evaluate", "Evaluations over datasets");
  evaluate->require_subcommand(1);
  auto ev = std::make_shared<EvaluateArgs>();
  auto* es = evaluate->add_subcommand(
      "segmentation",
      "Score segmentation methods on every episode of a dataset at the first-touch frame "
      "(thesis 5.1-5.2): P-R curves, Jaccard, L2, KS tests, CSV, plots and a JSON summary");
  es->add_option("dataset", ev->dataset, "Directory of episode directories")->required();
  es->add_option("--methods", ev->methods,
                 "Comma-separated: ml, ml-homography, ml-sparse, fm, ml-graphcut");
  es->add_option("--out", ev->out, "Directory to write")->required();
  es->add_option("--json", ev->json, "Also write the summary to this file");
  es->add_option("--threads", ev->threads, "Episodes evaluated at once")->check(CLI::Range(1, 256));
  es->add_flag("--overwrite", ev->overwrite, "Replace --out if it exists");
  es->add_flag("!--no-all-frames", ev->all_frames,
               "Skip M-L's mean over every frame from the first touch on (faster)");
  es->add_option("--seed", ev->seed, "Seed of the bootstrap");
  add_method_options(es, ev->m);
  es->callback([ev, &inv] { run_evaluate(*ev, inv); });
}

}  // namespace proprio::app
