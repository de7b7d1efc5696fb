#pragma once
// Streaming, atomic writing of an episode: frames, masks and arm samples go in one at a time
// (simulated recordings are long), the directory appears at its final path only on finish().

#include <filesystem>
#include <fstream>
#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

#include "proprio/core/files.hpp"
#include "proprio/episode/arm_sample.hpp"
#include "proprio/episode/episode_info.hpp"
#include "proprio/episode/objects.hpp"
#include "proprio/geometry/camera.hpp"

namespace cv {
class VideoWriter;
}

namespace proprio::episode {

struct EpisodeWriterOptions {
  /// Replace an existing directory at the final path (on finish() only).
  bool overwrite = false;
  /// PNG compression level 0-9 for frames, masks and depth. Default 1: fast, about as small as
  /// the default level for rendered and camera images.
  int png_compression = 1;
  /// Codec of frames.avi when EpisodeInfo::storage is kVideo (OpenCV's built-in MJPEG writer
  /// needs no external library).
  std::string video_fourcc = "MJPG";

  /// Throws Error when a value is out of range.
  void validate() const;
};

/// Extra images of one frame; each must be given exactly when episode.json declares it.
struct FrameExtras {
  cv::Mat mask{};         ///< CV_16UC1 object ids, 0 = background (EpisodeInfo::has_masks)
  cv::Mat depth{};        ///< CV_16UC1 millimetres, 0 = unknown (EpisodeInfo::has_depth)
  cv::Mat right_image{};  ///< 8-bit BGR or grey, the right camera's frame (EpisodeInfo::stereo)
};

/// Writes an episode into a staging directory (core::StagedDirectory) and moves it into place in
/// finish(), after reading it back with the checks of read_episode. Destroyed before finish(), it
/// removes everything it wrote: an interrupted write never leaves a directory that reads as an
/// episode.
class EpisodeWriter {
 public:
  /// `info` describes the episode (its frame_count is ignored: it is the number of add_frame
  /// calls). `camera`'s image size must be 0 or info's; it is written with info's. `objects` are
  /// written to objects.json when not empty (required when info has masks or a target).
  /// `right_camera` is required exactly when info.stereo. Throws Error on invalid input.
  EpisodeWriter(std::filesystem::path dir, EpisodeInfo info, geometry::Camera camera,
                std::vector<ObjectInfo> objects = {},
                std::optional<geometry::Camera> right_camera = std::nullopt,
                EpisodeWriterOptions options = {});
  EpisodeWriter(const EpisodeWriter&) = delete;
  EpisodeWriter& operator=(const EpisodeWriter&) = delete;
  ~EpisodeWriter();

  /// Appends the next frame (8-bit BGR or grey, info's size) and the arm's state at it.
  /// Throws Error when an image has the wrong size or type, the sample holds NaN or inf, has the
  /// wrong number of joints, or its time does not increase.
  void add_frame(const cv::Mat& image, const ArmSample& arm, const FrameExtras& extras = {});

  /// Writes episode.json, calib.yml and objects.json, reads the result back (read_episode's
  /// checks) and moves it to its final path. Throws Error when no frame was added.
  void finish();

  [[nodiscard]] int frames_written() const { return count_; }
  [[nodiscard]] const std::filesystem::path& staging_path() const { return staged_.staging_path(); }

 private:
  void write_image(const std::string& subdir, const cv::Mat& image);

  core::StagedDirectory staged_;
  EpisodeInfo info_;
  geometry::Camera camera_;
  std::vector<ObjectInfo> objects_;
  std::optional<geometry::Camera> right_;
  EpisodeWriterOptions options_;
  std::ofstream arm_csv_;
  std::unique_ptr<cv::VideoWriter> video_;
  std::unique_ptr<cv::VideoWriter> video_right_;
  int count_ = 0;
  double last_t_ = 0.0;
  bool finished_ = false;
};

}  // namespace proprio::episode
