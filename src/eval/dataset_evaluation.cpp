#include "proprio/eval/dataset_evaluation.hpp"

#include <fmt/format.h>

#include <map>
#include <mutex>

#include "proprio/core/error.hpp"
#include "proprio/core/files.hpp"
#include "proprio/core/parallel.hpp"
#include "proprio/core/progress.hpp"
#include "proprio/episode/discovery.hpp"
#include "proprio/episode/episode.hpp"

namespace proprio::eval {
namespace fs = std::filesystem;

void DatasetEvaluationOptions::validate() const {
  require(!dataset.empty(), "evaluate: no dataset given");
  require(!out.empty(), "evaluate: no output directory given");
  require(!methods.empty(), "evaluate: no method given");
  require(threads >= 1 && threads <= 256, "evaluate: threads must be in [1, 256]");
  eval.validate();
}

namespace {

// An episode that could not be read: kept in the results with every method "failed".
EpisodeEvaluation unreadable(const fs::path& dir, const std::vector<Method>& methods,
                             const std::string& why) {
  EpisodeEvaluation e;
  e.dir = dir;
  e.name = dir.filename().string();
  e.background = "unknown";
  for (Method m : methods) {
    MethodOutcome oc;
    oc.method = m;
    oc.status = "failed";
    oc.message = why;
    e.outcomes.push_back(oc);
  }
  return e;
}

}  // namespace

DatasetEvaluationResult run_dataset_evaluation(const DatasetEvaluationOptions& options,
                                               const core::Provenance& provenance) {
  options.validate();
  core::require_output_not_input(options.out, {options.dataset}, "--out");
  const std::vector<fs::path> dirs = episode::list_episode_dirs(options.dataset);
  core::StagedDirectory dir(options.out, options.overwrite);
  const fs::path stage = dir.staging_path();

  DatasetEvaluationResult r;
  r.methods = options.methods;
  r.episodes.resize(dirs.size());
  core::ProgressBar bar(dirs.size(), "evaluate", options.progress);
  std::mutex bar_mutex;
  core::parallel_for(dirs.size(), options.threads, [&](std::size_t i, int) {
    try {
      r.episodes[i] =
          evaluate_episode(episode::read_episode(dirs[i]), options.methods, options.eval);
    } catch (const Error& err) {
      // An unreadable episode is reported, not fatal.
      r.episodes[i] = unreadable(dirs[i], options.methods, err.what());
    }
    const std::lock_guard<std::mutex> lock(bar_mutex);
    bar.tick();
  });
  bar.finish();

  for (std::size_t k = 0; k < r.methods.size(); ++k) {
    const auto& sweep =
        r.methods[k] == Method::kFm ? options.eval.threshold_sweep : options.eval.fraction_sweep;
    r.by_background.push_back({summarise(r.episodes, k, sweep, options.eval, "static"),
                               summarise(r.episodes, k, sweep, options.eval, "moving"),
                               summarise(r.episodes, k, sweep, options.eval)});
  }

  core::write_file_atomic(stage / "episodes.csv", episodes_csv(r.episodes));
  r.files = write_plots(stage, r.episodes, r.methods, options.eval);
  r.dataset = options.dataset;
  r.options = options.eval;
  r.summary = dataset_summary(r.episodes, r.methods, options.eval);
  r.document = core::result_document("proprio.evaluate.segmentation", 1, provenance);
  core::fields_into_json(r, r.document);
  core::write_json_atomic(stage / "summary.json", r.document);
  dir.commit();
  r.message = core::first_line(r.brief());
  return r;
}

const std::string& DatasetEvaluationResult::method_key(Method m) {
  // One string per method for the program's life: a description's field names are C strings.
  static const std::map<Method, std::string> kNames = [] {
    std::map<Method, std::string> n;
    for (Method k : {Method::kMl, Method::kMlHomography, Method::kMlSparse, Method::kFm,
                     Method::kMlGraphCut, Method::kMlDepth})
      n.emplace(k, to_string(k));
    return n;
  }();
  return kNames.at(m);
}

std::vector<std::string> DatasetEvaluationResult::method_names() const {
  std::vector<std::string> names;
  names.reserve(methods.size());
  for (Method m : methods) names.emplace_back(to_string(m));
  return names;
}

std::string DatasetEvaluationResult::brief() const {
  std::string s = fmt::format(
      "{} episodes; mean Jaccard at the scored frame [95% bootstrap interval]:\n", episodes.size());
  for (std::size_t k = 0; k < methods.size(); ++k) {
    s += fmt::format("  {:<14}", to_string(methods[k]));
    const char* names[] = {"static", "moving", "all"};
    for (std::size_t g = 0; g < 3; ++g) {
      const GroupSummary& sum = by_background[k][g];
      s += fmt::format("  {} {:.3f} [{:.3f}, {:.3f}] ({})", names[g], sum.mean_jaccard,
                       sum.jaccard_ci95.lower, sum.jaccard_ci95.upper, sum.episodes);
    }
    const GroupSummary& all = by_background[k][2];
    s += fmt::format("; no touch {}, failed {}\n", all.no_touch, all.failed);
  }
  return s;
}

}  // namespace proprio::eval
