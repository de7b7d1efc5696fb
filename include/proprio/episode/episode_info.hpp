#pragma once
// episode.json: what an episode is (docs/formats/episode.md).
//
// Conventions used by every file of an episode: the world frame is the robot base frame (metres,
// z up); cameras follow OpenCV (x right, y down, z forward; pixel centres at integer coordinates);
// extrinsics map world to camera, x_cam = R x_world + t; P = K [R | t] (eq 3.7).

#include <filesystem>
#include <optional>
#include <string>

#include "proprio/core/json_io.hpp"
#include "proprio/core/provenance.hpp"

namespace proprio::episode {

inline constexpr const char* kEpisodeFormat = "proprio.episode";
/// The newest episode.json format version this build reads and the one it writes.
inline constexpr int kEpisodeFormatVersion = 1;

/// Limits that catch absurd values in episode.json (a corrupt or hand-edited file) before any
/// allocation is sized by them.
inline constexpr int kMaxImageSide = 16384;      ///< pixels
inline constexpr int kMaxFrameCount = 10000000;  ///< about 4 days at 30 fps
inline constexpr double kMaxFps = 10000.0;
inline constexpr int kMaxJointCount = 64;

/// Where the recording came from.
enum class Source { kSimulated, kReal };
/// How the frames are stored: one PNG per frame (frames/000000.png, ...) or one video file.
enum class FrameStorage { kPng, kVideo };

[[nodiscard]] std::string to_string(Source s);        ///< "simulated" / "real"
[[nodiscard]] std::string to_string(FrameStorage s);  ///< "png" / "video"

/// Provenance of an episode: the run that wrote it, plus what was recorded.
struct EpisodeProvenance {
  core::Provenance run;  ///< program, build, command line, seed (required when simulated)
  Source source = Source::kSimulated;
  std::optional<std::string> scenario;         ///< scenario name; none for most real recordings
  core::Json switches = core::Json::object();  ///< the scenario's switches, a JSON object
};

/// The contents of episode.json.
struct EpisodeInfo {
  int format_version = kEpisodeFormatVersion;
  int frame_count = 0;  ///< >= 1 in a valid episode
  double fps = 0.0;     ///< nominal frame rate, frames per second; arm.csv's t is authoritative
  int width = 0;        ///< image size, pixels, of every frame, mask and depth image
  int height = 0;
  std::string arm_name;
  int joint_count = 0;  ///< N of arm.csv's q1..qN (0 when only the end-effector is known)
  FrameStorage storage = FrameStorage::kPng;
  /// Video file names relative to the episode directory (storage == kVideo only; the right one
  /// only for stereo episodes).
  std::string video_file;
  std::string video_file_right;
  bool has_masks = false;  ///< masks/000000.png...: 16-bit ground-truth object ids, 0 = background
  bool has_depth = false;  ///< depth/000000.png...: 16-bit depth along the optical axis, mm
  bool stereo = false;     ///< calib_right.yml and frames_right/ (or video_file_right) exist
  std::optional<int> target;  ///< id (objects.json) of the object the robot acts on
  EpisodeProvenance provenance;

  /// frame_count / fps, seconds.
  [[nodiscard]] double duration() const { return fps > 0 ? frame_count / fps : 0.0; }
};

/// episode.json as a result document (core::result_document plus the fields above).
core::Json to_json(const EpisodeInfo& info);

/// Parses episode.json (`file` names it in messages). Checks format, version, ranges and types;
/// throws Error naming the file and the first problem.
EpisodeInfo episode_info_from_json(const core::Json& j, const std::filesystem::path& file);

}  // namespace proprio::episode
