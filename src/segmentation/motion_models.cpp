#include "proprio/segmentation/motion_models.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <opencv2/calib3d.hpp>

namespace proprio::segmentation {

RobustMeanResult robust_mean(const std::vector<Eigen::Vector2f>& samples, double bandwidth,
                             double tolerance, int max_iterations) {
  assert(!samples.empty() && bandwidth > 0);
  RobustMeanResult r;
  // Start at the coordinate-wise median: the plain mean (Algorithm 1's start) can be dragged by
  // far outliers to where no inlier lies within the bandwidth, and the iteration stops there.
  std::vector<float> xs(samples.size()), ys(samples.size());
  for (size_t i = 0; i < samples.size(); ++i) {
    xs[i] = samples[i].x();
    ys[i] = samples[i].y();
  }
  const auto mid = static_cast<std::ptrdiff_t>(samples.size() / 2);
  std::nth_element(xs.begin(), xs.begin() + mid, xs.end());
  std::nth_element(ys.begin(), ys.begin() + mid, ys.end());
  r.mean = Eigen::Vector2d(xs[mid], ys[mid]);
  const double c2 = bandwidth * bandwidth;
  for (r.iterations = 0; r.iterations < max_iterations;) {
    Eigen::Vector2d acc = Eigen::Vector2d::Zero();
    int n = 0;
    for (const auto& s : samples) {
      const Eigen::Vector2d d = s.cast<double>() - r.mean;
      if (d.squaredNorm() < c2) {
        acc += d;
        ++n;
      }
    }
    ++r.iterations;
    r.inliers = n;
    if (n == 0) break;
    const Eigen::Vector2d shift = acc / n;
    r.mean += shift;
    if (shift.norm() <= tolerance) break;
  }
  return r;
}

Eigen::Vector3d robust_mean_3d(const std::vector<Eigen::Vector3f>& samples, double bandwidth,
                               double tolerance, int max_iterations) {
  assert(!samples.empty() && bandwidth > 0);
  Eigen::Vector3d mean;
  std::vector<float> v(samples.size());
  const auto mid = static_cast<std::ptrdiff_t>(samples.size() / 2);
  for (int c = 0; c < 3; ++c) {
    for (size_t i = 0; i < samples.size(); ++i) v[i] = samples[i][c];
    std::nth_element(v.begin(), v.begin() + mid, v.end());
    mean[c] = v[static_cast<size_t>(mid)];
  }
  const double c2 = bandwidth * bandwidth;
  for (int it = 0; it < max_iterations; ++it) {
    Eigen::Vector3d acc = Eigen::Vector3d::Zero();
    int n = 0;
    for (const auto& s : samples) {
      const Eigen::Vector3d d = s.cast<double>() - mean;
      if (d.squaredNorm() < c2) {
        acc += d;
        ++n;
      }
    }
    if (n == 0) break;
    const Eigen::Vector3d shift = acc / n;
    mean += shift;
    if (shift.norm() <= tolerance) break;
  }
  return mean;
}

std::optional<Eigen::Matrix3d> fit_homography(const std::vector<Eigen::Vector2f>& from,
                                              const std::vector<Eigen::Vector2f>& to,
                                              double threshold, int min_points) {
  assert(from.size() == to.size());
  const int n = static_cast<int>(from.size());
  if (n < std::max(4, min_points)) return std::nullopt;
  std::vector<cv::Point2f> a(n), b(n);
  for (int i = 0; i < n; ++i) {
    a[i] = {from[i].x(), from[i].y()};
    b[i] = {to[i].x(), to[i].y()};
  }
  cv::Mat inliers;
  // Fixed iteration budget and confidence: cv::findHomography's RANSAC draws from cv::RNG
  // seeded per call, so the result is deterministic.
  const cv::Mat h = cv::findHomography(a, b, cv::RANSAC, threshold, inliers, 500, 0.995);
  if (h.empty() || cv::countNonZero(inliers) * 2 < n) return std::nullopt;
  Eigen::Matrix3d m;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) m(r, c) = h.at<double>(r, c);
  if (!m.allFinite()) return std::nullopt;
  return m;
}

Eigen::Vector2d apply_homography(const Eigen::Matrix3d& h, const Eigen::Vector2d& x) {
  const Eigen::Vector3d y = h * Eigen::Vector3d(x.x(), x.y(), 1.0);
  if (std::abs(y.z()) < 1e-12) return x;
  return {y.x() / y.z(), y.y() / y.z()};
}

double motion_likelihood(const Eigen::Vector2d& error, double lambda) {
  assert(lambda > 0);
  return std::exp(-error.squaredNorm() / (2.0 * lambda));
}

double motion_likelihood_3d(const Eigen::Vector3d& error, double lambda) {
  assert(lambda > 0);
  return std::exp(-error.squaredNorm() / (2.0 * lambda));
}

}  // namespace proprio::segmentation
