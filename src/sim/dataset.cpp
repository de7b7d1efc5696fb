#include "proprio/sim/dataset.hpp"

#include <cstdio>

#include "proprio/core/error.hpp"
#include "proprio/core/files.hpp"
#include "proprio/core/progress.hpp"
#include "proprio/sim/object_catalogue.hpp"

namespace proprio::sim {
namespace {

namespace fs = std::filesystem;

constexpr int kSeedsPerPush = 6;         // episodes per object and background
constexpr int kHomographyEpisodes = 10;  // episodes per homography scenario
constexpr int kDisturbanceKinds = 3;     // camera shake, lighting change, neighbour nudged

}  // namespace

void SimDatasetOptions::validate() const {
  if (preset != "thesis-ch5") throw Error("sim dataset: unknown preset '" + preset + "'");
  if (out.empty()) throw Error("sim dataset: the output directory is required");
  core::check_field_bounds(*this, "sim dataset");
}

std::vector<DatasetEntry> dataset_design(const SimDatasetOptions& options) {
  std::vector<DatasetEntry> list;
  std::uint64_t seed = options.seed;
  auto base = [&] {
    RecordOptions o;
    o.width = options.width;
    o.height = options.height;
    o.seed = seed++;
    if (options.frames > 0) o.max_frames = options.frames;
    return o;
  };
  for (const char* object : {"rabbit", "mug", "spirit-level", "bottle", "book"}) {
    for (const bool moving : {false, true}) {
      for (int k = 0; k < kSeedsPerPush; ++k) {
        RecordOptions o = base();
        o.object = object;
        o.moving_background = moving;
        if (moving) {
          o.camera_shake = k % kDisturbanceKinds == 0;
          o.lighting_change = k % kDisturbanceKinds == 1;
          o.nudge_neighbour = k % kDisturbanceKinds == 2;
        }
        std::string name = "push_";
        name += object;
        name += moving ? "_moving_" : "_static_";
        name += std::to_string(k);
        list.push_back({name, o});
      }
    }
  }
  struct Homography {
    const char* scenario;
    const char* object;
  };
  for (const Homography h : {Homography{"push-rotate", "bottle"}, Homography{"hold-3d", "box"},
                             Homography{"hold-3d", "spirit-level"}}) {
    for (int k = 0; k < kHomographyEpisodes; ++k) {
      RecordOptions o = base();
      o.scenario = h.scenario;
      o.object = h.object;
      std::string name = "homography_";
      name += h.scenario;
      name += '_';
      name += h.object;
      name += '_';
      name += std::to_string(k);
      list.push_back({name, o});
    }
  }
  if (options.episodes > 0 && static_cast<std::size_t>(options.episodes) < list.size())
    list.resize(static_cast<std::size_t>(options.episodes));
  return list;
}

std::string SimDatasetResult::brief() const {
  char line[160];
  std::snprintf(line, sizeof line, "episodes: %zu\nframes: %d\nfps: %.2f", design.size(), frames,
                fps());
  return line;
}

SimDatasetResult run_sim_dataset(const SimDatasetOptions& options,
                                 const core::Provenance& provenance) {
  options.validate();
  SimDatasetResult r;
  r.design = dataset_design(options);
  if (fs::exists(options.out)) throw Error::in_file(options.out, "already exists");
  const auto catalogue = ObjectCatalogue::load_default();
  core::StagedDirectory staged(options.out);
  core::ProgressBar bar(r.design.size(), "sim dataset", options.progress);
  for (const auto& [name, o] : r.design) {
    core::Provenance p = provenance;
    p.seed = o.seed;
    const RecordSummary s = record_episode(staged.staging_path() / name, o, p, catalogue);
    r.frames += s.frames;
    r.seconds += s.seconds;
    r.episodes.push_back({name, o.scenario, o.switches(), s.frames});
    bar.tick();
  }
  bar.finish();
  staged.commit();
  r.preset = options.preset;
  r.out = options.out;
  r.document = core::result_document("proprio.sim.dataset", 1, provenance);
  core::fields_into_json(r, r.document);
  r.message = core::first_line(r.brief());
  return r;
}

}  // namespace proprio::sim
