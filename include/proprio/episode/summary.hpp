#pragma once
// A short description of an episode, for `proprio episode info`.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "proprio/core/fields.hpp"
#include "proprio/core/json_io.hpp"
#include "proprio/core/provenance.hpp"
#include "proprio/episode/episode.hpp"

namespace proprio::episode {

/// An object as `episode info` lists it.
struct EpisodeObjectRecord {
  int id = 0;
  std::string name;
  std::string role;
  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.id, {"id", "Its value in the masks"});
    v(self.name, {"name", "Its name"});
    v(self.role, {"role", "target, object, arm or distractor"});
  }
};

/// Width and height of the frames, pixels.
struct ImageSizeRecord {
  int width = 0;
  int height = 0;
  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.width, {"width", "Frame width, px"});
    v(self.height, {"height", "Frame height, px"});
  }
};

/// The arm's name and joints.
struct ArmRecord {
  std::string name;
  int joints = 0;
  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.name, {"name", "The arm"});
    v(self.joints, {"joints", "Its joints"});
  }
};

// NOLINTNEXTLINE(bugprone-exception-escape)
struct EpisodeSummary {
  std::string dir;
  int frames = 0;
  double fps = 0.0;
  double duration = 0.0;    ///< seconds: frame_count / fps
  double first_time = 0.0;  ///< arm.csv's t of the first and last frames, seconds
  double last_time = 0.0;
  int width = 0;
  int height = 0;
  std::string arm;
  int joints = 0;
  Source source = Source::kSimulated;
  std::optional<std::uint64_t> seed;
  std::optional<std::string> scenario;
  core::Json switches = core::Json::object();
  std::optional<int> target;
  std::optional<std::string> target_name;
  std::vector<ObjectInfo> objects;
  std::optional<int> first_touch_frame;
  int touching_frames = 0;
  FrameStorage storage = FrameStorage::kPng;
  bool masks = false;
  bool depth = false;
  bool stereo = false;

  /// Output only: the record of `episode info` (docs/formats/schemas/episode_info.schema.json).
  /// The switches stay a JSON object: an episode's provenance may hold any (an imported one's).
  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.dir, {"dir", "The episode directory"});
    v(self.frames, {"frames", "Frames"});
    v(self.fps, {"fps", "Frame rate"});
    v(self.duration, {"duration_s", "frames / fps, s"});
    v(std::vector<double>{self.first_time, self.last_time},
      {"time_span_s", "arm.csv's t of the first and last frames, s"});
    v(ImageSizeRecord{self.width, self.height}, {"image", "Frame size"});
    v(ArmRecord{self.arm, self.joints}, {"arm", "The arm"});
    v(to_string(self.source), {"source", "simulated or real"});
    v(core::or_null(self.seed), {"seed", "The recording's seed (null: none)"});
    v(core::or_null(self.scenario), {"scenario", "What the recording shows (null: none)"});
    v(self.switches, {"switches", "The scenario's switches"});
    v(core::or_null(self.target), {"target", "The target's id (null: none)"});
    v(core::or_null(self.target_name), {"target_name", "The target's name (null: none)"});
    v(object_records(self.objects), {"objects", "The objects"});
    v(core::or_null(self.first_touch_frame), {"first_touch_frame", "null: no touch"});
    v(self.touching_frames, {"touching_frames", "Frames the arm touches"});
    v(to_string(self.storage), {"storage", "png or video"});
    v(self.masks, {"masks", "Ground-truth masks"});
    v(self.depth, {"depth", "Depth images"});
    v(self.stereo, {"stereo", "A stereo pair"});
  }

  [[nodiscard]] static std::vector<EpisodeObjectRecord> object_records(
      const std::vector<ObjectInfo>& objects);
};

EpisodeSummary summarize(const Episode& episode);

/// The summary's fields as JSON (its description's; to add to a result document).
inline core::Json to_json(const EpisodeSummary& s) { return core::fields_to_json(s); }

/// What `proprio episode info` does: read the episode (with every cheap check) and summarise it.
// NOLINTNEXTLINE(bugprone-exception-escape)
struct EpisodeInfoResult {
  EpisodeSummary summary;
  core::Json document;  ///< "proprio.episode.info" version 1: provenance, then the summary
  /// One line: the episode, its frames and its scenario.
  std::string message;
  /// Human-readable lines, "key: value" (format_summary).
  [[nodiscard]] std::string brief() const;
};

EpisodeInfoResult run_episode_info(const std::filesystem::path& dir,
                                   const core::Provenance& provenance);

/// Human-readable lines, "key: value".
std::string format_summary(const EpisodeSummary& s);

}  // namespace proprio::episode
