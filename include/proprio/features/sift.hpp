#pragma once
// SIFT descriptors (Lowe 2004; thesis 6.1.1) at detected interest points, and dense SIFT on a
// regular grid (Bosch et al. 2007; thesis 7.3.3), both computed by OpenCV's cv::SIFT.

#include <opencv2/core.hpp>

#include "proprio/features/features.hpp"

namespace proprio::features {

/// Options of detect_sift (OpenCV's cv::SIFT parameters; the defaults are OpenCV's).
struct SiftOptions {
  int max_features = 0;              ///< keep the strongest N; 0 keeps all
  int octave_layers = 3;             ///< layers per octave of the difference of Gaussians
  double contrast_threshold = 0.04;  ///< drops weak extrema (of the image scaled to [0, 1])
  double edge_threshold = 10.0;      ///< drops edge-like extrema (ratio of principal curvatures)
  double sigma = 1.6;                ///< Gaussian blur of the first octave, px
  /// Throws Error on a negative count, a non-positive threshold or sigma.
  void validate() const;
};

/// SIFT keypoints and descriptors of `image` (8-bit grey or BGR; colour is converted to grey).
/// Throws Error on an empty image or an unsupported type. An image without features gives an
/// empty Features (descriptors 0 x 128).
Features detect_sift(const cv::Mat& image, const SiftOptions& options = {});

/// Options of dense_sift.
struct DenseSiftOptions {
  int step = 8;  ///< grid spacing, px
  /// Side of the square patch a descriptor describes, px: 4 x 4 cells of size / 4 px (16 px
  /// as in Lazebnik et al. 2006 and vlfeat's dsift). OpenCV's SIFT spans 6 keypoint sizes with
  /// its 4 x 4 cells, so the keypoints get cv::KeyPoint::size = size / 6.
  float size = 16.0F;
  int margin = -1;  ///< px kept clear of the border; -1 means size / 2 so that patches fit
  /// Throws Error on a non-positive step or size or a margin < -1.
  void validate() const;
};

/// The grid of dense_sift for an image of `image_size`: points at (margin + i * step,
/// margin + j * step) inside [margin, width - 1 - margin] x [margin, height - 1 - margin],
/// row-major (x fastest), each with KeyPoint::size = options.size / 6 and angle 0 (upright).
std::vector<cv::KeyPoint> dense_grid(cv::Size image_size, const DenseSiftOptions& options = {});

/// SIFT descriptors on the dense_grid of `image` (no detection, no orientation: upright, as
/// dense SIFT is used for scene categories). Same image rules as detect_sift; an image smaller
/// than the grid's margins gives an empty Features.
Features dense_sift(const cv::Mat& image, const DenseSiftOptions& options = {});

/// Upright SIFT descriptors (N x 128 CV_32F, OpenCV's layout: 4 x 4 cells, row-major from the
/// patch's top left, 8 orientation bins each) of the same patches with the image turned by
/// `quarter_turns` x 90 degrees counter-clockwise as displayed (cv::ROTATE_90_COUNTERCLOCKWISE
/// for 1; any integer, taken mod 4): an exact permutation of the 128 values, cell (r, c) going
/// to (3 - c, r) and bin b to b + 2 (mod 8) per quarter turn, so dense_sift of the turned image
/// at the turned grid point is this (measured exact to float rounding). For words that do not
/// change when an object lies on its side or turns on the table (session 31, issue 21's
/// Experiment 8.2: `experiment clutter --right-angle-words`). Throws Error unless 128 columns of
/// CV_32F.
cv::Mat rotate_sift_descriptors(const cv::Mat& descriptors, int quarter_turns);

/// The rows of `descriptors` followed by their rotate_sift_descriptors at 1, 2 and 3 quarter
/// turns (4N x 128): a document whose bag of words is the same for the image and for the image
/// turned by any multiple of 90 degrees (the dense grid permitting). Empty in, empty out.
cv::Mat with_right_angle_turns(const cv::Mat& descriptors);

}  // namespace proprio::features
