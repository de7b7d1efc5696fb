#include "motion_blur.hpp"

#include <algorithm>

namespace proprio::sim {

namespace {

// Renders averaged per frame: each costs a colour pass, so a few.
constexpr int kBlurRenders = 4;

}  // namespace

MotionBlur::MotionBlur(bool on, int steps_per_frame)
    : on_(on),
      steps_per_frame_(steps_per_frame),
      renders_(on ? kBlurRenders : 1),
      every_(std::max(1, steps_per_frame / renders_)) {}

bool MotionBlur::due_after(int s) const {
  return on_ && (s + 1) % every_ == 0 && s + 1 < steps_per_frame_;
}

void MotionBlur::add(const cv::Mat& rgb) {
  cv::Mat sub;
  rgb.convertTo(sub, CV_32FC3);
  if (sum_.empty()) {
    sum_ = sub;
  } else {
    sum_ += sub;
  }
}

void MotionBlur::finish(cv::Mat& rgb) {
  if (sum_.empty()) return;
  cv::Mat last;
  rgb.convertTo(last, CV_32FC3);
  sum_ += last;
  sum_.convertTo(rgb, CV_8UC3, 1.0 / renders_);
  sum_ = cv::Mat();
}

}  // namespace proprio::sim
