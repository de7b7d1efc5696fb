#pragma once
// Dense optical flow between consecutive frames (step 2 of thesis 4.1).

#include <memory>
#include <opencv2/core.hpp>

#include "proprio/segmentation/ml_segmentation.hpp"

namespace proprio::segmentation {

/// Dense flow from one 8-bit grey image to another of the same size: flow(x) (CV_32FC2, pixels)
/// is where pixel x of `from` lies in `to`, x + flow(x). Keeps its state (DIS instance) between
/// calls; not thread-safe.
class DenseFlow {
 public:
  explicit DenseFlow(FlowMethod method);
  ~DenseFlow();
  DenseFlow(DenseFlow&&) noexcept;
  DenseFlow& operator=(DenseFlow&&) noexcept;
  [[nodiscard]] cv::Mat2f compute(const cv::Mat1b& from, const cv::Mat1b& to);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace proprio::segmentation
