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
  EvalOptions options;             ///< the evaluation options used
  DatasetSummary summary;          ///< its members are the record's

  /// One method's outcome on one episode, as summary.json lists it.
  struct OutcomeRecord {
    const MethodOutcome* outcome;
    template <class Self, class Visitor>
    static void describe(Self& self, Visitor& v) {
      const MethodOutcome& oc = *self.outcome;
      v(oc.status, {"status", "ok, no touch, no ground truth or failed"});
      v(oc.scored_frame, {"scored_frame", "The frame scored (-1: none)"});
      v(core::or_null(oc.status == "ok" ? std::optional<double>(oc.metrics.jaccard) : std::nullopt),
        {"jaccard", "Jaccard at the scored frame (null unless ok)"});
    }
  };
  /// An episode's facts and each method's outcome (keyed by the method's name).
  struct EpisodeRecord {
    const EpisodeEvaluation* episode;
    template <class Self, class Visitor>
    static void describe(Self& self, Visitor& v) {
      const EpisodeEvaluation& e = *self.episode;
      v(e.name, {"episode", "The episode directory's name"});
      v(e.background, {"background", "static, moving or unknown"});
      v(e.object, {"object", "The target's name"});
      v(e.scenario, {"scenario", "The scenario"});
      for (const MethodOutcome& oc : e.outcomes) {
        const std::string& name = method_key(oc.method);
        v(OutcomeRecord{&oc}, {name.c_str(), "The method's outcome"});
      }
    }
  };
  [[nodiscard]] std::vector<EpisodeRecord> episode_results() const {
    std::vector<EpisodeRecord> out;
    out.reserve(episodes.size());
    for (const EpisodeEvaluation& e : episodes) out.push_back({&e});
    return out;
  }
  /// The method's name, as a record's key (a name that outlives the description's visit).
  static const std::string& method_key(Method m);
  /// summary.json as written (format "proprio.evaluate.segmentation"): the fields described
  /// below.
  core::Json document;

  /// Mean Jaccard per method and background with intervals, in a few lines (what the CLI prints).
  std::string message;  ///< one line: what happened (brief()'s first line)
  [[nodiscard]] std::string brief() const;
  /// The methods' names, in `methods` order.
  [[nodiscard]] std::vector<std::string> method_names() const;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.dataset, {"dataset", "The dataset directory"});
    v(self.method_names(), {"method_names", "The methods, in order"});
    v(self.options, {"options", "The evaluation options"});
    DatasetSummary::describe(self.summary, v);
    v(self.episode_results(), {"episode_results", "Per episode: facts and outcomes"});
    v(self.files, {"files", "Plots written"});
  }
};

/// Evaluates every episode of the dataset (episode::list_episode_dirs) on `threads` threads and
/// writes `out` atomically: summary.json, episodes.csv and the plots.
DatasetEvaluationResult run_dataset_evaluation(const DatasetEvaluationOptions& options,
                                               const core::Provenance& provenance);

}  // namespace proprio::eval
