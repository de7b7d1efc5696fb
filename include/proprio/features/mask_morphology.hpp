#pragma once
// Masks grown or shrunk by a disc: the one morphology every layer above features applies to
// object masks (views' masks before their features are taken, touch cuts, evidence gaps).
// OpenCV's morphology with an elliptic structuring element; only the disc is ours.

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

namespace proprio::features {

/// The disc of radius `px` pixels as an OpenCV structuring element: a (2 px + 1)-square
/// ellipse. Requires px >= 0 (px 0: the single pixel, an identity for dilate and erode).
inline cv::Mat disc(int px) {
  return cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * px + 1, 2 * px + 1));
}

/// `mask` grown by a disc of radius `px` (px <= 0: a copy). A new matrix: the caller's mask is
/// never changed through it.
inline cv::Mat dilated(const cv::Mat& mask, int px) {
  if (px <= 0) return mask.clone();
  cv::Mat out;
  cv::dilate(mask, out, disc(px));
  return out;
}

/// `mask` shrunk by a disc of radius `px` (px <= 0: a copy); a new matrix, as dilated. Outside
/// the image counts as on the mask (OpenCV's default border), so a mask cut by the frame's edge
/// does not shrink from it; pass `outside_off` to make it shrink (outside counts as off).
inline cv::Mat eroded(const cv::Mat& mask, int px, bool outside_off = false) {
  if (px <= 0) return mask.clone();
  cv::Mat out;
  if (outside_off) {
    cv::erode(mask, out, disc(px), cv::Point(-1, -1), 1, cv::BORDER_CONSTANT, cv::Scalar(0));
  } else {
    cv::erode(mask, out, disc(px));
  }
  return out;
}

}  // namespace proprio::features
