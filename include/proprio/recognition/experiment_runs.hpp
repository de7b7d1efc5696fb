#pragma once
// The library calls behind `proprio experiment dictionary | batch-online | scatter` (thesis
// 6.3.1-6.3.3, 7.3.1): the experiments of experiments.hpp from files, with the text the CLI
// prints and the record it writes for --json (experiment_sets / experiment_scatter schemas).

#include <filesystem>
#include <string>
#include <vector>

#include "proprio/core/json_io.hpp"
#include "proprio/core/provenance.hpp"
#include "proprio/recognition/experiments.hpp"

namespace proprio::recognition {

/// What an experiment command prints and records.
// NOLINTNEXTLINE(bugprone-exception-escape)
struct ExperimentRun {
  std::string report;
  core::Json document;
};

struct SetExperimentRunOptions {
  std::filesystem::path images;  ///< folder-per-class image set, Caltech-256's layout (required)
  /// The runs, seeds and sizes; runs empty: dictionary_runs() when `dictionary`, else
  /// batch_online_runs(). The batch, online and k-means seeds are set to options.seed.
  SetExperimentOptions options;
  bool dictionary = true;  ///< 6.3.1 (specific vs wide dictionary) or 6.3.2 (batch vs online)
  bool progress = false;
};

ExperimentRun run_set_experiment_files(const SetExperimentRunOptions& options,
                                       const core::Provenance& provenance);

struct ScatterExperimentRunOptions {
  std::vector<std::filesystem::path> episodes;  ///< training videos (episodes or their parents)
  std::filesystem::path views;                  ///< folder-per-object views, or
  std::vector<std::filesystem::path> view_episodes;  ///< held-out episodes to cut views from
  std::vector<std::string> objects;  ///< with view_episodes: the objects (catalogue names)
  std::filesystem::path vocabulary;  ///< a vocabulary file; none: built from the frames
  /// The experiment's options; view_features is set from frames.features (frames themselves get
  /// no centre crop: the region decides, and neither do segmented views).
  ScatterExperimentOptions options;
  /// With view_episodes: several seeds over one feature extraction (run_scatter_experiments),
  /// one run each; empty: options.seed alone.
  std::vector<std::uint64_t> seeds;
  bool progress = false;

  /// Throws Error unless exactly one of views and view_episodes is given, and objects with
  /// view_episodes.
  void validate() const;
};

ExperimentRun run_scatter_experiment_files(const ScatterExperimentRunOptions& options,
                                           const core::Provenance& provenance);

/// One run per seed of options.seeds (or options.seed alone), in that order; each run's
/// provenance records its seed. Throws Error for several seeds with views (only view episodes
/// share their features between seeds).
std::vector<ExperimentRun> run_scatter_experiments_files(const ScatterExperimentRunOptions& options,
                                                         const core::Provenance& provenance);

}  // namespace proprio::recognition
