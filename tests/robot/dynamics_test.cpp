#include "proprio/robot/dynamics.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <numbers>

#include "proprio/core/error.hpp"
#include "proprio/robot/joint_tracking.hpp"
#include "test_arm.hpp"

namespace proprio::robot {
namespace {

using testing::error_of;
using testing::standard_arm;

JointVector rest_pose() {
  JointVector q;
  q << 0.0, 0.8, -1.4, -0.9, 0.0;
  return q;
}

/// A push along the table in front of the arm, pusher pointing down, 2 cm above the table.
BezierTrajectory push_path(double duration) {
  return BezierTrajectory({0.18, -0.12, 0.02}, {0.24, -0.01, 0.02}, {0.30, 0.10, 0.02}, duration);
}

TEST(Differentiate, ExactForQuadraticsAtEveryPoint) {
  std::vector<JointVector> q;
  const double dt = 0.01;
  JointVector a, b, c;
  a << 1, 2, 3, 4, 5;
  b << -1, 0.5, 0, 2, 1;
  c << 0.3, -0.2, 0.1, 0, 2;
  for (int i = 0; i < 9; ++i) {
    const double t = i * dt;
    q.push_back(a + b * t + c * t * t);
  }
  const JointTrajectory j = differentiate(q, dt);
  for (int i = 0; i < 9; ++i) {
    const double t = i * dt;
    EXPECT_LT((j.qdot[static_cast<std::size_t>(i)] - (b + 2 * c * t)).norm(), 1e-10) << i;
    EXPECT_LT((j.qddot[static_cast<std::size_t>(i)] - 2 * c).norm(), 1e-7) << i;
  }
  EXPECT_NEAR(j.duration(), 0.08, 1e-15);
  EXPECT_THROW(differentiate(q, 0.0), Error);
}

TEST(JointTracking, FollowsThePathContinuouslyWithThePusherDown) {
  ArmState state(standard_arm());
  const BezierTrajectory path = push_path(2.0);
  const TrackResult r = track_trajectory(state, path, rest_pose());
  const TrackSummary& s = r.summary;
  EXPECT_EQ(s.samples, 1001u);
  EXPECT_EQ(s.analytic, 1001);
  EXPECT_EQ(s.pitch_unmet, 0);
  EXPECT_LT(s.max_residual, 1e-9);
  EXPECT_NEAR(s.pitch_first, -std::numbers::pi / 2, 1e-9);
  EXPECT_LT(s.max_joint_speed, 3.0);
  ASSERT_EQ(r.joints.size(), r.path.size());
  EXPECT_NEAR(r.joints.dt, 0.002, 1e-15);
  for (std::size_t i = 0; i < r.path.size(); i += 25) {
    EXPECT_LT((state.ee_position(r.joints.q[i]) - r.path[i].position).norm(), 1e-9);
    // eq 3.3: J qdot = xdot, to the finite-difference error of qdot.
    const PositionJacobian J = state.jacobian(r.joints.q[i]);
    EXPECT_LT((J * r.joints.qdot[i] - r.path[i].velocity).norm(), 2e-5) << "t = " << r.path[i].t;
  }
  EXPECT_LT(r.joints.qdot.front().norm(), 1e-4);
  EXPECT_LT(r.joints.qdot.back().norm(), 1e-4);
}

TEST(JointTracking, UnreachableSampleOrJumpIsAnError) {
  ArmState state(standard_arm());
  const BezierTrajectory too_far({0.3, 0, 0.1}, {0.5, 0, 0.1}, {0.7, 0, 0.1}, 1.0);
  TrackOptions fast;
  fast.max_joint_speed = 1e3;  // the joints race as the arm straightens towards its rim
  const std::string e = error_of([&] { track_trajectory(state, too_far, rest_pose(), fast); });
  EXPECT_NE(e.find("t = "), std::string::npos) << e;
  EXPECT_NE(e.find("out of reach"), std::string::npos) << e;
  TrackOptions slow;
  slow.max_joint_speed = 0.01;
  const std::string j =
      error_of([&] { track_trajectory(state, push_path(1.0), rest_pose(), slow); });
  EXPECT_NE(j.find("jump"), std::string::npos) << j;
  TrackOptions bad;
  bad.rate_hz = 0;
  EXPECT_THROW(track_trajectory(state, push_path(1.0), rest_pose(), bad), Error);
}

TEST(InverseDynamics, StaticPoseNeedsExactlyGravityCompensation) {
  ArmState state(standard_arm());
  const JointVector poses[] = {rest_pose(), JointVector::Zero(), JointVector::Constant(0.3)};
  for (const JointVector& q : poses) {
    const JointVector tau = inverse_dynamics(state, q, JointVector::Zero(), JointVector::Zero());
    const JointVector g = gravity_torque(state, q);
    EXPECT_LT((tau - g).norm(), 1e-10);
    EXPECT_NEAR(tau[0], 0.0, 1e-12);  // yaw about the vertical carries no gravity load
  }
  // Known answer: arm horizontal, the shoulder holds the whole moving mass's moment.
  const mjModel& m = state.arm().model();
  const JointVector tau = gravity_torque(state, JointVector::Zero());
  const int link2 = m.jnt_bodyid[state.arm().joint_id(1)];
  const double moment = m.body_subtreemass[link2] * state.data().subtree_com[3 * link2];
  EXPECT_NEAR(tau[1], -m.opt.gravity[2] * moment, 1e-9);
  EXPECT_GT(tau[1], 1.0);  // positive: lifting
}

TEST(InverseDynamics, AccelerationTermIsTheMassMatrix) {
  ArmState state(standard_arm());
  const JointVector q = rest_pose();
  JointVector qddot;
  qddot << 0.5, -1.0, 2.0, 0.3, 1.0;
  const JointVector tau = inverse_dynamics(state, q, JointVector::Zero(), qddot);
  const JointVector g = gravity_torque(state, q);
  // M qddot from MuJoCo's full mass matrix.
  const mjModel& m = state.arm().model();
  std::vector<mjtNum> M(static_cast<std::size_t>(m.nv * m.nv));
  mj_fullM(&m, M.data(), state.data().qM);
  JointVector Mq = JointVector::Zero();
  for (int r = 0; r < kArmJoints; ++r) {
    for (int c = 0; c < kArmJoints; ++c) {
      const int at = (state.arm().dof_adr(r) * m.nv) + state.arm().dof_adr(c);
      Mq[r] += M[static_cast<std::size_t>(at)] * qddot[c];
    }
  }
  EXPECT_LT((tau - g - Mq).norm(), 1e-9);
}

TEST(Energy, TrapezoidOfAbsoluteTorque) {
  std::vector<JointVector> tau(11, JointVector::Zero());
  for (auto& t : tau) t << 2.0, -1.0, 0.0, 0.5, -0.5;
  const Energy e = energy(tau, 0.1);
  EXPECT_NEAR(e.per_joint[0], 2.0, 1e-12);
  EXPECT_NEAR(e.per_joint[1], 1.0, 1e-12);
  EXPECT_NEAR(e.total, 4.0, 1e-12);
  EXPECT_THROW(energy(tau, 0.0), Error);
}

TEST(Energy, PositiveAndLargerForFasterMovesWithoutGravity) {
  // Without gravity the torques are the dynamic ones alone: the integral of |tau| grows as the
  // move speeds up (acceleration ~ 1/T^2 over a time T). With gravity the holding torque dominates
  // (it integrates to ~ T), see the next test.
  ModelPtr m = copy_model(standard_arm().model());
  m->opt.gravity[2] = 0;
  ArmState state(Arm(std::shared_ptr<const mjModel>(m.release(), ModelDeleter{})));
  double previous = 0;
  for (double T : {4.0, 2.0, 1.0, 0.5}) {
    const TrackResult r = track_trajectory(state, push_path(T), rest_pose());
    const Energy e = energy(inverse_dynamics(state, r.joints), r.joints.dt);
    EXPECT_GT(e.total, 0.0);
    EXPECT_GT(e.total, previous) << "T = " << T;
    for (int k = 0; k < kArmJoints; ++k) EXPECT_GE(e.per_joint[k], 0.0);
    previous = e.total;
  }
}

TEST(Energy, SlowMoveApproachesTheQuasiStaticIntegral) {
  ArmState state(standard_arm());
  const TrackResult r = track_trajectory(state, push_path(8.0), rest_pose());
  const Energy e = energy(inverse_dynamics(state, r.joints), r.joints.dt);
  std::vector<JointVector> hold;
  for (const JointVector& q : r.joints.q) hold.push_back(gravity_torque(state, q));
  const Energy g = energy(hold, r.joints.dt);
  EXPECT_GT(e.total, 0.0);
  EXPECT_NEAR(e.total, g.total, 0.02 * g.total);
}

TEST(ServoCommands, StaticHoldIsTheSetpointPlusTorqueOverGain) {
  const Arm& arm = standard_arm();
  ArmState state(arm);
  JointTrajectory still = differentiate({rest_pose(), rest_pose(), rest_pose()}, 0.002);
  const auto tau = inverse_dynamics(state, still);
  const auto ctrl = servo_commands(arm, still, tau);
  for (int k = 0; k < kArmJoints; ++k) {
    const double kp = arm.model().actuator_gainprm[arm.actuator_id(k) * mjNGAIN];
    EXPECT_NEAR(ctrl[1][k], rest_pose()[k] + tau[1][k] / kp, 1e-12);
  }
  EXPECT_THROW(servo_commands(arm, still, {}), InternalError);  // a caller's bug, not bad input
}

}  // namespace
}  // namespace proprio::robot
