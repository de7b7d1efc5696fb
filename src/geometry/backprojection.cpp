#include "proprio/geometry/backprojection.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>

#include "proprio/core/error.hpp"

namespace proprio::geometry {

void Plane::validate() const {
  require(n.allFinite() && std::isfinite(kappa), "plane: values must be finite");
  require(n.norm() > 0.0, "plane: the normal n must not be zero");
}

void BackProjectionOptions::validate() const {
  require(parallel_tolerance > 0.0 && parallel_tolerance < 1.0,
          "back-projection option parallel_tolerance must lie in (0, 1)");
}

BackProjection back_project_to_plane(const Matrix34d& P, const Eigen::Vector2d& x,
                                     const Plane& plane, const BackProjectionOptions& options) {
  options.validate();
  plane.validate();
  if (!x.allFinite()) throw Error("back-projection: pixel is not finite");
  const Eigen::Matrix3d M = P.leftCols<3>();
  // Direction of the viewing ray in the world (towards the scene, since det(M) sign is folded in).
  Eigen::Vector3d ray = M.inverse() * x.homogeneous();
  if (M.determinant() < 0) ray = -ray;
  const Eigen::Vector3d n = plane.n.normalized();
  BackProjection out;
  out.incidence_cos = std::abs(n.dot(ray.normalized()));
  if (out.incidence_cos < options.parallel_tolerance) {
    throw Error("back-projection: the viewing ray is parallel to the plane");
  }

  // A camera centre on the plane sees the whole plane as one line: every pixel on it back-projects
  // to the centre itself.
  const Eigen::Vector3d centre = -M.inverse() * P.col(3);
  if (std::abs(n.dot(centre) - plane.kappa / plane.n.norm()) <= 1e-12 * (1.0 + centre.norm())) {
    throw Error("back-projection: the camera centre lies on the plane");
  }

  Eigen::Matrix<double, 3, 4> A;
  A.row(0) = x.x() * P.row(2) - P.row(0);         // eq 3.15
  A.row(1) = x.y() * P.row(2) - P.row(1);         // eq 3.16
  A.row(2) << plane.n.transpose(), -plane.kappa;  // eq 3.17 as corrected by SPEC §1
  // Scale the plane row like the others so the SVD weighs the three equations alike.
  A.row(2) *= A.topRows<2>().norm() / A.row(2).norm();
  const Eigen::JacobiSVD<Eigen::Matrix<double, 3, 4>> svd(A, Eigen::ComputeFullV);
  const Eigen::Vector4d Xh = svd.matrixV().col(3);
  if (std::abs(Xh(3)) < 1e-12) {
    throw Error("back-projection: the viewing ray meets the plane at infinity");
  }
  out.X = Xh.hnormalized();
  // Depth with the sign convention of a K [R | t] camera: w / |m3| with det(M) > 0.
  const double w = P.row(2) * out.X.homogeneous();
  out.depth = (M.determinant() > 0 ? w : -w) / M.row(2).norm();
  if (!(out.depth > 0.0)) {
    char buf[128];
    std::snprintf(buf, sizeof buf,
                  "back-projection: the plane point lies %s the camera (depth %.3g)",
                  out.depth < 0.0 ? "behind" : "at the centre of", out.depth);
    throw Error(buf);
  }
  return out;
}

}  // namespace proprio::geometry
