#pragma once
// Hartley normalisation (Hartley & Zisserman 2004, 4.4.4): similarity transforms that move a point
// set's centroid to the origin and scale its mean distance from it to sqrt(dim). Private to the
// geometry module.

#include <Eigen/Core>
#include <vector>

namespace proprio::geometry::detail {

/// T (3x3) with T (x, 1) normalised; the points must not all coincide.
Eigen::Matrix3d hartley_normalization(const std::vector<Eigen::Vector2d>& points);
/// U (4x4) with U (X, 1) normalised; the points must not all coincide.
Eigen::Matrix4d hartley_normalization(const std::vector<Eigen::Vector3d>& points);

/// Standard deviations along the principal axes of a point set, largest first.
Eigen::Vector3d principal_spread(const std::vector<Eigen::Vector3d>& points);

}  // namespace proprio::geometry::detail
