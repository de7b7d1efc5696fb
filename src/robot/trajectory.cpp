#include "proprio/robot/trajectory.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "proprio/core/error.hpp"

namespace proprio::robot {

Shaped shaping_function(double tau, double alpha) {
  const double at = alpha * tau;
  const double e = std::exp(-at * at * at);
  return {1.0 - e, 3.0 * alpha * at * at * e,
          alpha * alpha * (6.0 * at - 9.0 * at * at * at * at) * e};
}

TimeShaping::TimeShaping(double duration, double alpha) : duration_(duration), alpha_(alpha) {
  require(std::isfinite(duration) && duration > 0, "trajectory duration must be > 0 s");
  require(std::isfinite(alpha) && alpha > 0, "trajectory shaping alpha must be > 0");
  norm_ = 1.0 / shaping_function(kShapingEnd, alpha_).value;
}

Shaped TimeShaping::operator()(double t) const {
  if (!(t > 0)) return {0, 0, 0};
  if (t >= duration_) return {1, 0, 0};
  const double k = kShapingEnd / duration_;  // dtau/dt
  const Shaped f = shaping_function(k * t, alpha_);
  return {f.value * norm_, f.rate * k * norm_, f.accel * k * k * norm_};
}

BezierTrajectory::BezierTrajectory(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                                   const Eigen::Vector3d& p2, double duration, double alpha)
    : p0_(p0), p1_(p1), p2_(p2), shaping_(duration, alpha) {
  require(p0.allFinite() && p1.allFinite() && p2.allFinite(),
          "trajectory control points must be finite");
}

Eigen::Vector3d BezierTrajectory::curve(double s) const {
  return (1 - s) * (1 - s) * p0_ + 2 * (1 - s) * s * p1_ + s * s * p2_;
}

Eigen::Vector3d BezierTrajectory::curve_derivative(double s) const {
  return 2 * (1 - s) * (p1_ - p0_) + 2 * s * (p2_ - p1_);
}

Eigen::Vector3d BezierTrajectory::curve_second_derivative() const {
  return 2 * (p2_ - 2 * p1_ + p0_);
}

double BezierTrajectory::length() const {
  // |b'(s)| is the square root of a quadratic in s, smooth unless the curve nearly folds back on
  // itself: composite 8-point Gauss-Legendre over 16 panels (exact for a straight move).
  static constexpr std::array<double, 4> kX = {0.1834346424956498, 0.5255324099163290,
                                               0.7966664774136267, 0.9602898564975363};
  static constexpr std::array<double, 4> kW = {0.3626837833783620, 0.3137066458778873,
                                               0.2223810344533745, 0.1012285362903763};
  constexpr int kPanels = 16;
  constexpr double kH = 1.0 / kPanels;
  double sum = 0;
  for (int p = 0; p < kPanels; ++p) {
    const double mid = (p + 0.5) * kH;
    for (std::size_t i = 0; i < kX.size(); ++i) {
      sum += kW[i] * (curve_derivative(mid + 0.5 * kH * kX[i]).norm() +
                      curve_derivative(mid - 0.5 * kH * kX[i]).norm());
    }
  }
  return 0.5 * kH * sum;
}

CartesianSample BezierTrajectory::sample(double t) const {
  const double tc = std::clamp(t, 0.0, duration());
  const Shaped s = shaping_(tc);
  const Eigen::Vector3d db = curve_derivative(s.value);
  CartesianSample out;
  out.t = tc;
  out.position = curve(s.value);                                                  // eq 3.34
  out.velocity = db * s.rate;                                                     // eq 3.35
  out.acceleration = db * s.accel + curve_second_derivative() * s.rate * s.rate;  // eq 3.36
  return out;
}

BezierTrajectory straight_move(const Eigen::Vector3d& from, const Eigen::Vector3d& to,
                               double speed) {
  require(from.allFinite() && to.allFinite(), "straight move: end points must be finite");
  require(std::isfinite(speed) && speed > 0, "straight move: speed must be > 0 m/s");
  const double length = (to - from).norm();
  require(length > 1e-9, "straight move: start and end coincide");
  return BezierTrajectory(from, 0.5 * (from + to), to, length / speed);
}

BezierTrajectory psi_trajectory(const Eigen::Vector3d& start, const TrajectoryParams& psi,
                                double duration) {
  require(std::isfinite(psi.theta) && std::isfinite(psi.gamma),
          "trajectory parameters must be finite");
  require(std::isfinite(psi.length) && psi.length > 0, "trajectory length l must be > 0 m");
  const Eigen::Vector3d d =
      psi.length * Eigen::Vector3d(std::sin(psi.theta), std::cos(psi.theta), 0);
  const Eigen::Vector3d perp(-d.y(), d.x(), 0);
  const Eigen::Vector3d p2 = start + d;                           // eq 3.39, relative to the start
  const Eigen::Vector3d p1 = start + 0.5 * d + psi.gamma * perp;  // eq 3.40
  return BezierTrajectory(start, p1, p2, duration);
}

std::vector<CartesianSample> sample_trajectory(const CartesianTrajectory& trajectory,
                                               double rate_hz) {
  require(std::isfinite(rate_hz) && rate_hz > 0, "sampling rate must be > 0 Hz");
  const double T = trajectory.duration();
  const double intervals = std::ceil(T * rate_hz - 1e-9);
  require(intervals < 1e8, "too many trajectory samples (duration * rate >= 1e8)");
  const int n = std::max(1, static_cast<int>(intervals));
  std::vector<CartesianSample> out;
  out.reserve(static_cast<std::size_t>(n) + 1);
  for (int i = 0; i <= n; ++i) out.push_back(trajectory.sample(i == n ? T : T * i / n));
  return out;
}

}  // namespace proprio::robot
