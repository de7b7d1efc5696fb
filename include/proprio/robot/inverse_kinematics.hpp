#pragma once
// Inverse kinematics, ee position -> joint angles (thesis 3.1.1, eqs 3.4-3.6, Appendix A).
//
// The arm has five joints and a position target has three coordinates: the two spare degrees are
// the roll j5 (it does not move the ee; it keeps its start value) and the pitch of the last link,
// which the caller asks for. Pitch is the elevation of the last link's pointing direction above
// the horizontal (rad; -pi/2 = pointing straight down). Appendix A's approach angle is
// psi = pitch + pi (A.18 places the wrist at v + |c| (sin psi n3 + cos psi o)).

#include <Eigen/Core>
#include <numbers>
#include <string>

#include "proprio/robot/arm.hpp"

namespace proprio::robot {

enum class IkMethod {
  automatic,  ///< analytic when the arm's geometry allows it, else numerical
  analytic,   ///< Appendix A only; throws Error for an arm without the required structure
  numerical,  ///< damped least squares from the start configuration (eq 3.6)
};

[[nodiscard]] const char* to_string(IkMethod method);

struct IkOptions {
  IkMethod method = IkMethod::automatic;
  /// Requested pitch of the last link, rad. Pushing uses a pusher pointing down.
  double pitch = -std::numbers::pi / 2;
  /// Whether `pitch` must be met exactly. When false, the analytic solver takes the reachable
  /// pitch nearest to it (within the joint limits), and the numerical solver treats it as a soft
  /// secondary goal (position first).
  bool strict_pitch = false;
  /// Prefer the convex elbow (elbow above the shoulder-wrist line; the thesis's t = pi).
  bool elbow_up = true;
  /// Accept the other elbow when the preferred one violates a joint limit.
  bool allow_elbow_flip = true;
  /// Targets below this height (the table top) are unreachable, m.
  double min_height = 0.0;
  /// Margin added around the base's keep-out cylinder, m.
  double base_clearance = 0.0;
  // Numerical solver (Levenberg-Marquardt-damped Gauss-Newton on g(q) = f(q) - x, eq 3.6).
  /// Iteration budget of each phase (with the pitch goal, then position only when it fails).
  int max_iterations = 200;
  /// Convergence: ee position error below this, m.
  double tolerance = 1e-10;
  /// Initial damping lambda of (J^T J + lambda^2 I) dq = J^T e; adapted each step.
  double initial_damping = 1e-2;
  /// Weight of the pointing-direction residual against the position residual, m per unit.
  double pitch_weight = 0.05;

  /// Throws Error when an option is out of range.
  void validate() const;
};

struct IkSummary {
  IkMethod method = IkMethod::automatic;  ///< the solver that produced the answer
  int iterations = 0;                     ///< numerical iterations (0 for the analytic solver)
  double residual = 0;                    ///< |f(q) - target| at the answer, m
  bool elbow_up = true;                   ///< which elbow the answer uses (analytic)
  bool pitch_met = false;                 ///< the answer has the requested pitch (to 1e-9 rad)
  std::string message;                    ///< how it stopped, in words
  /// What a person reads: the message.
  [[nodiscard]] std::string brief() const { return message; }
};

struct IkResult {
  JointVector q = JointVector::Zero();
  double pitch = 0;  ///< pitch of the last link at q, rad
  IkSummary summary;
};

/// Solves for joint angles that put the ee site at `target` (world frame, m), starting from and
/// staying close to `q_start` (the current configuration; its j5 is kept). The answer respects
/// the joint limits. Throws Error, naming the target and the reason, when the target is not
/// finite, below `min_height`, inside the base, out of reach, or has no solution within the
/// limits; never returns NaN.
IkResult solve_ik(ArmState& state, const Eigen::Vector3d& target, const JointVector& q_start,
                  const IkOptions& options = {});

/// The set of reachable pitches at `target` ignoring joint limits, as the interval of elevation
/// offsets [lo, hi] (rad, both >= 0) such that pitch = phi +- delta with delta in [lo, hi], where
/// phi is the elevation of the target seen from the shoulder in the forward plane. Empty (lo > hi)
/// when the target is out of reach. Analytic arms only (Appendix A's circle A.14 exists).
struct PitchWindow {
  double phi = 0;
  double lo = 1;
  double hi = 0;
  [[nodiscard]] bool empty() const { return lo > hi; }
};
PitchWindow reachable_pitch(const ArmGeometry& geometry, double radial, double height);

}  // namespace proprio::robot
