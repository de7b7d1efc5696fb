#pragma once
// The moving background (thesis 5.1, RecordOptions::moving_background): the backdrop shows a
// video frame by frame, from its start again when it ends.

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
  /// Shows the video's next frame on the backdrop. Throws Error when no frame can be read.
  void show_next(World& world, Renderer& renderer);

 private:
  std::filesystem::path file_;
  cv::VideoCapture video_;
};

}  // namespace proprio::sim
