#pragma once
// Depth pixels as world points: the one back-projection of the depth finders (learn's
// depth_candidates and depth_points, planning's measure_footprint and depth_tops, loop's
// depth_footprints). What each finder then groups the points into differs (docs/architecture.md,
// the debt list).

#include <Eigen/Core>
#include <Eigen/LU>
#include <cmath>

#include "proprio/geometry/camera.hpp"

namespace proprio::geometry {

/// Whether a depth image's value (metres along the optical axis) is a measurement: finite and
/// positive (0, NaN and Inf mark no return).
inline bool depth_measured(double d) { return std::isfinite(d) && d > 0; }

/// The world point X = R^T (d K^-1 (u, v, 1) - t) of pixel (u, v) at depth d (Camera::depth(X)
/// is d; project(X) is (u, v)), with K^-1 and R^T computed once for a whole image. The same
/// operations in the same order as the finders had each written them: their points are unchanged
/// to the bit.
class DepthPixels {
 public:
  explicit DepthPixels(const Camera& camera)
      : k_inv_(camera.K.inverse()), r_t_(camera.R.transpose()), t_(camera.t) {}

  [[nodiscard]] Eigen::Vector3d world(int u, int v, double d) const {
    return r_t_ * (d * (k_inv_ * Eigen::Vector3d(u, v, 1.0)) - t_);
  }

 private:
  Eigen::Matrix3d k_inv_;
  Eigen::Matrix3d r_t_;
  Eigen::Vector3d t_;
};

}  // namespace proprio::geometry
