#include "proprio/robot/joint_tracking.hpp"

#include <algorithm>
#include <cmath>

#include "proprio/core/error.hpp"
#include "text.hpp"

namespace proprio::robot {

using detail::cat;
using detail::num;

JointTrajectory differentiate(std::vector<JointVector> q, double dt) {
  require(std::isfinite(dt) && dt > 0, "joint trajectory: dt must be > 0 s");
  for (const JointVector& v : q) require(v.allFinite(), "joint trajectory: q is not finite");
  JointTrajectory out;
  out.dt = dt;
  const std::size_t n = q.size();
  out.qdot.assign(n, JointVector::Zero());
  out.qddot.assign(n, JointVector::Zero());
  if (n >= 2) {
    for (std::size_t i = 1; i + 1 < n; ++i) {
      out.qdot[i] = (q[i + 1] - q[i - 1]) / (2 * dt);
      out.qddot[i] = (q[i + 1] - 2 * q[i] + q[i - 1]) / (dt * dt);
    }
    if (n == 2) {
      out.qdot[0] = out.qdot[1] = (q[1] - q[0]) / dt;
    } else {
      out.qdot[0] = (-3 * q[0] + 4 * q[1] - q[2]) / (2 * dt);
      out.qdot[n - 1] = (3 * q[n - 1] - 4 * q[n - 2] + q[n - 3]) / (2 * dt);
    }
    if (n >= 4) {
      out.qddot[0] = (2 * q[0] - 5 * q[1] + 4 * q[2] - q[3]) / (dt * dt);
      out.qddot[n - 1] = (2 * q[n - 1] - 5 * q[n - 2] + 4 * q[n - 3] - q[n - 4]) / (dt * dt);
    } else if (n == 3) {
      out.qddot[0] = out.qddot[2] = out.qddot[1];
    }
  }
  out.q = std::move(q);
  return out;
}

void TrackOptions::validate() const {
  require(std::isfinite(rate_hz) && rate_hz > 0 && rate_hz <= 1e5,
          "TrackOptions: rate_hz must be in (0, 1e5]");
  require(std::isfinite(max_joint_speed) && max_joint_speed > 0,
          "TrackOptions: max_joint_speed must be > 0 rad/s");
  ik.validate();
}

TrackResult track_trajectory(ArmState& state, const CartesianTrajectory& trajectory,
                             const JointVector& q_start, const TrackOptions& options) {
  return track_trajectory(state, trajectory, q_start, options,
                          [&options](ArmState& s, const Eigen::Vector3d& x, const JointVector& q) {
                            return solve_ik(s, x, q, options.ik);
                          });
}

TrackResult track_trajectory(ArmState& state, const CartesianTrajectory& trajectory,
                             const JointVector& q_start, const TrackOptions& options,
                             const SampleIk& solve) {
  options.validate();
  TrackResult result;
  result.path = sample_trajectory(trajectory, options.rate_hz);
  const std::size_t n = result.path.size();
  const double dt = trajectory.duration() / static_cast<double>(n - 1);
  std::vector<JointVector> q;
  q.reserve(n);
  TrackSummary& s = result.summary;
  JointVector previous = q_start;
  for (std::size_t i = 0; i < n; ++i) {
    const CartesianSample& sample = result.path[i];
    IkResult r;
    try {
      r = solve(state, sample.position, previous);
    } catch (const Error& e) {
      throw Error(cat({"trajectory sample at t = ", num(sample.t), " s: ", e.what()}));
    }
    if (i > 0) {
      const double speed = (r.q - previous).cwiseAbs().maxCoeff() / dt;
      if (speed > options.max_joint_speed) {
        throw Error(cat({"trajectory sample at t = ", num(sample.t), " s: the joints jump at ",
                         num(speed), " rad/s (limit ", num(options.max_joint_speed),
                         "): an IK branch change or a singularity on the path"}));
      }
      s.max_joint_speed = std::max(s.max_joint_speed, speed);
    } else {
      s.pitch_first = r.pitch;
    }
    s.pitch_last = r.pitch;
    s.max_residual = std::max(s.max_residual, r.summary.residual);
    (r.summary.method == IkMethod::analytic ? s.analytic : s.numerical) += 1;
    s.pitch_unmet += r.summary.pitch_met ? 0 : 1;
    previous = r.q;
    q.push_back(r.q);
  }
  s.samples = n;
  s.message = cat({"tracked ", std::to_string(n), " samples at ", num(1.0 / dt), " Hz"});
  result.joints = differentiate(std::move(q), dt);
  return result;
}

}  // namespace proprio::robot
