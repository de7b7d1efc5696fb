#pragma once
// Private to the loop module: a mask grown or shrunk by a disc, as every view's mask is before
// its features are taken (OpenCV's morphology with an elliptic kernel of radius px).

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

namespace proprio::loop::detail {

/// `mask` grown by a disc of radius `px` (px <= 0: a copy). A new matrix: the caller's mask is
/// never changed through it.
inline cv::Mat dilated(const cv::Mat& mask, int px) {
  if (px <= 0) return mask.clone();
  cv::Mat out;
  cv::dilate(mask, out,
             cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * px + 1, 2 * px + 1)));
  return out;
}

/// `mask` shrunk by a disc of radius `px` (px <= 0: a copy); a new matrix, as dilated.
inline cv::Mat eroded(const cv::Mat& mask, int px) {
  if (px <= 0) return mask.clone();
  cv::Mat out;
  cv::erode(mask, out,
            cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * px + 1, 2 * px + 1)));
  return out;
}

}  // namespace proprio::loop::detail
