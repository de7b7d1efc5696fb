#pragma once
// `proprio evaluate segmentation` as a library call: the Chapter 5 evaluation over a dataset
// directory (thesis 5.1-5.2), episodes evaluated in parallel, written as summary.json,
// episodes.csv and plots.

#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "proprio/core/fields.hpp"
#include "proprio/core/json_io.hpp"
#include "proprio/core/json_members.hpp"
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
  std::filesystem::path dataset;   ///< the dataset directory evaluated
  core::Json options;              ///< the evaluation options used (options_json)
  core::Json summary;              ///< dataset_summary_json: its members are the record's
  core::Json episode_results;      ///< per episode: its facts and each method's outcome
  /// summary.json as written (format "proprio.evaluate.segmentation"): the fields described
  /// below.
  core::Json document;

  /// Mean Jaccard per method and background with intervals, in a few lines (what the CLI prints).
  [[nodiscard]] std::string brief() const;
  /// The methods' names, in `methods` order.
  [[nodiscard]] std::vector<std::string> method_names() const;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.dataset, {"dataset", "The dataset directory"});
    v(self.method_names(), {"method_names", "The methods, in order"});
    v(self.options, {"options", "The evaluation options"});
    core::describe_json_members(self.summary, v);
    v(self.episode_results, {"episode_results", "Per episode: facts and outcomes"});
    v(self.files, {"files", "Plots written"});
  }
};

/// Evaluates every episode of the dataset (episode::list_episode_dirs) on `threads` threads and
/// writes `out` atomically: summary.json, episodes.csv and the plots.
DatasetEvaluationResult run_dataset_evaluation(const DatasetEvaluationOptions& options,
                                               const core::Provenance& provenance);

}  // namespace proprio::eval
