#pragma once
// Scores for regions that no evidence reached, from their neighbours (MlOptions::fill_unknown).

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <vector>

namespace proprio::segmentation {

struct RegionFillSummary {
  int unknown = 0;         ///< regions of the label image without a known score
  int filled = 0;          ///< of those, regions that received one (a path to a known region)
  int sweeps = 0;          ///< Gauss-Seidel sweeps run
  bool converged = false;  ///< the last sweep changed no score by 1e-4 or more
};

/// Gives each region of `labels` (CV_32S ids indexing the other arguments) whose score is not
/// `known` the mean of its neighbours' scores (4-connected), each weighted by the length of the
/// common boundary, pixels, times exp(-|c_i - c_j|^2 / (2 colour_sigma^2)) of their mean colours
/// `colour` (any 3-channel space, same units as colour_sigma). Solved by Gauss-Seidel sweeps,
/// which converge to the harmonic function on the region adjacency graph that the known scores
/// bound: a weighted mean of the known scores, so it stays within their range. Regions with no
/// path to a known one keep their score. Deterministic (regions are swept in id order).
RegionFillSummary fill_unknown_scores(const cv::Mat1i& labels, const std::vector<char>& known,
                                      const std::vector<Eigen::Vector3f>& colour,
                                      double colour_sigma, std::vector<float>& score);

}  // namespace proprio::segmentation
