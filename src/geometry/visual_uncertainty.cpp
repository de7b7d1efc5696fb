#include "proprio/geometry/visual_uncertainty.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <numbers>

#include "proprio/core/error.hpp"

namespace proprio::geometry {
namespace {

// True when X is in front of the camera P (positive depth for either sign of P).
bool in_front(const Matrix34d& P, const Eigen::Vector3d& X) {
  const double w = P.row(2) * X.homogeneous();
  return w * P.leftCols<3>().determinant() > 0.0;
}

}  // namespace

double log_posterior(const Matrix34d& P1, const Matrix34d& P2, const Eigen::Vector2d& x1,
                     const Eigen::Vector2d& x2, const Eigen::Vector3d& X,
                     const Eigen::Matrix2d& Sigma) {
  const Eigen::LLT<Eigen::Matrix2d> llt(Sigma);
  if (llt.info() != Eigen::Success) throw Error("pixel covariance is not positive definite");
  const double log_det = 2.0 * std::log(llt.matrixL().toDenseMatrix().diagonal().prod());
  double sum = 0.0;
  for (const auto& [P, x] : {std::pair{&P1, &x1}, std::pair{&P2, &x2}}) {
    const Eigen::Vector2d r = *x - project(*P, X);
    sum += -0.5 * r.dot(llt.solve(r)) - std::log(2.0 * std::numbers::pi) - 0.5 * log_det;
  }
  return sum;
}

Eigen::Matrix3d triangulation_covariance(const Matrix34d& P1, const Matrix34d& P2,
                                         const Eigen::Vector3d& X, const Eigen::Matrix2d& Sigma) {
  const Eigen::LLT<Eigen::Matrix2d> llt(Sigma);
  if (llt.info() != Eigen::Success) throw Error("pixel covariance is not positive definite");
  if (!in_front(P1, X) || !in_front(P2, X)) {
    throw Error("uncertainty: the point is behind a camera");
  }
  const Eigen::Matrix2d W = llt.solve(Eigen::Matrix2d::Identity());
  const Eigen::Matrix<double, 2, 3> J1 = projection_jacobian(P1, X);
  const Eigen::Matrix<double, 2, 3> J2 = projection_jacobian(P2, X);
  const Eigen::Matrix3d information = J1.transpose() * W * J1 + J2.transpose() * W * J2;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(information);
  const Eigen::Vector3d& ev = eig.eigenvalues();  // ascending
  if (!(ev(0) > 1e-12 * ev(2))) {
    throw Error("uncertainty: the point lies on the baseline; its depth is unobservable");
  }
  return eig.eigenvectors() * ev.cwiseInverse().asDiagonal() * eig.eigenvectors().transpose();
}

}  // namespace proprio::geometry
