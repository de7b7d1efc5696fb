#pragma once
// `proprio sim dataset` as a library call: the design of a preset set of episodes (today the
// Chapter 5 set, thesis 5.1-5.2) and its recording into one directory that appears whole or not
// at all.

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "proprio/core/fields.hpp"
#include "proprio/core/json_io.hpp"
#include "proprio/core/provenance.hpp"
#include "proprio/sim/recorder.hpp"

namespace proprio::sim {

struct SimDatasetOptions {
  std::string preset = "thesis-ch5";  ///< the only preset so far
  std::filesystem::path out;          ///< directory to create (required; must not exist)
  int frames = 0;                     ///< at most this many frames per episode; 0: the scenario's
  int episodes = 0;                   ///< only the first N episodes of the design; 0: all
  int width = 640;                    ///< image width, px
  int height = 480;                   ///< image height, px
  std::uint64_t seed = 1;             ///< the first episode's seed; the others follow it by 1
  bool progress = false;              ///< a progress bar on stderr

  /// Throws Error naming the first bad option.
  void validate() const;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.frames,
      {"frames", "At most this many frames per episode (0: the scenario's)", core::at_least(0)});
    v(self.episodes,
      {"episodes", "Only the first N episodes of the preset (0: all)", core::at_least(0)});
    v(self.width, {"width", "Image width, pixels", core::between(16, 8192)});
    v(self.height, {"height", "Image height, pixels", core::between(16, 8192)});
    v(self.seed, {"seed", "Seed of the first episode"});
  }
};

/// One episode of a design: its directory name and how it is recorded.
struct DatasetEntry {
  std::string name;
  RecordOptions options;
};

/// The Chapter 5 set: the five objects pushed with static and moving backgrounds (6 seeds each,
/// 60 episodes), then 10 episodes each of the rotating bottle (push-rotate), the held box and
/// the held spirit level (hold-3d) for the homography experiments; seeds options.seed,
/// options.seed + 1, ... in this order. Every moving episode has the disturbances of the
/// thesis's experiment (a) (SPEC 3): people walking behind (the video backdrop) and moving
/// distractors, plus, cycling over k, camera shake (k = 0, 3), a lighting change (k = 1, 4) or a
/// neighbouring object nudged (k = 2, 5). Cut to options.episodes when that is set.
std::vector<DatasetEntry> dataset_design(const SimDatasetOptions& options);

/// One recorded episode of a dataset, as its record lists it.
// NOLINTNEXTLINE(bugprone-exception-escape)
struct DatasetEpisode {
  std::string episode;   ///< directory name
  std::string scenario;  ///< RecordOptions::scenario
  RecordSwitches switches;
  int frames = 0;  ///< frames recorded

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.episode, {"episode", "Directory name"});
    v(self.scenario, {"scenario", "The scenario"});
    v(self.switches, {"switches", "The recording's switches"});
    v(self.frames, {"frames", "Frames recorded"});
  }
};

// NOLINTNEXTLINE(bugprone-exception-escape)
struct SimDatasetResult {
  std::vector<DatasetEntry> design;
  std::string preset;                    ///< SimDatasetOptions::preset
  std::filesystem::path out;             ///< the directory written
  std::vector<DatasetEpisode> episodes;  ///< in the design's order
  int frames = 0;
  double seconds = 0.0;  ///< recording, wall clock
  /// Format "proprio.sim.dataset" (sim_dataset.schema.json): the fields described below.
  core::Json document;

  std::string message;  ///< one line: what happened (brief()'s first line)
  [[nodiscard]] std::string brief() const;
  /// Frames recorded per second of wall clock (0 when no time was measured).
  [[nodiscard]] double fps() const { return seconds > 0 ? frames / seconds : 0.0; }

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.preset, {"preset", "The preset"});
    v(self.out, {"out", "The directory written"});
    v(self.episodes, {"episodes", "The episodes recorded"});
    v(self.frames, {"frames", "Frames recorded"});
    v(self.seconds, {"seconds", "Recording time, wall clock, s"});
    v(self.fps(), {"fps", "Frames per second of wall clock"});
  }
};

/// Records every episode of the design into a staging directory renamed to `out` at the end.
/// Each episode's provenance is `provenance` with its own seed.
SimDatasetResult run_sim_dataset(const SimDatasetOptions& options,
                                 const core::Provenance& provenance);

}  // namespace proprio::sim
