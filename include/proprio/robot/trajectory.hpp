#pragma once
// Time-shaped Cartesian trajectories for the end-effector (thesis 3.5.1, SPEC section 2).
//
// A move is a quadratic Bezier curve b(s) (eq 3.30) traversed at the shaped time s = f(t)
// (eq 3.34): Phi(t) = b(s(t)). The shaping f(tau) = 1 - exp(-(alpha tau)^3), alpha = 1.66
// (eq 3.31), is evaluated on tau in [0, 1.5] and rescaled to the move's duration T:
// s(t) = f(1.5 t / T) / f(1.5), so that s(0) = 0 and s(T) = 1 exactly, with velocity and
// acceleration zero at both ends (on [0, 1] as the thesis has it the move stops 1 % short).
// World frame (robot base frame), metres, seconds.

#include <Eigen/Core>
#include <vector>

namespace proprio::robot {

inline constexpr double kShapingAlpha = 1.66;
inline constexpr double kShapingEnd = 1.5;

/// A scalar and its first two time derivatives.
struct Shaped {
  double value = 0;
  double rate = 0;   ///< d/dt
  double accel = 0;  ///< d^2/dt^2
};

/// The thesis's shaping function of tau (eqs 3.31-3.33 with SPEC's corrected derivatives):
/// f = 1 - e^{-(a tau)^3}, f' = 3 a (a tau)^2 e^{-(a tau)^3},
/// f'' = a^2 (6 (a tau) - 9 (a tau)^4) e^{-(a tau)^3}.
Shaped shaping_function(double tau, double alpha = kShapingAlpha);

/// The shaped progress s(t) in [0, 1] of a move of `duration` seconds, with ds/dt and d2s/dt2:
/// s(t) = f(kShapingEnd t / T) / f(kShapingEnd). Times outside [0, T] give the end values (at
/// rest). Throws Error unless duration > 0 and alpha > 0 are finite.
class TimeShaping {
 public:
  explicit TimeShaping(double duration, double alpha = kShapingAlpha);
  [[nodiscard]] double duration() const { return duration_; }
  [[nodiscard]] double alpha() const { return alpha_; }
  [[nodiscard]] Shaped operator()(double t) const;

 private:
  double duration_;
  double alpha_;
  double norm_;  // 1 / f(kShapingEnd)
};

/// One sample of a Cartesian trajectory at time t (s since its start).
struct CartesianSample {
  double t = 0;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();      ///< m
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();      ///< m/s
  Eigen::Vector3d acceleration = Eigen::Vector3d::Zero();  ///< m/s^2
};

/// Interface of an end-effector trajectory defined on [0, duration()].
class CartesianTrajectory {
 public:
  virtual ~CartesianTrajectory() = default;
  [[nodiscard]] virtual double duration() const = 0;
  /// Position, velocity and acceleration at time t; t is clamped to [0, duration()].
  [[nodiscard]] virtual CartesianSample sample(double t) const = 0;
};

/// Quadratic Bezier from p0 to p2 with control point p1 (eq 3.30), time-shaped (eqs 3.34-3.36):
/// Phi = b(s), Phi' = b'(s) s', Phi'' = b'(s) s'' + b''(s) s'^2 (the chain rule).
class BezierTrajectory final : public CartesianTrajectory {
 public:
  /// Throws Error for non-finite points or a non-positive duration.
  BezierTrajectory(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& p2,
                   double duration, double alpha = kShapingAlpha);

  [[nodiscard]] double duration() const override { return shaping_.duration(); }
  [[nodiscard]] CartesianSample sample(double t) const override;

  /// b(s), b'(s) = db/ds and b''(s) for s in [0, 1] (eq 3.30).
  [[nodiscard]] Eigen::Vector3d curve(double s) const;
  [[nodiscard]] Eigen::Vector3d curve_derivative(double s) const;
  [[nodiscard]] Eigen::Vector3d curve_second_derivative() const;
  /// Arc length of the curve, m (Gauss-Legendre quadrature).
  [[nodiscard]] double length() const;

  [[nodiscard]] const Eigen::Vector3d& p0() const { return p0_; }
  [[nodiscard]] const Eigen::Vector3d& p1() const { return p1_; }
  [[nodiscard]] const Eigen::Vector3d& p2() const { return p2_; }
  [[nodiscard]] const TimeShaping& shaping() const { return shaping_; }

 private:
  Eigen::Vector3d p0_, p1_, p2_;
  TimeShaping shaping_;
};

/// A straight move from `from` to `to` at mean speed `speed` (m/s): duration = length / speed,
/// shaped as above (a Bezier whose control point is the midpoint is the straight segment
/// traversed at rate s). Throws Error for a zero-length move or a non-positive speed.
BezierTrajectory straight_move(const Eigen::Vector3d& from, const Eigen::Vector3d& to,
                               double speed);

/// The trajectory parameters psi = (theta, l, gamma) of eq 3.37.
struct TrajectoryParams {
  double theta = 0;   ///< direction of the move in the table plane, rad (0 = +y, pi/2 = +x)
  double length = 0;  ///< l: distance from start to end, m
  double gamma = 0;   ///< curvature: control point offset, as a fraction of l, to the side
};

/// The Bezier of eqs 3.38-3.40 relative to `start` (SPEC section 2): p0 = start,
/// p2 = p0 + l (sin theta, cos theta, 0), p1 = p0 + (p2 - p0) / 2 + gamma (p2 - p0)_perp, where
/// (x, y, 0)_perp = (-y, x, 0) (the move's direction turned +90 degrees about z). Throws Error for
/// a non-positive length or duration.
BezierTrajectory psi_trajectory(const Eigen::Vector3d& start, const TrajectoryParams& psi,
                                double duration);

/// Uniform samples from t = 0 to exactly the end: N = ceil(duration * rate) intervals of
/// duration / N (at least the requested rate), N + 1 samples. Throws Error unless rate > 0.
std::vector<CartesianSample> sample_trajectory(const CartesianTrajectory& trajectory,
                                               double rate_hz);

}  // namespace proprio::robot
