#pragma once
// Region scores smoothed over the region adjacency graph (MlOptions::region_smoothing).

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <vector>

namespace proprio::segmentation {

struct RegionSmoothingOptions {
  /// beta: a region's own score is held by alpha_i = beta * n_i * L_i, n_i its evidence (M-L:
  /// post-touch intervals), L_i its boundary length, pixels. Small: a region with one interval
  /// of evidence yields to colour-alike neighbours; large: only regions without evidence move.
  double data_weight = 0.01;
  /// Colour kernel sigma, in the units of the colours given (BGR grey levels for M-L).
  double colour_sigma = 25.0;
  /// Depth steps, mm (with a depth image; 0 = off): a boundary pixel pair whose depths (both
  /// known) differ by more than this does not join its two regions (w_ij counts only the pairs
  /// without a step; L_i counts all). The object's outline against what lies behind it is a
  /// depth step: its scores must not bleed into the background's, or the background's into it.
  double depth_step = 0.0;
  int max_sweeps = 200;
  double tolerance = 1e-4;  ///< stop when no score changes by this much in a sweep
  /// Throws Error naming the bad field.
  void validate() const;
};

struct RegionSmoothingSummary {
  int regions = 0;           ///< regions in the label image
  int without_evidence = 0;  ///< of those, regions with n_i = 0 (interpolated)
  int sweeps = 0;            ///< Gauss-Seidel sweeps run
  bool converged = false;    ///< the last sweep changed no score by tolerance or more
};

/// Smooths the per-region `score` (indexed by the CV_32S ids of `labels`) over the regions'
/// 4-connected adjacency: minimises
///   E(s) = sum_i alpha_i (s_i - score_i)^2 + sum_{i~j} w_ij (s_i - s_j)^2,
///   alpha_i = data_weight * evidence_i * L_i,  w_ij = l_ij exp(-|c_i - c_j|^2 / (2 sigma^2)),
/// where l_ij is the length of the boundary between regions i and j, pixels, L_i = sum_j l_ij
/// and c the regions' mean colours: a Gaussian Markov random field on the region graph whose
/// pairwise terms follow colour (the object's pieces look alike, and unlike the table). Regions
/// without evidence (evidence_i = 0) take the harmonic interpolation of the others; a connected
/// group of regions none of which has evidence keeps its scores. Solved by Gauss-Seidel sweeps
/// in id order (deterministic); E is convex, so they converge to its unique minimum. Every new
/// score is a weighted mean of the old ones: the scores stay within their range.
/// `depth` (optional: CV_32F millimetres of labels' size, 0 = unknown) with
/// options.depth_step > 0: l_ij counts only boundary pixel pairs without a depth step.
RegionSmoothingSummary smooth_region_scores(const cv::Mat1i& labels,
                                            const std::vector<int>& evidence,
                                            const std::vector<Eigen::Vector3f>& colour,
                                            const RegionSmoothingOptions& options,
                                            std::vector<float>& score,
                                            const cv::Mat1f& depth = cv::Mat1f());

}  // namespace proprio::segmentation
