#pragma once
// A recorded interaction, read from its directory (docs/formats/episode.md).
//
// Everything small (episode.json, calibration, arm.csv, objects.json) is read and validated once;
// images are decoded on demand, one frame at a time, so long episodes never sit in memory.

#include <Eigen/Core>
#include <filesystem>
#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

#include "proprio/episode/arm_sample.hpp"
#include "proprio/episode/episode_info.hpp"
#include "proprio/episode/objects.hpp"
#include "proprio/geometry/camera.hpp"

namespace proprio::episode {

namespace detail {
class VideoCursor;
}

/// A read episode. Constant after reading; copies share the (internally locked) video readers, so
/// frame access is safe from several threads.
class Episode {
 public:
  [[nodiscard]] const std::filesystem::path& dir() const { return dir_; }
  [[nodiscard]] const EpisodeInfo& info() const { return info_; }
  [[nodiscard]] int frame_count() const { return info_.frame_count; }
  /// The camera of calib.yml (the one source of the camera; its image size is the episode's).
  [[nodiscard]] const geometry::Camera& camera() const { return camera_; }
  /// The right camera of a stereo episode (calib_right.yml), none otherwise.
  [[nodiscard]] const std::optional<geometry::Camera>& right_camera() const { return right_; }
  /// One sample per frame (arm.csv).
  [[nodiscard]] const std::vector<ArmSample>& arm() const { return arm_; }
  /// objects.json; empty when the episode has none.
  [[nodiscard]] const std::vector<ObjectInfo>& objects() const { return objects_; }
  /// The object with this id, or nullptr.
  [[nodiscard]] const ObjectInfo* object(int id) const;

  /// Frame i (0 <= i < frame_count), 8-bit BGR (CV_8UC3). Throws Error naming the file when it
  /// cannot be decoded or has the wrong size.
  [[nodiscard]] cv::Mat frame(int i) const;
  /// Frame i of the right camera (stereo episodes only).
  [[nodiscard]] cv::Mat frame_right(int i) const;
  /// Ground-truth object ids of frame i, CV_16UC1, 0 = background (has_masks only). Throws Error
  /// when the image is not 16-bit single-channel, is of the wrong size, or holds an id that
  /// objects.json lacks.
  [[nodiscard]] cv::Mat mask(int i) const;
  /// Depth of frame i along the camera's optical axis, CV_16UC1 in millimetres, 0 = unknown
  /// (has_depth only).
  [[nodiscard]] cv::Mat depth(int i) const;

  /// Times of the frames, seconds (arm.csv's t), strictly increasing.
  [[nodiscard]] std::vector<double> frame_times() const;
  /// The first frame whose `touching` is set: the arm touched an object in a physics step since
  /// the previous frame (the first-touch frame of thesis 4.3, eq 4.18). None if it never does.
  [[nodiscard]] std::optional<int> first_touch_frame() const;
  /// The end-effector's image position in frame i, pixels (step 3 of thesis 4.1): ee_u, ee_v of
  /// arm.csv, or, where they are empty, the projection of ee through the calibration (with its
  /// lens distortion, if any, so that it lands where the frame shows it). None when the
  /// end-effector is behind the camera.
  [[nodiscard]] std::optional<Eigen::Vector2d> ee_image(int i) const;
  /// ee_image for every frame.
  [[nodiscard]] std::vector<std::optional<Eigen::Vector2d>> ee_image_track() const;

 private:
  friend Episode read_episode(const std::filesystem::path& dir);
  Episode() = default;

  std::filesystem::path dir_;
  EpisodeInfo info_;
  geometry::Camera camera_;
  std::optional<geometry::Camera> right_;
  std::vector<ArmSample> arm_;
  std::vector<ObjectInfo> objects_;
  std::shared_ptr<detail::VideoCursor> video_;
  std::shared_ptr<detail::VideoCursor> video_right_;
};

/// Reads and validates episode directory `dir` with the cheap checks of check_episode (every
/// file present and consistent, every image's size from its PNG header, PNG trailers present, no
/// image decoded). Throws Error naming the file and the first problem found.
Episode read_episode(const std::filesystem::path& dir);

/// Path of frame i's image in a PNG directory ("frames", "frames_right", "masks", "depth").
std::filesystem::path image_path(const std::filesystem::path& episode_dir,
                                 const std::string& subdir, int i);

}  // namespace proprio::episode
