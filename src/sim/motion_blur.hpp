#pragma once
// Disturbance (thesis 5.1, RecordOptions::motion_blur): each frame averages renders at
// 4 instants of its interval, the last one the frame's own render.

#include <opencv2/core.hpp>

namespace proprio::sim {

class MotionBlur {
 public:
  /// Off: frames are single renders. `steps_per_frame` physics steps make a frame's interval.
  MotionBlur(bool on, int steps_per_frame);
  /// Whether a render is due after the physics step `s` (0-based) of a frame's interval.
  [[nodiscard]] bool due_after(int s) const;
  /// Adds a render of the interval (8-bit 3-channel).
  void add(const cv::Mat& rgb);
  /// Makes `rgb`, the frame's own render, the average of it and the renders added since the last
  /// call (unchanged when none was), and starts the next frame's sum.
  void finish(cv::Mat& rgb);

 private:
  bool on_;
  int steps_per_frame_;
  int renders_;
  int every_;  // physics steps between renders
  cv::Mat sum_;
};

}  // namespace proprio::sim
