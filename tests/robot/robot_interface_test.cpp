// The robot interface's shared pieces: pixels to the table (eqs 3.13-3.17), a push's joint
// samples (IK of lower, push, lift) and its refusals.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "proprio/core/error.hpp"
#include "proprio/robot/robot_interface.hpp"
#include "test_arm.hpp"

namespace proprio::robot {
namespace {

geometry::Camera oblique_camera() {
  geometry::Camera c;
  c.K << 500, 0, 320, 0, 500, 240, 0, 0, 1;
  // Looking along +y and down 45 degrees from (0.25, -0.5, 0.5).
  const double a = std::numbers::pi / 4;
  Eigen::Matrix3d R;
  R << 1, 0, 0, 0, -std::sin(a), -std::cos(a), 0, std::cos(a), -std::sin(a);
  c.R = R;
  c.t = -R * Eigen::Vector3d(0.25, -0.5, 0.5);
  c.width = 640;
  c.height = 480;
  return c;
}

TEST(RobotInterface, PixelsBackProjectOntoTheTable) {
  const geometry::Camera c = oblique_camera();
  for (const Eigen::Vector3d& X : {Eigen::Vector3d(0.25, 0.0, 0.0), Eigen::Vector3d(0.4, 0.1, 0.0),
                                   Eigen::Vector3d(0.1, -0.1, 0.03)}) {
    const Eigen::Vector2d t = pixel_to_table(c, c.project(X), X.z());
    EXPECT_LT((t - X.head<2>()).norm(), 1e-9);
  }
  ImagePush ip;
  ip.start = c.project(Eigen::Vector3d(0.2, 0.0, 0.0));
  ip.end = c.project(Eigen::Vector3d(0.3, 0.05, 0.0));
  const TablePush tp = to_table(c, ip);
  EXPECT_LT((tp.start - Eigen::Vector2d(0.2, 0.0)).norm(), 1e-9);
  EXPECT_LT((tp.end - Eigen::Vector2d(0.3, 0.05)).norm(), 1e-9);
  EXPECT_THROW((void)pixel_to_table(c, Eigen::Vector2d(320, -2000)), Error);  // above the horizon
}

TEST(RobotInterface, PushMotionLowersPushesAndLiftsAtTheTipHeight) {
  ArmState state(testing::standard_arm());
  TablePush p;
  p.start = {0.18, -0.05};
  p.end = {0.28, -0.05};
  const PushMotion m = plan_push_motion(state, p, JointVector::Zero());
  ASSERT_GT(m.push_end, m.push_begin);
  ASSERT_LT(static_cast<std::size_t>(m.push_end), m.joints.size());
  const Eigen::Vector3d a = state.ee_position(m.joints.q[static_cast<std::size_t>(m.push_begin)]);
  const Eigen::Vector3d b = state.ee_position(m.joints.q[static_cast<std::size_t>(m.push_end)]);
  EXPECT_LT((a - Eigen::Vector3d(0.18, -0.05, p.height)).norm(), 1e-6);
  EXPECT_LT((b - Eigen::Vector3d(0.28, -0.05, p.height)).norm(), 1e-6);
  const Eigen::Vector3d top = state.ee_position(m.joints.q.back());
  EXPECT_NEAR(top.z(), p.height + PushMotionOptions{}.lift, 1e-6);
  for (const JointVector& q : m.joints.q) ASSERT_TRUE(q.allFinite());
  EXPECT_TRUE(reachable(state, p.start, p.height, JointVector::Zero()));
}

// The jaws' line (the ee site's y axis) against the push's direction, |cos|, where the tip is
// nearest the push's middle.
double jaws_along_push(ArmState& state, const PushMotion& m, const TablePush& p) {
  const Eigen::Vector2d middle = 0.5 * (p.start + p.end);
  std::size_t mid = 0;
  double nearest = 1e9;
  for (int k = m.push_begin; k <= m.push_end; ++k) {
    const auto i = static_cast<std::size_t>(k);
    const double gap = (state.ee_position(m.joints.q[i]).head<2>() - middle).norm();
    if (gap < nearest) {
      nearest = gap;
      mid = i;
    }
  }
  EXPECT_LT(nearest, 1e-3);
  const Eigen::Vector3d y = state.ee_pose(m.joints.q[mid]).rotation.col(1);
  const Eigen::Vector2d d = (p.end - p.start).normalized();
  return std::abs(y.head<2>().dot(d)) / y.norm();
}

TEST(RobotInterface, RollAcrossTurnsTheJawsAcrossTheLineOfATangentialPush) {
  ArmState state(testing::standard_arm());
  TablePush across;  // across the arm's radius, at 0.25 m
  across.start = {0.25, -0.05};
  across.end = {0.25, 0.05};
  const PushMotion kept = plan_push_motion(state, across, JointVector::Zero());
  // j5 kept at 0: the jaws lie along the arm's tangent, ahead of and behind the pusher.
  EXPECT_GT(jaws_along_push(state, kept, across), 0.95);
  PushMotionOptions o;
  o.roll_across = true;
  const PushMotion rolled = plan_push_motion(state, across, JointVector::Zero(), o);
  EXPECT_LT(jaws_along_push(state, rolled, across), 0.01);  // a sample from the middle
  // The roll does not move the tip: the push is the same line.
  for (const int k : {rolled.push_begin, rolled.push_end}) {
    const auto i = static_cast<std::size_t>(k);
    EXPECT_LT((state.ee_position(rolled.joints.q[i]) - state.ee_position(kept.joints.q[i])).norm(),
              1e-6);
  }
  // A push along the radius keeps (about) the roll it had: the jaws already lie across it.
  TablePush along;
  along.start = {0.18, 0.0};
  along.end = {0.28, 0.0};
  const PushMotion radial = plan_push_motion(state, along, JointVector::Zero(), o);
  EXPECT_LT(std::abs(radial.q_above_start[4]), 1e-6);
  EXPECT_LT(jaws_along_push(state, radial, along), 0.01);
  EXPECT_THROW((void)fingers_across_roll(state, JointVector::Zero(), Eigen::Vector2d::Zero()),
               Error);
}

TEST(RobotInterface, APushsJawLineOverridesTheRobotsRoll) {
  // TablePush::jaws: kAlong turns the jaws' line along the push (radial and tangential pushes),
  // kAcross across it even when the robot's own setting (roll_across) is off, kRobot leaves it to
  // that setting; the tip's path is the same line whatever the roll.
  ArmState state(testing::standard_arm());
  for (const bool radial : {false, true}) {
    TablePush p;
    p.start = radial ? Eigen::Vector2d(0.18, 0.0) : Eigen::Vector2d(0.25, -0.05);
    p.end = radial ? Eigen::Vector2d(0.28, 0.0) : Eigen::Vector2d(0.25, 0.05);
    const PushMotion kept = plan_push_motion(state, p, JointVector::Zero());
    p.jaws = JawLine::kAlong;
    const PushMotion along = plan_push_motion(state, p, JointVector::Zero());
    EXPECT_GT(jaws_along_push(state, along, p), 0.9999) << radial;
    PushMotionOptions o;
    o.roll_across = true;  // the push's own line wins over the robot's setting
    EXPECT_GT(jaws_along_push(state, plan_push_motion(state, p, JointVector::Zero(), o), p),
              0.9999);
    p.jaws = JawLine::kAcross;
    EXPECT_LT(jaws_along_push(state, plan_push_motion(state, p, JointVector::Zero()), p), 0.01);
    for (const int k : {along.push_begin, along.push_end}) {
      const auto i = static_cast<std::size_t>(k);
      EXPECT_LT((state.ee_position(along.joints.q[i]) - state.ee_position(kept.joints.q[i])).norm(),
                1e-6);
    }
  }
  EXPECT_THROW((void)fingers_along_roll(state, JointVector::Zero(), Eigen::Vector2d::Zero()),
               Error);
}

TEST(RobotInterface, RefusesBadAndUnreachablePushes) {
  ArmState state(testing::standard_arm());
  TablePush far;
  far.start = {0.80, 0.0};
  far.end = {0.90, 0.0};
  EXPECT_THROW((void)plan_push_motion(state, far, JointVector::Zero()), Error);
  EXPECT_FALSE(reachable(state, far.start, far.height, JointVector::Zero()));
  EXPECT_FALSE(reachable(state, {std::nan(""), 0.0}, 0.01, JointVector::Zero()));
  TablePush shortp;
  shortp.start = {0.2, 0.0};
  shortp.end = {0.201, 0.0};
  EXPECT_THROW(shortp.validate(), Error);
  TablePush high = shortp;
  high.end = {0.3, 0.0};
  high.height = 0.5;
  EXPECT_THROW(high.validate(), Error);
}

}  // namespace
}  // namespace proprio::robot
