#pragma once
// The Chapter 5 evaluation of object segmentation (thesis 5.1-5.2, SPEC §3): every method run on
// every episode of a dataset, scored against the target's ground-truth mask at the scored frame
// (the first touch: M-L's map there integrates the whole episode; the baseline is scored on the
// same frame), with P-R curves over each method's free parameter, means with bootstrap
// intervals, KS tests between methods, grouped by the episode's background switch.

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "proprio/core/fields.hpp"
#include "proprio/core/json_io.hpp"
#include "proprio/episode/episode.hpp"
#include "proprio/eval/mask_metrics.hpp"
#include "proprio/eval/statistics.hpp"
#include "proprio/segmentation/fm_baseline.hpp"
#include "proprio/segmentation/graph_cut.hpp"
#include "proprio/segmentation/ml_segmentation.hpp"

namespace proprio::eval {

/// Segmentation methods: M-L with the translation model, with the homography model, the sparse
/// variant, the Fitzpatrick & Metta baseline, M-L followed by graph cuts, and M-L's depth variant
/// (thesis 9.2: 3-D region motion and depth steps; needs episodes with depth).
enum class Method { kMl, kMlHomography, kMlSparse, kFm, kMlGraphCut, kMlDepth };
[[nodiscard]] std::string to_string(
    Method m);  ///< "ml", "ml-homography", "ml-sparse", "fm", "ml-graphcut", "ml-depth"
/// The method named `s`; Error listing the names otherwise.
Method parse_method(const std::string& s);
/// Comma-separated names; Error on an unknown or repeated name or an empty list.
std::vector<Method> parse_methods(const std::string& list);
/// The free parameter each P-R curve sweeps: "mask_fraction" (M-L variants and ml-graphcut) or
/// "difference_threshold" (fm).
[[nodiscard]] std::string free_parameter(Method m);

struct EvalOptions {
  segmentation::MlOptions ml = {};  ///< translation; kMlHomography / kMlDepth switch it
  segmentation::SparseOptions sparse = {};
  segmentation::FmOptions fm = {};
  segmentation::MlGraphCutOptions ml_graph_cut = {};
  /// Sweep values of the free parameters (P-R curves).
  std::vector<double> fraction_sweep = {0.05, 0.15, 0.25, 0.35, 0.45, 0.55, 0.65, 0.75, 0.85, 0.95};
  std::vector<double> threshold_sweep = {1, 2, 3, 5, 8, 12, 16, 24, 32, 48, 64};
  /// Also score M-L on every frame from the first touch on that has ground truth.
  bool all_frames = true;
  int bootstrap_resamples = 2000;
  std::uint64_t seed = 1;  ///< of the bootstrap
  void validate() const;   ///< throws Error naming the bad field

  /// The options as segment.json and summary.json record them ("options"). Output only: the
  /// commands bind the methods' options from their own descriptions (MlOptions, FmOptions).
  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.ml.mask_fraction, {"mask_fraction", "M-L mask fraction"});
    v(self.ml.depth_mask_fraction, {"depth_mask_fraction", "ml-depth's mask fraction"});
    v(self.fm.difference_threshold, {"difference_threshold", "Baseline's threshold"});
    v.choice(self.fm.touch, {"fm_touch", "Baseline's touch frame"},
             segmentation::kTouchSourceNames);
    v(self.ml_graph_cut.unary_weight, {"ml_graphcut_unary_weight", "ml-graphcut's unary weight"});
    v(self.ml_graph_cut.graph_cut.smoothness, {"graph_cut_smoothness", "Graph cut smoothness"});
    v(self.ml_graph_cut.graph_cut.max_side, {"graph_cut_max_side", "Graph cut's largest side"});
    v(self.fraction_sweep, {"fraction_sweep", "Mask fractions of the P-R curves"});
    v(self.threshold_sweep, {"threshold_sweep", "Thresholds of the baseline's P-R curve"});
  }
};

/// One method on one episode.
struct MethodOutcome {
  Method method = Method::kMl;
  /// "ok", "no touch", "no ground truth" (no masks, no target, or the target not visible at the
  /// scored frame), or "failed" (the method threw Error; see message).
  std::string status;
  std::string message;
  int scored_frame = -1;
  MaskMetrics metrics;  ///< at the scored frame (status ok)
  /// precision and recall at each sweep value (status ok).
  std::vector<double> sweep_precision, sweep_recall;
  /// Mean Jaccard over the frames from the first touch on with ground truth (M-L, ml-homography
  /// when EvalOptions::all_frames); none otherwise.
  std::optional<double> all_frames_jaccard;
  int all_frames_count = 0;
  double seconds = 0.0;
  /// Outputs for `proprio segment` (kept only when asked): map at the scored frame (M-L
  /// variants), mask, and the frame.
  cv::Mat1f map;
  cv::Mat1b mask;
  cv::Mat frame;
};

struct EpisodeEvaluation {
  std::filesystem::path dir;
  std::string name;        ///< the directory's name
  std::string scenario;    ///< provenance scenario, "" when none
  std::string object;      ///< the target's name (objects.json), "" when none
  std::string background;  ///< provenance switch "background": "static", "moving" or "unknown"
  std::optional<int> first_touch_frame;
  std::vector<MethodOutcome> outcomes;  ///< in the order of the methods asked for
};

/// Runs `methods` on `episode` and scores them. `keep_images` keeps maps, masks and the frame in
/// the outcomes. Errors of a method are caught into its outcome (status "failed"); an episode
/// with no frames or no arm data throws Error.
EpisodeEvaluation evaluate_episode(const episode::Episode& episode,
                                   const std::vector<Method>& methods, const EvalOptions& options,
                                   bool keep_images = false);

/// Aggregates of one method over one group of episodes.
struct GroupSummary {
  int episodes = 0;  ///< scored (status ok)
  int no_touch = 0, no_ground_truth = 0, failed = 0;
  double mean_jaccard = 0.0, std_jaccard = 0.0;
  Interval jaccard_ci95;
  double mean_precision = 0.0, mean_recall = 0.0, mean_l2 = 0.0, std_l2 = 0.0;
  double mean_tanimoto = 0.0;
  std::optional<double> mean_jaccard_all_frames;
  int all_frames_episodes = 0;
  /// P-R curve: mean precision and recall over the group's episodes at each sweep value, and the
  /// index of the point closest to (1, 1).
  std::vector<double> sweep_values, pr_precision, pr_recall;
  int pr_best = -1;
  double mean_seconds = 0.0;
  std::vector<double> jaccards;  ///< per scored episode (for KS)

  /// A point of the P-R curve.
  struct PrPoint {
    double value = 0, precision = 0, recall = 0;
    template <class Self, class Visitor>
    static void describe(Self& self, Visitor& v) {
      v(self.value, {"value", "The free parameter"});
      v(self.precision, {"precision", "Mean precision"});
      v(self.recall, {"recall", "Mean recall"});
    }
  };
  /// The P-R curve as records write it: values, precision, recall, best (null: none).
  struct PrCurve {
    const GroupSummary* g;
    template <class Self, class Visitor>
    static void describe(Self& self, Visitor& v) {
      v(self.g->sweep_values, {"values", "The free parameter's values"});
      v(self.g->pr_precision, {"precision", "Mean precision at each"});
      v(self.g->pr_recall, {"recall", "Mean recall at each"});
      v(core::or_null(self.g->best_point()), {"best", "The point nearest (1, 1) (null: none)"});
    }
  };
  [[nodiscard]] std::optional<PrPoint> best_point() const {
    if (pr_best < 0) return std::nullopt;
    const auto b = static_cast<std::size_t>(pr_best);
    return PrPoint{sweep_values[b], pr_precision[b], pr_recall[b]};
  }

  /// Output only: summary.json's record of a group.
  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.episodes, {"episodes", "Episodes scored"});
    v(self.no_touch, {"no_touch", "Episodes without a touch"});
    v(self.no_ground_truth, {"no_ground_truth", "Episodes without ground truth"});
    v(self.failed, {"failed", "Episodes the method failed on"});
    v(self.mean_jaccard, {"mean_jaccard", "Mean Jaccard"});
    v(self.std_jaccard, {"std_jaccard", "Its standard deviation"});
    v(self.jaccard_ci95.bounds(), {"mean_jaccard_ci95", "95% bootstrap interval of the mean"});
    v(self.mean_tanimoto, {"mean_tanimoto", "Mean Tanimoto distance"});
    v(self.mean_precision, {"mean_precision", "Mean precision"});
    v(self.mean_recall, {"mean_recall", "Mean recall"});
    v(self.mean_l2, {"mean_l2", "Mean L2"});
    v(self.std_l2, {"std_l2", "Its standard deviation"});
    v(self.mean_seconds, {"mean_seconds", "Mean time"});
    v(core::or_null(self.mean_jaccard_all_frames),
      {"mean_jaccard_all_frames", "Mean Jaccard over every frame from the touch (null: none)"});
    v(self.all_frames_episodes, {"all_frames_episodes", "Episodes in that mean"});
    v(PrCurve{&self}, {"pr", "The P-R curve"});
  }
};

/// Matches every episode in summarise's filters.
inline const std::string kAnyGroup = "*";

/// Summary of outcome `method_index` over the episodes whose background, object and scenario
/// equal the filters (kAnyGroup: any).
GroupSummary summarise(const std::vector<EpisodeEvaluation>& episodes, std::size_t method_index,
                       const std::vector<double>& sweep_values, const EvalOptions& options,
                       const std::string& background = kAnyGroup,
                       const std::string& object = kAnyGroup,
                       const std::string& scenario = kAnyGroup);

/// One method's summaries: by background, over all episodes, by object and by scenario.
struct MethodSummary {
  std::string parameter;  ///< free_parameter(method)
  GroupSummary static_background, moving_background, all;
  std::map<std::string, GroupSummary> by_object, by_scenario;  ///< "(none)" for none
  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.parameter, {"parameter", "The free parameter of the P-R curve"});
    v(self.static_background, {"static", "Episodes with a static background"});
    v(self.moving_background, {"moving", "Episodes with a moving background"});
    v(self.all, {"all", "Every episode"});
    v(self.by_object, {"by_object", "By target object"});
    v(self.by_scenario, {"by_scenario", "By scenario"});
  }
};

/// KS between two methods' per-episode Jaccard indices: over all episodes (flat), and by
/// background.
struct KsComparison {
  KsResult all, static_background, moving_background;
  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    KsResult::describe(self.all, v);
    v(std::string("jaccard"), {"metric", "The metric compared"});
    v(self.static_background, {"static", "Static backgrounds"});
    v(self.moving_background, {"moving", "Moving backgrounds"});
  }
};

/// The dataset's summary (summary.json's members after the header): {"methods": {"ml":
/// {"static", "moving", "all", "by_object", "by_scenario"}, ...}, "ks": {"ml_vs_fm": {...}, ...},
/// "episodes": N}. KS on the per-episode Jaccard indices.
struct DatasetSummary {
  std::map<std::string, MethodSummary> methods;  ///< by method name
  std::map<std::string, KsComparison> ks;        ///< "a_vs_b" for each pair in order
  std::size_t episodes = 0;
  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.methods, {"methods", "Each method's summaries"});
    v(self.ks, {"ks", "KS tests between the methods"});
    v(self.episodes, {"episodes", "Episodes in the dataset"});
  }
};

DatasetSummary dataset_summary(const std::vector<EpisodeEvaluation>& episodes,
                               const std::vector<Method>& methods, const EvalOptions& options);
/// dataset_summary as JSON (its description's).
inline core::Json dataset_summary_json(const std::vector<EpisodeEvaluation>& episodes,
                                       const std::vector<Method>& methods,
                                       const EvalOptions& options) {
  return core::fields_to_json(dataset_summary(episodes, methods, options));
}

/// One CSV row per episode and method.
std::string episodes_csv(const std::vector<EpisodeEvaluation>& episodes);

/// P-R curves by background and by object, and bar charts of mean Jaccard and L2 by object and
/// by background with standard-deviation error bars (like thesis Fig 5-3), written as PNG files
/// into `dir`: pr_by_background.png, pr_by_object.png, bars_jaccard.png, bars_l2.png. Returns
/// the file names.
std::vector<std::string> write_plots(const std::filesystem::path& dir,
                                     const std::vector<EpisodeEvaluation>& episodes,
                                     const std::vector<Method>& methods,
                                     const EvalOptions& options);

}  // namespace proprio::eval
