#pragma once
// Closed-form products and overlaps of Gaussians, the two operations the interception planner is
// built on (thesis 3.4.3 and 3.6): the product p(x | C) p(x | K, t) of the camera's and the Kalman
// filter's beliefs (eq 3.29; it is the Kalman measurement update) and the integral over x of the
// arm's and the target's beliefs (eq 3.48).

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <cassert>
#include <cmath>
#include <numbers>

namespace proprio::planning {

/// N(mean, cov) in D dimensions; cov symmetric positive definite.
template <int D>
struct Gaussian {
  Eigen::Matrix<double, D, 1> mean = Eigen::Matrix<double, D, 1>::Zero();
  Eigen::Matrix<double, D, D> cov = Eigen::Matrix<double, D, D>::Identity();
};

/// log N(x | g.mean, g.cov), normalisation included.
template <int D>
double log_density(const Gaussian<D>& g, const Eigen::Matrix<double, D, 1>& x) {
  const Eigen::LLT<Eigen::Matrix<double, D, D>> llt(g.cov);
  assert(llt.info() == Eigen::Success);
  const Eigen::Matrix<double, D, 1> w = llt.matrixL().solve(x - g.mean);
  const double log_det = 2 * llt.matrixL().toDenseMatrix().diagonal().array().log().sum();
  return -0.5 * (w.squaredNorm() + log_det + D * std::log(2 * std::numbers::pi));
}

/// log of the integral over x of N(x | a) N(x | b): log N(a.mean | b.mean, a.cov + b.cov)
/// (eq 3.48 with the delta of eq 3.47 already integrated out).
template <int D>
double log_overlap(const Gaussian<D>& a, const Gaussian<D>& b) {
  return log_density(Gaussian<D>{b.mean, Eigen::Matrix<double, D, D>(a.cov + b.cov)}, a.mean);
}

/// N(x | a) N(x | b) = exp(log_scale) N(x | gaussian): the normalised product (information
/// form: cov = (A^-1 + B^-1)^-1, mean = cov (A^-1 a + B^-1 b)) and the log of its weight, which
/// is log_overlap(a, b).
template <int D>
struct GaussianProduct {
  Gaussian<D> gaussian;
  double log_scale = 0;
};

/// The product of eq 3.29, computed in the Kalman gain form, which stays accurate when one
/// covariance is much smaller than the other: K = A (A + B)^-1, mean = a + K (b - a),
/// cov = A - K A.
template <int D>
GaussianProduct<D> product(const Gaussian<D>& a, const Gaussian<D>& b) {
  using Matrix = Eigen::Matrix<double, D, D>;
  const Eigen::LLT<Matrix> llt(a.cov + b.cov);
  assert(llt.info() == Eigen::Success);
  const Matrix K = llt.solve(a.cov).transpose();  // A (A + B)^-1, both symmetric
  GaussianProduct<D> p;
  p.gaussian.mean = a.mean + K * (b.mean - a.mean);
  p.gaussian.cov = a.cov - K * a.cov;
  p.gaussian.cov = 0.5 * (p.gaussian.cov + p.gaussian.cov.transpose()).eval();
  p.log_scale = log_overlap(a, b);
  return p;
}

}  // namespace proprio::planning
