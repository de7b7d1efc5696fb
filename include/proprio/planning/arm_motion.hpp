#pragma once
// Joint-space tracking of the interception trajectories. The psi family (eqs 3.37-3.40) sweeps a
// half-disc of radius 0.21 m, wider than the band where the pusher can point straight down, and
// near the edge of the reachable pitches the elbow straightens and the joints race. So the pitch
// of the last link follows a schedule: the reachable pitch nearest the preferred one that keeps
// `pitch_margin` from the limits of the reachable window (robot::reachable_pitch). It varies
// continuously with the target, so the joints move smoothly.

#include <Eigen/Core>
#include <numbers>

#include "proprio/robot/arm.hpp"
#include "proprio/robot/inverse_kinematics.hpp"
#include "proprio/robot/joint_tracking.hpp"
#include "proprio/robot/trajectory.hpp"

namespace proprio::planning {

struct ArmMotionOptions {
  /// Pitch of the last link asked for where it is comfortably reachable, rad (pusher down).
  double preferred_pitch = -std::numbers::pi / 2;
  /// Distance kept from the limits of the reachable pitch window, rad.
  double pitch_margin = 0.35;
  /// Fastest joint motion accepted between samples, rad/s (robot::TrackOptions).
  double max_joint_speed = 10;
  /// Throws Error when an option is out of range.
  void validate() const;
};

/// The scheduled pitch at world point x, rad. For an arm without the analytic structure
/// (robot::ArmGeometry::analytic false) it is the preferred pitch.
double scheduled_pitch(const robot::ArmGeometry& geometry, const Eigen::Vector3d& x,
                       const ArmMotionOptions& options);

/// Inverse kinematics of x with the scheduled pitch (exact on analytic arms; a soft goal of the
/// numerical solver otherwise), from q_start. Throws Error like robot::solve_ik.
robot::IkResult solve_scheduled(robot::ArmState& state, const Eigen::Vector3d& x,
                                const robot::JointVector& q_start, const ArmMotionOptions& options);

/// Samples `trajectory` at `rate_hz` (robot::sample_trajectory) and solves each sample with
/// solve_scheduled from the previous solution; velocities and accelerations by finite
/// differences. Throws Error naming the sample's time when a sample is unreachable or the joints
/// jump faster than max_joint_speed.
robot::TrackResult track_scheduled(robot::ArmState& state,
                                   const robot::CartesianTrajectory& trajectory,
                                   const robot::JointVector& q_start, double rate_hz,
                                   const ArmMotionOptions& options);

}  // namespace proprio::planning
