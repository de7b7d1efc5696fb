#pragma once
// What the learners of the loop module (self-supervision, look-plan-move) do alike with the
// putative objects of a look: find one again by where it was, and paint one as a mask.
#include <Eigen/Core>
#include <cstddef>
#include <opencv2/core.hpp>

#include "proprio/planning/push_planner.hpp"

namespace proprio::loop::detail {

/// The blob of `view` whose centre is nearest `centre` and nearer than `radius` (the units of
/// the blobs' centres: table metres); -1 when none is.
inline int nearest_blob(const planning::PlanningView& view, const Eigen::Vector2d& centre,
                        double radius) {
  int best = -1;
  double best_d = radius;
  for (std::size_t k = 0; k < view.objects.size(); ++k) {
    const double d = (view.objects[k].centre - centre).norm();
    if (d < best_d) {
      best_d = d;
      best = static_cast<int>(k);
    }
  }
  return best;
}

/// The blob's pixels as an 8-bit mask of the image's size (255 inside).
inline cv::Mat blob_mask(const planning::PutativeObject& o, cv::Size size) {
  cv::Mat m = cv::Mat::zeros(size, CV_8U);
  o.mask.copyTo(m(o.box), o.mask);
  return m;
}

}  // namespace proprio::loop::detail
