#include "proprio/planning/arm_motion.hpp"

#include <algorithm>
#include <cmath>

#include "proprio/core/error.hpp"

namespace proprio::planning {

void ArmMotionOptions::validate() const {
  require(std::isfinite(preferred_pitch) && std::abs(preferred_pitch) <= std::numbers::pi,
          "ArmMotionOptions: preferred_pitch must be in [-pi, pi]");
  require(std::isfinite(pitch_margin) && pitch_margin >= 0 && pitch_margin < 1.5,
          "ArmMotionOptions: pitch_margin must be in [0, 1.5) rad");
  require(std::isfinite(max_joint_speed) && max_joint_speed > 0,
          "ArmMotionOptions: max_joint_speed must be > 0 rad/s");
}

double scheduled_pitch(const robot::ArmGeometry& g, const Eigen::Vector3d& x,
                       const ArmMotionOptions& options) {
  if (!g.analytic) return options.preferred_pitch;
  const double radial = (x.head<2>() - g.base_xy).norm();
  const robot::PitchWindow w = robot::reachable_pitch(g, radial, x.z());
  if (w.empty()) return options.preferred_pitch;  // out of reach: IK reports it
  double lo = w.lo + options.pitch_margin;
  double hi = w.hi - options.pitch_margin;
  if (lo > hi) lo = hi = 0.5 * (w.lo + w.hi);
  const double d = options.preferred_pitch - w.phi;
  const double ad = std::clamp(std::abs(d), lo, hi);
  return w.phi + (d >= 0 ? ad : -ad);
}

robot::IkResult solve_scheduled(robot::ArmState& state, const Eigen::Vector3d& x,
                                const robot::JointVector& q_start,
                                const ArmMotionOptions& options) {
  robot::IkOptions ik;
  ik.pitch = scheduled_pitch(state.arm().geometry(), x, options);
  ik.strict_pitch = state.arm().geometry().analytic;
  return robot::solve_ik(state, x, q_start, ik);
}

robot::TrackResult track_scheduled(robot::ArmState& state,
                                   const robot::CartesianTrajectory& trajectory,
                                   const robot::JointVector& q_start, double rate_hz,
                                   const ArmMotionOptions& options) {
  options.validate();
  robot::TrackOptions track;
  track.rate_hz = rate_hz;
  track.max_joint_speed = options.max_joint_speed;
  return robot::track_trajectory(
      state, trajectory, q_start, track,
      [&options](robot::ArmState& s, const Eigen::Vector3d& x, const robot::JointVector& q) {
        return solve_scheduled(s, x, q, options);
      });
}

}  // namespace proprio::planning
