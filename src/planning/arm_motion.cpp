#include "proprio/planning/arm_motion.hpp"

#include <algorithm>
#include <cmath>

#include "proprio/core/error.hpp"
#include "text.hpp"

namespace proprio::planning {

using detail::cat;
using detail::num;

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
  robot::TrackResult result;
  result.path = robot::sample_trajectory(trajectory, rate_hz);
  const std::size_t n = result.path.size();
  const double dt = trajectory.duration() / static_cast<double>(n - 1);
  std::vector<robot::JointVector> q;
  q.reserve(n);
  robot::TrackSummary& s = result.summary;
  robot::JointVector previous = q_start;
  for (std::size_t i = 0; i < n; ++i) {
    const robot::CartesianSample& sample = result.path[i];
    robot::IkResult r;
    try {
      r = solve_scheduled(state, sample.position, previous, options);
    } catch (const Error& e) {
      throw Error(cat({"trajectory sample at t = ", num(sample.t), " s: ", e.what()}));
    }
    if (i > 0) {
      const double speed = (r.q - previous).cwiseAbs().maxCoeff() / dt;
      if (speed > options.max_joint_speed) {
        throw Error(cat({"trajectory sample at t = ", num(sample.t), " s: the joints jump at ",
                         num(speed), " rad/s (limit ", num(options.max_joint_speed), ")"}));
      }
      s.max_joint_speed = std::max(s.max_joint_speed, speed);
    } else {
      s.pitch_first = r.pitch;
    }
    s.pitch_last = r.pitch;
    s.max_residual = std::max(s.max_residual, r.summary.residual);
    if (r.summary.method == robot::IkMethod::analytic) {
      ++s.analytic;
    } else {
      ++s.numerical;
    }
    if (!r.summary.pitch_met) ++s.pitch_unmet;
    q.push_back(r.q);
    previous = r.q;
  }
  s.samples = n;
  s.message = "tracked";
  result.joints = robot::differentiate(std::move(q), dt);
  return result;
}

}  // namespace proprio::planning
