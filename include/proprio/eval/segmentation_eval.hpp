#pragma once
// The Chapter 5 evaluation of object segmentation (thesis 5.1-5.2, SPEC §3): every method run on
// every episode of a dataset, scored against the target's ground-truth mask at the scored frame
// (the first touch: M-L's map there integrates the whole episode; the baseline is scored on the
// same frame), with P-R curves over each method's free parameter, means with bootstrap
// intervals, KS tests between methods, grouped by the episode's background switch.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

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

/// The dataset's JSON summary (without the result-document header):
/// {"methods": {"ml": {"static": {...}, "moving": {...}, "all": {...}, "by_object": {...},
/// "by_scenario": {...}}, ...}, "ks": {"ml_vs_fm": {"statistic", "p_value", "static": {...},
/// "moving": {...}}, ...}, "episodes": N}. KS on the per-episode Jaccard indices.
core::Json dataset_summary_json(const std::vector<EpisodeEvaluation>& episodes,
                                const std::vector<Method>& methods, const EvalOptions& options);

/// The options as segment.json and summary.json record them ("options").
core::Json options_json(const EvalOptions& options);
/// A mask's scores as segment.json records them ("metrics"), the Tanimoto distance included.
core::Json metrics_json(const MaskMetrics& metrics);

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
