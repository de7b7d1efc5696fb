// The arm's own image in a push's frame (loop/arm_image.hpp).
#include "arm_image.hpp"

#include <mujoco/mujoco.h>

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "proprio/robot/robot_interface.hpp"

namespace proprio::loop::detail {

namespace {

constexpr double kArmRadius = 0.035;  // the pusher and links' half width, m
// The links' half width as the arm mask draws them, m: the image of a raised link (nearer the
// camera, with its shading) is wider than kArmRadius at the table would give.
constexpr double kLinkRadius = 0.06;
constexpr double kArmBaseHeight = 0.1;  // a point of the arm's base above the table, m

// A band kArmRadius wide (on the table) from the end effector at `ee` (px) toward the base.
cv::Mat1b arm_region(const episode::Episode& e, const std::optional<Eigen::Vector2d>& ee,
                     cv::Size size) {
  cv::Mat1b m(size, 0);
  if (!ee) return m;
  const geometry::Camera& cam = e.camera();
  const Eigen::Vector2d base = cam.project(Eigen::Vector3d(0, 0, kArmBaseHeight));
  const Eigen::Vector3d at = robot::pixel_to_table(cam, *ee).homogeneous();
  const Eigen::Vector3d tip(at.x(), at.y(), 0.0);
  const double r = (cam.project(tip + Eigen::Vector3d(kArmRadius, 0, 0)) - cam.project(tip)).norm();
  const int t = std::max(2, static_cast<int>(std::lround(2 * r)));
  const Eigen::Vector2d toward = base - *ee;
  const Eigen::Vector2d far = *ee + (toward.norm() > 0 ? 4.0 * toward : toward);
  cv::line(m, cv::Point(static_cast<int>(ee->x()), static_cast<int>(ee->y())),
           cv::Point(static_cast<int>(far.x()), static_cast<int>(far.y())), 255, t);
  cv::circle(m, cv::Point(static_cast<int>(ee->x()), static_cast<int>(ee->y())), t / 2, 255, -1);
  return m;
}

}  // namespace

// The arm's own image in frame `i` of a push's episode: every link of its kinematic chain
// (base body to the end effector, placed by the frame's joint angles with the robot's own
// kinematics) drawn as a band kLinkRadius wide, plus the pusher. The old band from the end
// effector toward the base's foot missed the raised forearm and cut the table in front of it.
// Without joint angles, arm_region.
cv::Mat1b arm_image_mask(const episode::Episode& e, int i, cv::Size size, const robot::Arm& arm,
                         std::optional<robot::ArmState>& state) {
  const auto iu = static_cast<std::size_t>(i);
  if (iu >= e.arm().size() || e.arm()[iu].q.size() < robot::kArmJoints) {
    return arm_region(e, e.ee_image(i), size);
  }
  if (!state) state.emplace(arm);
  const robot::JointVector q = e.arm()[iu].q.head<robot::kArmJoints>();
  state->set_joints(q);
  const mjModel& m = state->arm().model();
  const mjData& d = state->data();
  const int base = state->arm().base_body();
  const auto in_chain = [&](int b) {
    for (int a = b; a > 0; a = m.body_parentid[a]) {
      if (a == base) return true;
    }
    return false;
  };
  const geometry::Camera& cam = e.camera();
  cv::Mat1b out(size, 0);
  const auto pos = [&](const mjtNum* x) { return Eigen::Vector3d(x[0], x[1], x[2]); };
  const auto band = [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    const Eigen::Vector3d mid = 0.5 * (a + b);
    const Eigen::Vector2d pm = cam.project(mid);
    const double r = std::max((cam.project(mid + Eigen::Vector3d(kLinkRadius, 0, 0)) - pm).norm(),
                              (cam.project(mid + Eigen::Vector3d(0, kLinkRadius, 0)) - pm).norm());
    const int t = std::max(2, static_cast<int>(std::lround(2 * r)));
    const Eigen::Vector2d pa = cam.project(a);
    const Eigen::Vector2d pb = cam.project(b);
    const cv::Point qa(static_cast<int>(std::lround(pa.x())),
                       static_cast<int>(std::lround(pa.y())));
    const cv::Point qb(static_cast<int>(std::lround(pb.x())),
                       static_cast<int>(std::lround(pb.y())));
    cv::line(out, qa, qb, 255, t);
    cv::circle(out, qa, t / 2, 255, -1);
    cv::circle(out, qb, t / 2, 255, -1);
  };
  for (int b = 1; b < m.nbody; ++b) {
    if (!in_chain(b) || b == base) continue;
    band(pos(d.xpos + (3 * m.body_parentid[b])), pos(d.xpos + (3 * b)));
  }
  const int site = state->arm().ee_site();
  if (site >= 0) band(pos(d.xpos + (3 * m.site_bodyid[site])), pos(d.site_xpos + (3 * site)));
  // The base's column, from the table up to its body.
  const Eigen::Vector3d b0 = pos(d.xpos + (3 * base));
  band(Eigen::Vector3d(b0.x(), b0.y(), 0.0), b0);
  return out;
}

}  // namespace proprio::loop::detail
