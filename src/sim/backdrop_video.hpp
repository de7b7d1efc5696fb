#pragma once
// The moving background (thesis 5.1, RecordOptions::moving_background, TableOptions::background
// kMoving): the backdrop shows a video frame by frame, from its start again when it ends.

#include <cstdint>
#include <filesystem>
#include <opencv2/videoio.hpp>

#include "proprio/sim/renderer.hpp"
#include "proprio/sim/world.hpp"

namespace proprio::sim {

class BackdropVideo {
 public:
  /// Opens `file` when `on`. Throws Error when it is missing or cannot be opened.
  BackdropVideo(bool on, const std::filesystem::path& file);
  [[nodiscard]] bool on() const { return video_.isOpened(); }
  /// Shows the video's next frame on the backdrop (the recorder: one video frame per episode
  /// frame). Throws Error when no frame can be read.
  void show_next(World& world, Renderer& renderer);
  /// Shows the frame the video is at `t` seconds after its start (at its own frame rate, looped),
  /// reading forward from the frame shown last; `t` must not go back in time. Nothing is decoded
  /// or uploaded when that frame is already shown. Deterministic in `t`.
  void show_at(World& world, Renderer& renderer, double t);
  /// The video's frame rate (its header's; 25 when it gives none), Hz.
  [[nodiscard]] double fps() const { return fps_; }

 private:
  // Reads the next frame into `frame`, from the start again at the end; counts the frames.
  void read_next(cv::Mat& frame, bool decode);

  std::filesystem::path file_;
  cv::VideoCapture video_;
  double fps_ = 25;
  std::int64_t shown_ = -1;    // absolute index of the frame shown (show_at), -1 none
  std::int64_t position_ = 0;  // frames read since the start of the current pass
  std::int64_t length_ = 0;    // frames in the video, once one pass was read; 0 unknown
};

}  // namespace proprio::sim
