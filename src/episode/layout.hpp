#pragma once
// Internal: the names of the files of an episode directory (docs/formats/episode.md) and the
// loader shared by read_episode and check_episode.

#include <filesystem>
#include <optional>
#include <vector>

#include "problem_sink.hpp"
#include "proprio/episode/arm_sample.hpp"
#include "proprio/episode/check.hpp"
#include "proprio/episode/episode_info.hpp"
#include "proprio/episode/objects.hpp"
#include "proprio/geometry/camera.hpp"

namespace proprio::episode::detail {

inline constexpr const char* kEpisodeJson = "episode.json";
inline constexpr const char* kCalib = "calib.yml";
inline constexpr const char* kCalibRight = "calib_right.yml";
inline constexpr const char* kArmCsv = "arm.csv";
inline constexpr const char* kObjectsJson = "objects.json";
inline constexpr const char* kFramesDir = "frames";
inline constexpr const char* kFramesRightDir = "frames_right";
inline constexpr const char* kMasksDir = "masks";
inline constexpr const char* kDepthDir = "depth";

/// What the loader could read; each part is none when it is missing or invalid (reported).
struct Loaded {
  std::optional<EpisodeInfo> info;
  std::optional<geometry::Camera> camera;
  std::optional<geometry::Camera> right_camera;
  std::optional<std::vector<ArmSample>> arm;
  std::vector<ObjectInfo> objects;  ///< empty when objects.json is absent or invalid
  bool objects_valid = false;
};

/// Reads and checks everything in `dir`, reporting each problem to `sink`.
Loaded load_episode(const std::filesystem::path& dir, ProblemSink& sink,
                    const CheckOptions& options);

/// Ids in a CV_16UC1 mask that are neither 0 nor in `objects`, ascending.
std::vector<int> unknown_mask_ids(const cv::Mat& mask, const std::vector<ObjectInfo>& objects);

/// "3, 7, 9" (at most 10, then "...").
std::string list_ids(const std::vector<int>& ids);

}  // namespace proprio::episode::detail
