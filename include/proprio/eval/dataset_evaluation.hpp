#pragma once
// `proprio evaluate segmentation` as a library call: the Chapter 5 evaluation over a dataset
// directory (thesis 5.1-5.2), episodes evaluated in parallel, written as summary.json,
// episodes.csv and plots.

#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "proprio/core/json_io.hpp"
#include "proprio/core/provenance.hpp"
#include "proprio/eval/segmentation_eval.hpp"

namespace proprio::eval {

struct DatasetEvaluationOptions {
  std::filesystem::path dataset;  ///< a directory of episode directories (required)
  std::filesystem::path out;      ///< directory to write (required)
  bool overwrite = false;         ///< replace `out` when it exists (else it must not)
  std::vector<Method> methods = {Method::kMl, Method::kFm, Method::kMlGraphCut};
  /// Episodes evaluated at once (each episode's result is the same for any count).
  int threads = 1;
  bool progress = false;  ///< a progress bar on stderr
  EvalOptions eval = {};  ///< the methods' options, sweeps, all_frames and the bootstrap seed

  /// Throws Error naming the first bad option.
  void validate() const;
};

// The implicit noexcept move of core::Json (nlohmann's) calls its assert_invariant(), which
// clang-tidy 14 cannot prove free of exceptions.
// NOLINTNEXTLINE(bugprone-exception-escape)
struct DatasetEvaluationResult {
  std::vector<Method> methods;
  /// One per episode, sorted by directory name. An episode that cannot be read is kept, with
  /// every method "failed" and the reason as its message: one bad episode does not stop the run.
  std::vector<EpisodeEvaluation> episodes;
  /// Per method (in `methods` order): the static, moving and all-episodes summaries.
  std::vector<std::array<GroupSummary, 3>> by_background;
  std::vector<std::string> files;  ///< plots written into `out`
  /// summary.json as written (format "proprio.evaluate.segmentation").
  core::Json document;

  /// Mean Jaccard per method and background with intervals, in a few lines (what the CLI prints).
  [[nodiscard]] std::string brief() const;
};

/// Evaluates every episode of the dataset (episode::list_episode_dirs) on `threads` threads and
/// writes `out` atomically: summary.json, episodes.csv and the plots.
DatasetEvaluationResult run_dataset_evaluation(const DatasetEvaluationOptions& options,
                                               const core::Provenance& provenance);

}  // namespace proprio::eval
