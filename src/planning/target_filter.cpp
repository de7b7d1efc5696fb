#include "proprio/planning/target_filter.hpp"

#include <Eigen/Dense>
#include <cmath>

#include "proprio/core/error.hpp"
#include "text.hpp"

namespace proprio::planning {

using detail::cat;
using detail::num;

const char* to_string(TransitionModel model) {
  return model == TransitionModel::kLearned ? "learned" : "constant-velocity";
}

TransitionModel transition_model_from_string(const std::string& name) {
  if (name == "learned") return TransitionModel::kLearned;
  if (name == "constant-velocity") return TransitionModel::kConstantVelocity;
  throw Error(cat({"unknown transition model '", name, "' (learned or constant-velocity)"}));
}

void FilterOptions::validate() const {
  require(learn_states >= 3 && learn_states <= 10000,
          "FilterOptions: learn_states must be in [3, 10000]");
  require(std::isfinite(dt) && dt > 0 && dt <= 10, "FilterOptions: dt must be in (0, 10] s");
  require(std::isfinite(pinv_rcond) && pinv_rcond >= 0 && pinv_rcond < 1,
          "FilterOptions: pinv_rcond must be in [0, 1)");
  require(std::isfinite(pinv_noise_factor) && pinv_noise_factor >= 0,
          "FilterOptions: pinv_noise_factor must be >= 0");
  require(std::isfinite(q_floor) && q_floor >= 0, "FilterOptions: q_floor must be >= 0");
  require(std::isfinite(cv_accel_psd) && cv_accel_psd >= 0,
          "FilterOptions: cv_accel_psd must be >= 0");
}

std::vector<State> measured_states(const std::vector<Eigen::Vector3d>& positions, double dt) {
  std::vector<State> states;
  for (std::size_t i = 1; i < positions.size(); ++i) {
    State s;
    s << positions[i], (positions[i] - positions[i - 1]) / dt;
    states.push_back(s);
  }
  return states;
}

TransitionFit learn_transition(const std::vector<Eigen::Vector3d>& positions, double noise_std,
                               const FilterOptions& options) {
  options.validate();
  const int N = options.learn_states;
  if (static_cast<int>(positions.size()) < N + 1) {
    throw Error(cat({"learning the target's transition needs ", std::to_string(N + 1),
                     " measured positions (N = ", std::to_string(N), " states), got ",
                     std::to_string(positions.size())}));
  }
  require(std::isfinite(noise_std) && noise_std >= 0, "measurement noise std must be >= 0");
  const std::vector<Eigen::Vector3d> first(positions.begin(), positions.begin() + N + 1);
  for (const auto& p : first) require(p.allFinite(), "a measured target position is not finite");
  const std::vector<State> s = measured_states(first, options.dt);  // s_1..s_N
  const int n = N - 1;                                              // transitions
  Eigen::Matrix<double, 6, Eigen::Dynamic> H1(6, n), H2(6, n);
  for (int i = 0; i < n; ++i) {
    H1.col(i) = s[static_cast<std::size_t>(i)];
    H2.col(i) = s[static_cast<std::size_t>(i) + 1];
  }
  // Pseudo-inverse of H1 (eq 3.24) by SVD, with a cut-off at the noise level: a random 6 x n
  // matrix whose row i has entries of std s_i has a spectral norm of about
  // max_i s_i sqrt(n) + sqrt(sum_i s_i^2).
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(H1, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::VectorXd& sv = svd.singularValues();
  const double s_pos = noise_std;
  const double s_vel = std::sqrt(2.0) * noise_std / options.dt;
  const double noise_norm =
      s_vel * std::sqrt(static_cast<double>(n)) + std::sqrt(3 * s_pos * s_pos + 3 * s_vel * s_vel);
  TransitionFit fit;
  fit.tolerance = std::max(options.pinv_rcond * sv(0), options.pinv_noise_factor * noise_norm);
  Eigen::VectorXd inv = Eigen::VectorXd::Zero(sv.size());
  for (int i = 0; i < sv.size(); ++i) {
    fit.singular_values(i) = sv(i);
    if (sv(i) > fit.tolerance && sv(i) > 0) {
      inv(i) = 1 / sv(i);
      ++fit.rank;
    }
  }
  const Eigen::MatrixXd pinv = svd.matrixV() * inv.asDiagonal() * svd.matrixU().transpose();
  fit.A = H2 * pinv;  // eq 3.24
  const Eigen::MatrixXd residual = H2 - fit.A * H1;
  fit.Q = residual * residual.transpose() / static_cast<double>(n) +
          options.q_floor * StateMatrix::Identity();
  fit.residual_rms = std::sqrt(residual.squaredNorm() / static_cast<double>(residual.size()));
  return fit;
}

TransitionFit constant_velocity_transition(const FilterOptions& options) {
  options.validate();
  const double dt = options.dt;
  const double q = options.cv_accel_psd;
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  TransitionFit fit;
  fit.A.setIdentity();
  fit.A.topRightCorner<3, 3>() = dt * I;
  fit.Q.topLeftCorner<3, 3>() = q * dt * dt * dt / 3 * I;
  fit.Q.topRightCorner<3, 3>() = q * dt * dt / 2 * I;
  fit.Q.bottomLeftCorner<3, 3>() = q * dt * dt / 2 * I;
  fit.Q.bottomRightCorner<3, 3>() = q * dt * I;
  fit.Q += options.q_floor * StateMatrix::Identity();
  fit.rank = 6;
  return fit;
}

namespace {

void check_measurement(const PositionMeasurement& m) {
  require(std::isfinite(m.t) && m.position.allFinite() && m.covariance.allFinite(),
          "a target measurement is not finite");
  const Eigen::LLT<Eigen::Matrix3d> llt(m.covariance);
  require(llt.info() == Eigen::Success,
          "a target measurement's covariance is not positive definite");
}

}  // namespace

TargetFilter::TargetFilter(const std::vector<PositionMeasurement>& measurements,
                           const FilterOptions& options)
    : options_(options) {
  options_.validate();
  const int N = options_.learn_states;
  const std::size_t need = static_cast<std::size_t>(N) + 1;
  if (measurements.size() < need) {
    throw Error(cat({"the target filter needs at least ", std::to_string(need),
                     " measurements to learn its transition (N = ", std::to_string(N),
                     " states), got ", std::to_string(measurements.size())}));
  }
  for (const auto& m : measurements) check_measurement(m);
  const double dt = options_.dt;
  std::vector<Eigen::Vector3d> first;
  double variance = 0;
  for (std::size_t i = 0; i < need; ++i) {
    if (i > 0 && std::abs(measurements[i].t - measurements[i - 1].t - dt) > 1e-6 * dt + 1e-9) {
      throw Error(cat({"the first ", std::to_string(need),
                       " target measurements must be at consecutive frames ", num(dt),
                       " s apart (measurement ", std::to_string(i + 1), " is at ",
                       num(measurements[i].t), " s)"}));
    }
    first.push_back(measurements[i].position);
    variance += measurements[i].covariance.trace() / 3;
  }
  summary_.transition = options_.transition;
  summary_.fit =
      options_.transition == TransitionModel::kLearned
          ? learn_transition(first, std::sqrt(variance / static_cast<double>(need)), options_)
          : constant_velocity_transition(options_);
  // Initial state at the second measurement: its position and the finite-difference velocity,
  // with their joint covariance.
  const auto& m0 = measurements[0];
  const auto& m1 = measurements[1];
  estimate_.t = m1.t;
  estimate_.mean << m1.position, (m1.position - m0.position) / dt;
  estimate_.cov.setZero();
  estimate_.cov.topLeftCorner<3, 3>() = m1.covariance;
  estimate_.cov.topRightCorner<3, 3>() = m1.covariance / dt;
  estimate_.cov.bottomLeftCorner<3, 3>() = m1.covariance / dt;
  estimate_.cov.bottomRightCorner<3, 3>() = (m0.covariance + m1.covariance) / (dt * dt);
  summary_.updates = 2;
  for (std::size_t i = 2; i < measurements.size(); ++i) update(measurements[i]);
}

void TargetFilter::predict_one(TargetEstimate& e) const {
  const TransitionFit& f = summary_.fit;
  e.mean = f.A * e.mean;                        // eq 3.22
  e.cov = f.A * e.cov * f.A.transpose() + f.Q;  // eq 3.25
  e.cov = 0.5 * (e.cov + e.cov.transpose()).eval();
  e.t += options_.dt;
}

void TargetFilter::update(const PositionMeasurement& m) {
  check_measurement(m);
  const double dt = options_.dt;
  const double steps = (m.t - estimate_.t) / dt;
  const long k = std::lround(steps);
  if (k < 1 || std::abs(steps - static_cast<double>(k)) > 1e-6) {
    throw Error(cat({"target measurement at ", num(m.t), " s is not a frame after the filter's ",
                     num(estimate_.t), " s (frames are ", num(dt), " s apart)"}));
  }
  for (long i = 0; i < k; ++i) predict_one(estimate_);
  estimate_.t = m.t;
  summary_.missed_steps += static_cast<int>(k - 1);
  // The update is the product of the prediction's position Gaussian and the camera's (eq 3.29),
  // carried to the whole state by the Kalman gain; Joseph form for a symmetric PSD result.
  Eigen::Matrix<double, 3, 6> H = Eigen::Matrix<double, 3, 6>::Zero();
  H.leftCols<3>().setIdentity();
  const Eigen::Matrix3d S = H * estimate_.cov * H.transpose() + m.covariance;
  const Eigen::Matrix<double, 6, 3> K =
      Eigen::LLT<Eigen::Matrix3d>(S).solve(H * estimate_.cov).transpose();
  estimate_.mean += K * (m.position - H * estimate_.mean);
  const StateMatrix IKH = StateMatrix::Identity() - K * H;
  estimate_.cov = IKH * estimate_.cov * IKH.transpose() + K * m.covariance * K.transpose();
  estimate_.cov = 0.5 * (estimate_.cov + estimate_.cov.transpose()).eval();
  ++summary_.updates;
}

std::vector<TargetEstimate> TargetFilter::predict(int steps) const {
  std::vector<TargetEstimate> out;
  out.reserve(static_cast<std::size_t>(std::max(steps, 0)));
  TargetEstimate e = estimate_;
  for (int i = 0; i < steps; ++i) {
    predict_one(e);
    out.push_back(e);
  }
  return out;
}

}  // namespace proprio::planning
