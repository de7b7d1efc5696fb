#include "video_cursor.hpp"

#include "proprio/core/error.hpp"

namespace proprio::episode::detail {

void VideoCursor::open() {
  cap_.release();
  if (!cap_.open(file_.string()) || !cap_.isOpened()) {
    throw Error::in_file(file_, "cannot open as a video (OpenCV cannot read it)");
  }
  next_ = 0;
}

cv::Mat VideoCursor::read(int i) {
  const std::lock_guard lock(mutex_);
  if (!cap_.isOpened() || i < next_) open();
  while (next_ < i) {
    if (!cap_.grab()) {
      throw Error::in_file(file_, "has only " + std::to_string(next_) +
                                      " frames, cannot read frame " + std::to_string(i));
    }
    ++next_;
  }
  cv::Mat frame;
  if (!cap_.read(frame) || frame.empty()) {
    cap_.release();
    throw Error::in_file(file_, "cannot decode frame " + std::to_string(i));
  }
  ++next_;
  return frame;
}

}  // namespace proprio::episode::detail
