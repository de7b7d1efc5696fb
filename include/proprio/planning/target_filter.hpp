#pragma once
// Tracking and predicting the target (thesis 3.4.2, eqs 3.22-3.27; SPEC section 2): a Kalman
// filter over the state s = (position, velocity) in the world frame (m, m/s), at the camera's
// frame period dt. The transition matrix A is learned by least squares from the first N measured
// states, A = H(2..N) pinv(H(1..N-1)) (eqs 3.23-3.24), with the process noise Q from the fit's
// residuals; prediction into the future grows the covariance, M_t = A M_{t-1} A^T + Q (3.25).
//
// The camera measures positions only; a measured state pairs a measured position with the
// finite difference of the last two, v_i = (z_i - z_{i-1}) / dt. Each measurement update is the
// product of the camera's Gaussian p(x | C) (the linearised stereo triangulation) and the
// filter's prediction p(x | K, t) (eq 3.29).

#include <Eigen/Core>
#include <string>
#include <vector>

namespace proprio::planning {

using State = Eigen::Matrix<double, 6, 1>;
using StateMatrix = Eigen::Matrix<double, 6, 6>;

/// Where the transition matrix comes from.
enum class TransitionModel {
  kLearned,           ///< least squares on the first N measured states (eqs 3.22-3.24), the thesis
  kConstantVelocity,  ///< the known constant-velocity model, for comparison (not the thesis's)
};
const char* to_string(TransitionModel model);
/// "learned" or "constant-velocity"; throws Error otherwise.
TransitionModel transition_model_from_string(const std::string& name);

struct FilterOptions {
  TransitionModel transition = TransitionModel::kLearned;
  /// N: measured states used to learn A (it takes N + 1 positions). At least 3.
  int learn_states = 10;
  /// Frame period of the camera, the filter's time step, s.
  double dt = 0.04;
  /// The pseudo-inverse treats singular values of H(1..N-1) as zero below the larger of
  /// rcond times the largest one and noise_factor times the spectral norm that the measurement
  /// noise alone would give that matrix (a constant-velocity target spans a plane of the state
  /// space; noise in the other directions must not be inverted).
  double pinv_rcond = 1e-9;
  double pinv_noise_factor = 1.0;
  /// Added to the diagonal of Q (units of the state squared), so that a noise-free fit still has
  /// a positive definite Q.
  double q_floor = 1e-12;
  /// Constant-velocity model only: spectral density of the white acceleration noise, m^2/s^3.
  double cv_accel_psd = 1e-7;
  /// Throws Error when an option is out of range.
  void validate() const;
};

/// One camera measurement of the target's position.
struct PositionMeasurement {
  double t = 0;                                          ///< s
  Eigen::Vector3d position = Eigen::Vector3d::Zero();    ///< world, m
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();  ///< m^2, positive definite
};

/// The least-squares transition of eqs 3.23-3.24.
struct TransitionFit {
  StateMatrix A = StateMatrix::Identity();
  StateMatrix Q = StateMatrix::Zero();  ///< residual covariance (+ q_floor)
  int rank = 0;                         ///< singular values kept by the pseudo-inverse
  Eigen::Matrix<double, 6, 1> singular_values = Eigen::Matrix<double, 6, 1>::Zero();
  double tolerance = 0;     ///< the pseudo-inverse's cut-off
  double residual_rms = 0;  ///< RMS of H(2..N) - A H(1..N-1)
};

/// Measured states s_i = (z_i, (z_i - z_{i-1}) / dt), i = 1..n-1, from n positions.
std::vector<State> measured_states(const std::vector<Eigen::Vector3d>& positions, double dt);

/// Learns A from the measured states of positions[0..N] (eqs 3.22-3.24) and Q from the residuals
/// (their covariance over the N - 1 transitions, plus q_floor). `noise_std` is the per-axis
/// standard deviation of the measured positions (m), which sets the pseudo-inverse's cut-off.
/// Throws Error with fewer than N + 1 positions, or non-finite ones.
TransitionFit learn_transition(const std::vector<Eigen::Vector3d>& positions, double noise_std,
                               const FilterOptions& options);

/// The constant-velocity transition [[I, dt I], [0, I]] and its white-acceleration Q.
TransitionFit constant_velocity_transition(const FilterOptions& options);

struct FilterSummary {
  TransitionModel transition = TransitionModel::kLearned;
  TransitionFit fit;
  int updates = 0;       ///< measurement updates so far (the first two set the initial state)
  int missed_steps = 0;  ///< camera frames without a measurement (prediction only)
};

/// The filter's estimate at one time, or its prediction into the future.
struct TargetEstimate {
  double t = 0;  ///< s
  State mean = State::Zero();
  StateMatrix cov = StateMatrix::Identity();
  [[nodiscard]] Eigen::Vector3d position() const { return mean.head<3>(); }
  [[nodiscard]] Eigen::Matrix3d position_cov() const { return cov.topLeftCorner<3, 3>(); }
};

class TargetFilter {
 public:
  /// Learns (or sets) the transition from the first N + 1 measurements, which must be at
  /// consecutive frames (t_{i+1} = t_i + dt), then filters all of `measurements` in time order:
  /// the state starts at the second measurement (position, finite-difference velocity, and their
  /// covariance from the two measurements'), and every later one is a predict-update step. Later
  /// measurements may skip frames (missed detections). Throws Error for too few measurements,
  /// times that are not on the frame grid or not increasing, or non-finite values.
  TargetFilter(const std::vector<PositionMeasurement>& measurements, const FilterOptions& options);

  /// Predicts to the measurement's frame (eqs 3.22, 3.25) and updates with it (eq 3.29). Throws
  /// Error when its time is not a later frame.
  void update(const PositionMeasurement& measurement);

  [[nodiscard]] const TargetEstimate& estimate() const { return estimate_; }
  [[nodiscard]] const FilterOptions& options() const { return options_; }
  [[nodiscard]] const FilterSummary& summary() const { return summary_; }

  /// Predictions at the next `steps` frames after the current estimate (t + dt, ..., t + steps dt):
  /// mean A^k s (eq 3.22), covariance M_k = A M_{k-1} A^T + Q (eq 3.25). With the constant-velocity
  /// model, or A learned from exact states, the covariance grows without bound; A learned from
  /// noisy states usually contracts (eigenvalues below 1), and then it grows towards the fixed
  /// point of eq 3.25 instead.
  [[nodiscard]] std::vector<TargetEstimate> predict(int steps) const;

 private:
  void predict_one(TargetEstimate& e) const;

  FilterOptions options_;
  TargetEstimate estimate_;
  FilterSummary summary_;
};

}  // namespace proprio::planning
