#include "proprio/robot/robot_interface.hpp"

#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "proprio/core/error.hpp"
#include "proprio/robot/trajectory.hpp"

namespace proprio::robot {

namespace {
constexpr double kShortestPush = 0.005;  // m
constexpr double kHighestPush = 0.1;     // m
constexpr double kFastestPush = 0.5;     // m/s
}  // namespace

void TablePush::validate() const {
  require(start.allFinite() && end.allFinite(), "push: start and end must be finite");
  require(std::isfinite(height) && height > 0 && height <= kHighestPush,
          "push: height must be in (0, 0.1] m");
  require(std::isfinite(speed) && speed > 0 && speed <= kFastestPush,
          "push: speed must be in (0, 0.5] m/s");
  require(length() >= kShortestPush, "push: the line must be at least 5 mm long");
}

void PushMotionOptions::validate() const {
  require(std::isfinite(rate_hz) && rate_hz > 0, "push motion: rate must be > 0 Hz");
  require(std::isfinite(lift) && lift > 0 && lift <= 0.3,
          "push motion: lift must be in (0, 0.3] m");
  require(std::isfinite(lift_speed) && lift_speed > 0 && lift_speed <= 1.0,
          "push motion: lift speed must be in (0, 1] m/s");
  require(std::isfinite(max_joint_speed) && max_joint_speed > 0,
          "push motion: max joint speed must be > 0 rad/s");
  ik.validate();
}

Eigen::Vector2d pixel_to_table(const geometry::Camera& camera, const Eigen::Vector2d& pixel,
                               double plane_height) {
  geometry::Plane plane;
  plane.n = Eigen::Vector3d::UnitZ();
  plane.kappa = plane_height;
  const geometry::BackProjection b = geometry::back_project_to_plane(camera.P(), pixel, plane);
  return b.X.head<2>();
}

TablePush to_table(const geometry::Camera& camera, const ImagePush& push) {
  TablePush t;
  t.start = pixel_to_table(camera, push.start);
  t.end = pixel_to_table(camera, push.end);
  t.height = push.height;
  t.speed = push.speed;
  return t;
}

namespace {

// Appends the joint samples of `move` tracked from `q` (the first sample repeats q and is
// dropped when `out` is not empty); returns the last joints.
JointVector append_move(ArmState& state, const CartesianTrajectory& move, const JointVector& q,
                        const PushMotionOptions& options, std::vector<JointVector>& out) {
  TrackOptions track;
  track.rate_hz = options.rate_hz;
  track.ik = options.ik;
  track.max_joint_speed = options.max_joint_speed;
  const TrackResult r = track_trajectory(state, move, q, track);
  const std::size_t first = out.empty() ? 0 : 1;
  for (std::size_t i = first; i < r.joints.q.size(); ++i) out.push_back(r.joints.q[i]);
  return r.joints.q.back();
}

}  // namespace

namespace {

// The roll that puts the jaws' line (the last link's y axis) across (`along` false) or along the
// table direction `direction`, with j1..j4 of q: the one of theta + k pi within j5's limits
// nearest q's j5.
double fingers_roll(ArmState& state, const JointVector& q, const Eigen::Vector2d& direction,
                    bool along) {
  require(direction.allFinite() && direction.norm() > 0,
          along ? "fingers along: the push direction must be finite and non-zero"
                : "fingers across: the push direction must be finite and non-zero");
  const Eigen::Vector3d d(direction.x(), direction.y(), 0);
  // j5 turns about the last link's x axis: y(theta) = cos(theta) y0 + sin(theta) z0 (y0, z0 at
  // j5 = 0, the joint's axis is +x), so y . d = 0 at theta = atan2(-y0 . d, z0 . d) (mod pi)
  // and y . d is largest (z . d = 0) at theta = atan2(z0 . d, y0 . d).
  JointVector q0 = q;
  q0[4] = 0;
  const Eigen::Matrix3d r = state.ee_pose(q0).rotation;
  const double a = r.col(1).dot(d);
  const double b = r.col(2).dot(d);
  const double theta = along ? std::atan2(b, a) : std::atan2(-a, b);
  const double lo = state.arm().lower()[4];
  const double hi = state.arm().upper()[4];
  double best = q[4];
  double best_gap = std::numeric_limits<double>::infinity();
  for (int k = -2; k <= 2; ++k) {
    const double c = theta + k * std::numbers::pi;
    if (c < lo || c > hi) continue;
    const double gap = std::abs(c - q[4]);
    if (gap < best_gap) {
      best = c;
      best_gap = gap;
    }
  }
  ensure(std::isfinite(best_gap), "fingers: no roll within j5's limits");
  return best;
}

}  // namespace

double fingers_across_roll(ArmState& state, const JointVector& q,
                           const Eigen::Vector2d& direction) {
  return fingers_roll(state, q, direction, false);
}

double fingers_along_roll(ArmState& state, const JointVector& q, const Eigen::Vector2d& direction) {
  return fingers_roll(state, q, direction, true);
}

PushMotion plan_push_motion(ArmState& state, const TablePush& push, const JointVector& q_rest,
                            const PushMotionOptions& options) {
  push.validate();
  options.validate();
  const Eigen::Vector3d start(push.start.x(), push.start.y(), push.height);
  const Eigen::Vector3d end(push.end.x(), push.end.y(), push.height);
  const Eigen::Vector3d up(0, 0, options.lift);
  PushMotion m;
  JointVector q_from = q_rest;
  const bool across =
      push.jaws == JawLine::kAcross || (push.jaws == JawLine::kRobot && options.roll_across);
  if (across || push.jaws == JawLine::kAlong) {
    // The roll at the push's middle (j1 turns during a push across the arm's radius).
    const JointVector q_mid = solve_ik(state, 0.5 * (start + end), q_rest, options.ik).q;
    q_from[4] = fingers_roll(state, q_mid, push.end - push.start, !across);
  }
  m.q_above_start = solve_ik(state, start + up, q_from, options.ik).q;
  std::vector<JointVector> q;
  JointVector last = append_move(state, straight_move(start + up, start, options.lift_speed),
                                 m.q_above_start, options, q);
  m.push_begin = static_cast<int>(q.size()) - 1;
  last = append_move(state, straight_move(start, end, push.speed), last, options, q);
  m.push_end = static_cast<int>(q.size()) - 1;
  (void)append_move(state, straight_move(end, end + up, options.lift_speed), last, options, q);
  for (const JointVector& s : q) ensure(s.allFinite(), "push motion: non-finite joint sample");
  m.joints = differentiate(std::move(q), 1.0 / options.rate_hz);
  return m;
}

bool reachable(ArmState& state, const Eigen::Vector2d& xy, double height, const JointVector& q_rest,
               const IkOptions& ik) {
  if (!xy.allFinite()) return false;
  try {
    (void)solve_ik(state, Eigen::Vector3d(xy.x(), xy.y(), height), q_rest, ik);
    return true;
  } catch (const Error&) {
    return false;
  }
}

}  // namespace proprio::robot
