#pragma once
// Internal: lazy, thread-safe access to frame i of a video file. Frames are decoded in order:
// frame i after frame i-1 costs one decode; going back reopens the file. (Seeking with
// CAP_PROP_POS_FRAMES is not frame-exact for every codec.)

#include <filesystem>
#include <mutex>
#include <opencv2/core.hpp>
#include <opencv2/videoio.hpp>

namespace proprio::episode::detail {

class VideoCursor {
 public:
  explicit VideoCursor(std::filesystem::path file) : file_(std::move(file)) {}

  /// Frame i, 8-bit BGR. Throws Error naming the file when it cannot be read.
  cv::Mat read(int i);

 private:
  void open();

  std::mutex mutex_;
  std::filesystem::path file_;
  cv::VideoCapture cap_;
  int next_ = 0;  ///< index of the frame the next cap_.read() returns
};

}  // namespace proprio::episode::detail
