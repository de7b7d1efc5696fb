#pragma once
// Joint-space tracking of a Cartesian trajectory: sample it at the control rate and solve the
// inverse kinematics of each sample from the previous solution, so that q(t) is continuous.

#include <functional>
#include <string>
#include <vector>

#include "proprio/robot/arm.hpp"
#include "proprio/robot/inverse_kinematics.hpp"
#include "proprio/robot/trajectory.hpp"

namespace proprio::robot {

/// Joint positions (rad), velocities (rad/s) and accelerations (rad/s^2) at uniform times
/// t_i = i dt, i = 0..size()-1.
struct JointTrajectory {
  double dt = 0;  ///< s
  std::vector<JointVector> q;
  std::vector<JointVector> qdot;
  std::vector<JointVector> qddot;
  [[nodiscard]] std::size_t size() const { return q.size(); }
  [[nodiscard]] double duration() const {
    return q.empty() ? 0.0 : dt * static_cast<double>(q.size() - 1);
  }
};

/// Fills qdot and qddot from q by finite differences: central in the interior, second-order
/// one-sided at the ends. Throws Error unless dt > 0 and q is finite.
JointTrajectory differentiate(std::vector<JointVector> q, double dt);

struct TrackOptions {
  /// Control rate, Hz (500 = MuJoCo's default 2 ms step).
  double rate_hz = 500;
  /// Inverse kinematics of every sample (pitch, elbow, method); each sample starts from the
  /// previous solution. The requested pitch is met where reachable and approached (continuously)
  /// where not.
  IkOptions ik;
  /// Fastest joint motion accepted between samples, rad/s: a faster jump means the IK switched
  /// branches or crossed a singularity, and is an Error.
  double max_joint_speed = 10;
  /// Throws Error when an option is out of range.
  void validate() const;
};

struct TrackSummary {
  std::size_t samples = 0;
  int analytic = 0;            ///< samples solved analytically
  int numerical = 0;           ///< samples solved numerically
  double max_residual = 0;     ///< largest |f(q_i) - x_i|, m
  double max_joint_speed = 0;  ///< largest |q_{i+1} - q_i|_inf / dt, rad/s
  double pitch_first = 0;      ///< pitch of the last link at the start, rad
  double pitch_last = 0;       ///< and at the end
  int pitch_unmet = 0;         ///< samples where the requested pitch was not reachable
  std::string message;
  /// What a person reads: the message.
  [[nodiscard]] std::string brief() const { return message; }
};

struct TrackResult {
  JointTrajectory joints;
  std::vector<CartesianSample> path;  ///< the Cartesian samples, one per joint sample
  TrackSummary summary;
};

/// Tracks `trajectory` from `q_start` (the current configuration; the first sample is solved from
/// it). Throws Error naming the sample's time when a sample is unreachable or the solution jumps.
TrackResult track_trajectory(ArmState& state, const CartesianTrajectory& trajectory,
                             const JointVector& q_start, const TrackOptions& options = {});

/// The inverse kinematics of one sample: position `x` (m, robot frame) solved from `q_previous`.
using SampleIk = std::function<IkResult(ArmState& state, const Eigen::Vector3d& x,
                                        const JointVector& q_previous)>;

/// track_trajectory with `solve` in place of solve_ik with options.ik (which is not used), for a
/// per-sample choice of IK options such as planning's pitch schedule (planning::track_scheduled).
TrackResult track_trajectory(ArmState& state, const CartesianTrajectory& trajectory,
                             const JointVector& q_start, const TrackOptions& options,
                             const SampleIk& solve);

}  // namespace proprio::robot
