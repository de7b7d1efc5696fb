#pragma once
// Motion models of one region between two frames (thesis 4.4.1, 4.4.3) and the error density.

#include <Eigen/Core>
#include <optional>
#include <vector>

namespace proprio::segmentation {

struct RobustMeanResult {
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  int iterations = 0;
  int inliers = 0;  ///< samples within the bandwidth of the final mean
};

/// Robust mean of 2-D samples (Algorithm 1, eq 4.16-4.17): flat-kernel mean shift started at the
/// coordinate-wise median (the thesis starts at the plain mean, which far outliers can drag away
/// from every inlier); each step moves to the mean of the samples within `bandwidth` of the current
/// estimate (divided by their count, not by all K), until it moves less than `tolerance` or
/// after `max_iterations`. When no sample lies within the bandwidth it stops where it is.
/// Requires a non-empty sample set.
RobustMeanResult robust_mean(const std::vector<Eigen::Vector2f>& samples, double bandwidth,
                             double tolerance, int max_iterations);

/// The same in 3-D (the depth variant: a region's 3-D translation, millimetres): started at the
/// coordinate-wise median, flat kernel of radius `bandwidth`. Requires a non-empty sample set.
Eigen::Vector3d robust_mean_3d(const std::vector<Eigen::Vector3f>& samples, double bandwidth,
                               double tolerance, int max_iterations);

/// Homography H with to ~ H from (eq 4.9), by RANSAC (Algorithm 2, cv::findHomography) with a
/// reprojection threshold in pixels. None when there are fewer than `min_points` pairs, RANSAC
/// fails, or fewer than half the pairs are inliers.
std::optional<Eigen::Matrix3d> fit_homography(const std::vector<Eigen::Vector2f>& from,
                                              const std::vector<Eigen::Vector2f>& to,
                                              double threshold, int min_points);

/// H applied to an image point (homogeneous division); the point itself when w is ~0.
Eigen::Vector2d apply_homography(const Eigen::Matrix3d& h, const Eigen::Vector2d& x);

/// Unnormalised Gaussian error density exp(-e^T e / (2 lambda)) in (0, 1] (eq 4.13-4.14 with
/// Sigma = lambda I, SPEC §3): 1 for a region moving exactly as the arm.
double motion_likelihood(const Eigen::Vector2d& error, double lambda);
/// The same for a 3-D error (the depth variant; lambda in the error's units squared).
double motion_likelihood_3d(const Eigen::Vector3d& error, double lambda);

}  // namespace proprio::segmentation
