#pragma once
// A short description of an episode, for `proprio episode info`.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "proprio/core/json_io.hpp"
#include "proprio/episode/episode.hpp"

namespace proprio::episode {

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
};

EpisodeSummary summarize(const Episode& episode);

/// The summary's fields as JSON (to add to a result document).
core::Json to_json(const EpisodeSummary& s);

/// Human-readable lines, "key: value".
std::string format_summary(const EpisodeSummary& s);

}  // namespace proprio::episode
