#pragma once
// Back-projection of a pixel onto a known plane (thesis 3.4.1, eqs 3.13-3.17; SPEC §1): one camera
// suffices when the point is known to lie on, e.g., the table top.

#include <Eigen/Core>

#include "proprio/geometry/camera.hpp"

namespace proprio::geometry {

/// The plane n . X = kappa (world frame; n need not be a unit vector).
struct Plane {
  Eigen::Vector3d n = Eigen::Vector3d::UnitZ();
  double kappa = 0.0;

  /// Throws Error when n is zero or a value is not finite.
  void validate() const;
};

struct BackProjectionOptions {
  /// The ray counts as parallel to the plane when |cos| of the angle between the ray and the
  /// plane's normal is below this.
  double parallel_tolerance = 1e-9;

  /// Throws Error when an option is out of range.
  void validate() const;
};

struct BackProjection {
  Eigen::Vector3d X = Eigen::Vector3d::Zero();  ///< the point on the plane, world frame
  double depth = 0.0;  ///< its depth along the optical axis (> 0), world units
  /// |cos| of the angle between the viewing ray and the plane normal (1 = head on); a grazing ray
  /// (small value) makes X sensitive to pixel noise.
  double incidence_cos = 0.0;
};

/// The world point on `plane` that projects to the ideal (undistorted) pixel x under P = K [R | t]:
/// the null vector, by SVD, of the rows x1 P3 - P1, x2 P3 - P2 (eqs 3.15-3.16) and
/// (n^T, -kappa) (the corrected eq 3.17). Throws Error when the pixel is not finite, the ray is
/// parallel to the plane, or the plane point lies behind the camera (or at its centre).
BackProjection back_project_to_plane(const Matrix34d& P, const Eigen::Vector2d& x,
                                     const Plane& plane, const BackProjectionOptions& options = {});

}  // namespace proprio::geometry
