#include "proprio/geometry/dlt.hpp"

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <cmath>
#include <cstdio>

#include "normalization.hpp"
#include "proprio/core/error.hpp"

namespace proprio::geometry {
namespace {

std::string g(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

}  // namespace

void DltOptions::validate() const {
  require(min_points >= 6,
          "DLT option min_points must be at least 6, got " + std::to_string(min_points));
  require(degeneracy_tolerance > 0.0 && degeneracy_tolerance < 1.0,
          "DLT option degeneracy_tolerance must lie in (0, 1)");
  require(rank_tolerance > 0.0 && rank_tolerance < 1.0,
          "DLT option rank_tolerance must lie in (0, 1)");
}

std::string DltSummary::brief() const {
  std::string s = "DLT on " + std::to_string(num_points) + " points";
  s += normalized ? " (normalised)" : " (not normalised)";
  s += ": sigma11/sigma1 = " + g(sigma11_ratio) + ", sigma12/sigma1 = " + g(sigma12_ratio);
  s += ", max residual " + g(max_residual_px) + " px";
  if (points_behind > 0) s += ", " + std::to_string(points_behind) + " points behind the camera";
  return s;
}

DltResult calibrate_dlt(const std::vector<Eigen::Vector3d>& world,
                        const std::vector<Eigen::Vector2d>& pixels, const DltOptions& options) {
  options.validate();
  if (world.size() != pixels.size()) {
    throw Error("DLT: " + std::to_string(world.size()) + " world points but " +
                std::to_string(pixels.size()) + " pixels");
  }
  const int n = static_cast<int>(world.size());
  if (n < options.min_points) {
    throw Error("DLT needs at least " + std::to_string(options.min_points) + " point pairs, got " +
                std::to_string(n));
  }
  for (int i = 0; i < n; ++i) {
    if (!world[i].allFinite() || !pixels[i].allFinite()) {
      throw Error("DLT: point " + std::to_string(i + 1) + " is not finite");
    }
  }

  // Degenerate world point sets: P is not determined by points on a plane or a line.
  const Eigen::Vector3d spread = detail::principal_spread(world);
  if (spread(0) == 0.0) throw Error("DLT: all world points coincide");
  if (spread(1) < options.degeneracy_tolerance * spread(0)) {
    throw Error("DLT: the world points are collinear; P needs points spanning 3D");
  }
  if (spread(2) < options.degeneracy_tolerance * spread(0)) {
    throw Error("DLT: the world points are coplanar (spread " + g(spread(2)) +
                " across the plane vs " + g(spread(0)) + " along it); P needs non-coplanar points");
  }
  // The image points can still all coincide (a broken tracker); normalisation needs a spread.
  bool distinct_pixels = false;
  for (int i = 1; i < n && !distinct_pixels; ++i) distinct_pixels = pixels[i] != pixels[0];
  if (!distinct_pixels) throw Error("DLT: all pixels coincide");

  Eigen::Matrix3d T = Eigen::Matrix3d::Identity();
  Eigen::Matrix4d U = Eigen::Matrix4d::Identity();
  if (options.normalize) {
    T = detail::hartley_normalization(pixels);
    U = detail::hartley_normalization(world);
  }

  // Corrected eq 3.10: rows [X^T, 0^T, -u X^T] and [0^T, X^T, -v X^T] on (P1; P2; P3).
  Eigen::MatrixXd A(2 * n, 12);
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector4d X = U * world[i].homogeneous();
    const Eigen::Vector3d x = T * pixels[i].homogeneous();
    const double u = x(0) / x(2);
    const double v = x(1) / x(2);
    A.row(2 * i) << X.transpose(), Eigen::RowVector4d::Zero(), -u * X.transpose();
    A.row(2 * i + 1) << Eigen::RowVector4d::Zero(), X.transpose(), -v * X.transpose();
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(A, Eigen::ComputeFullV);
  const Eigen::VectorXd& sv = svd.singularValues();
  DltResult result;
  result.summary.num_points = n;
  result.summary.normalized = options.normalize;
  result.summary.sigma11_ratio = sv(10) / sv(0);
  result.summary.sigma12_ratio = sv(11) / sv(0);
  if (!(result.summary.sigma11_ratio >= options.rank_tolerance)) {
    throw Error(
        "DLT: the point pairs do not determine P (the DLT matrix has rank < 11, "
        "sigma11/sigma1 = " +
        g(result.summary.sigma11_ratio) + ")");
  }

  const Eigen::VectorXd p = svd.matrixV().col(11);
  Matrix34d Pn;
  Pn << p.segment<4>(0).transpose(), p.segment<4>(4).transpose(), p.segment<4>(8).transpose();
  Matrix34d P = T.inverse() * Pn * U;  // undo the normalisation: x = T^-1 Pn U X
  P /= P.norm();
  if (P.leftCols<3>().determinant() < 0) P = -P;
  result.P = P;
  try {
    result.camera = decompose_projection(P);
  } catch (const Error& e) {
    throw Error(std::string("DLT: ") + e.what());
  }

  double sum_sq = 0.0;
  result.residuals_px.resize(n);
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d y = P * world[i].homogeneous();
    if (y.z() <= 0.0) ++result.summary.points_behind;
    const double r = (y.hnormalized() - pixels[i]).norm();
    result.residuals_px[i] = r;
    sum_sq += r * r;
    result.summary.max_residual_px = std::max(result.summary.max_residual_px, r);
  }
  result.rms_px = std::sqrt(sum_sq / n);
  result.summary.message = core::first_line(result.summary.brief());
  return result;
}

}  // namespace proprio::geometry
