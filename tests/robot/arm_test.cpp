#include "proprio/robot/arm.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>

#include "proprio/core/error.hpp"
#include "proprio/core/random.hpp"
#include "proprio/robot/mujoco_ptr.hpp"
#include "test_arm.hpp"

namespace proprio::robot {
namespace {

using testing::error_of;
using testing::standard_arm;
constexpr double kPi = std::numbers::pi;

TEST(MujocoPtr, LoadModelNamesTheFileOnError) {
  const std::string missing = error_of([] { load_model("/nonexistent/arm.xml"); });
  EXPECT_NE(missing.find("/nonexistent/arm.xml"), std::string::npos) << missing;

  const auto bad = std::filesystem::temp_directory_path() / "proprio_robot_bad_model.xml";
  std::ofstream(bad) << "<mujoco><worldbody><body><geom type='sphere'/></body></worldbody>";
  const std::string broken = error_of([&] { load_model(bad); });
  EXPECT_NE(broken.find(bad.string()), std::string::npos) << broken;
  EXPECT_NE(broken.find("MuJoCo"), std::string::npos) << broken;
  std::filesystem::remove(bad);
}

TEST(MujocoPtr, LoadFromStringAndCopy) {
  ModelPtr m = load_model_from_string(
      "<mujoco><worldbody><body><freejoint/><geom size='0.1'/></body></worldbody></mujoco>");
  ASSERT_TRUE(m);
  EXPECT_EQ(m->nq, 7);
  ModelPtr c = copy_model(*m);
  EXPECT_EQ(c->nq, 7);
  DataPtr d = make_data(*c);
  mj_step(c.get(), d.get());
  EXPECT_TRUE(warnings(*d).empty());
  EXPECT_NE(error_of([] {
              load_model_from_string("<mujoco><bogus/></mujoco>", "scene.xml");
            }).find("scene.xml"),
            std::string::npos);
}

TEST(Arm, ReadsNamesLimitsAndGeometry) {
  const Arm& arm = standard_arm();
  EXPECT_TRUE(arm.has_gripper());
  EXPECT_GE(arm.marker_geom(), 0);
  EXPECT_EQ(arm.model().nu, 7);
  const ArmGeometry& g = arm.geometry();
  ASSERT_TRUE(g.analytic) << g.why_not_analytic;
  EXPECT_NEAR(g.shoulder.x(), 0.0, 1e-12);
  EXPECT_NEAR(g.shoulder.y(), 0.2015, 1e-12);
  EXPECT_NEAR(g.upper_arm, 0.190, 1e-12);
  EXPECT_NEAR(g.forearm, 0.139, 1e-12);
  EXPECT_NEAR(g.hand, 0.190, 1e-12);
  EXPECT_NEAR(g.reach, 0.519, 1e-12);
  EXPECT_NEAR(g.base_radius, 0.075, 1e-12);
  EXPECT_NEAR(g.base_top, 0.2015, 1e-12);
  for (double s : g.pitch_sign) EXPECT_EQ(s, 1.0);
  EXPECT_EQ(g.yaw_sign, 1.0);
  EXPECT_NEAR(g.yaw_zero, 0.0, 1e-12);
  for (int k = 0; k < kArmJoints; ++k) EXPECT_LT(arm.lower()[k], arm.upper()[k]);
  EXPECT_NEAR(arm.upper()[1], 135.0 * kPi / 180, 1e-12);  // MJCF ranges are in degrees
}

TEST(Arm, MissingPartsAreErrorsNamingThePart) {
  ArmNames names;
  names.joints[2] = "elbow";
  const std::string e = error_of([&] { Arm::load(testing::arm_model_path(), names); });
  EXPECT_NE(e.find("'elbow'"), std::string::npos) << e;
  EXPECT_NE(e.find("arm_standalone.xml"), std::string::npos) << e;

  ArmNames swapped;
  swapped.actuators[0] = "a2";
  const std::string e2 = error_of([&] { Arm::load(testing::arm_model_path(), swapped); });
  EXPECT_NE(e2.find("does not drive joint 'j1'"), std::string::npos) << e2;
}

TEST(Arm, IncludedInAnotherSceneKeepsItsGeometry) {
  // A scene with its own defaults and a free object, including arm.xml as the simulator does
  // (MuJoCo 2.2 resolves <include> relative to the including file).
  const auto dir = std::filesystem::temp_directory_path() / "proprio_robot_scene_test";
  std::filesystem::create_directories(dir);
  std::filesystem::copy_file(test::data_dir() / "models" / "arm.xml", dir / "arm.xml",
                             std::filesystem::copy_options::overwrite_existing);
  std::ofstream(dir / "scene.xml")
      << "<mujoco><default><geom rgba='1 1 1 1'/></default><include file='arm.xml'/>"
      << "<worldbody><geom type='plane' size='1 1 0.1'/>"
      << "<body pos='0.3 0 0.03'><freejoint/><geom type='box' size='0.03 0.03 0.03' mass='0.1'/>"
      << "</body></worldbody></mujoco>";
  const Arm arm = Arm::load(dir / "scene.xml");
  std::filesystem::remove_all(dir);
  EXPECT_TRUE(arm.geometry().analytic);
  EXPECT_NEAR(arm.geometry().reach, 0.519, 1e-12);
  ArmState state(arm);
  EXPECT_NEAR((state.ee_position(JointVector::Zero()) - Eigen::Vector3d(0.519, 0, 0.2015)).norm(),
              0.0, 1e-12);
}

TEST(ForwardKinematics, KnownConfigurations) {
  ArmState state(standard_arm());
  JointVector q = JointVector::Zero();
  EXPECT_LT((state.ee_position(q) - Eigen::Vector3d(0.519, 0, 0.2015)).norm(), 1e-12);
  q << kPi / 2, kPi / 2, 0, 0, 1.0;  // yawed left, arm straight up; roll moves nothing
  EXPECT_LT((state.ee_position(q) - Eigen::Vector3d(0, 0, 0.2015 + 0.519)).norm(), 1e-12);
  q << kPi / 2, 0, -kPi / 2, 0, 0;  // upper arm forward (= +y), forearm and hand down
  EXPECT_LT((state.ee_position(q) - Eigen::Vector3d(0, 0.19, 0.2015 - 0.329)).norm(), 1e-12);
  const EePose pose = state.ee_pose(q);
  EXPECT_NEAR(pose.pitch(), -kPi / 2, 1e-12);
  EXPECT_NEAR(pose.rotation.determinant(), 1.0, 1e-12);
}

TEST(ForwardKinematics, JacobianMatchesFiniteDifferences) {
  const Arm& arm = standard_arm();
  ArmState state(arm);
  core::Rng rng(7);
  for (int trial = 0; trial < 20; ++trial) {
    JointVector q;
    for (int k = 0; k < kArmJoints; ++k) {
      q[k] = rng.uniform(arm.lower()[k] + 0.1, arm.upper()[k] - 0.1);
    }
    const PositionJacobian J = state.jacobian(q);
    const PositionJacobian Jr = state.rotation_jacobian(q);
    PositionJacobian fd;
    PositionJacobian fd_rot;
    constexpr double h = 1e-6;
    for (int k = 0; k < kArmJoints; ++k) {
      JointVector qp = q;
      JointVector qm = q;
      qp[k] += h;
      qm[k] -= h;
      const EePose a = state.ee_pose(qp);
      const EePose b = state.ee_pose(qm);
      fd.col(k) = (a.position - b.position) / (2 * h);
      // Angular velocity from dR/dq R^T (skew-symmetric).
      const Eigen::Matrix3d W =
          (a.rotation - b.rotation) / (2 * h) * state.ee_pose(q).rotation.transpose();
      fd_rot.col(k) = Eigen::Vector3d(W(2, 1), W(0, 2), W(1, 0));
    }
    EXPECT_LT((J - fd).cwiseAbs().maxCoeff(), 1e-8) << "trial " << trial;
    EXPECT_LT((Jr - fd_rot).cwiseAbs().maxCoeff(), 1e-8) << "trial " << trial;
    EXPECT_LT(J.col(4).norm(), 1e-12);  // the roll does not move the ee point
  }
}

TEST(ArmModel, SimulatesWithoutWarningsAndHoldsItsPose) {
  const Arm& arm = standard_arm();
  DataPtr d = make_data(arm.model());
  JointVector q;
  q << 0.3, 0.6, -1.2, -0.9, 0.4;
  for (int k = 0; k < kArmJoints; ++k) {
    d->qpos[arm.qpos_adr(k)] = q[k];
    d->ctrl[arm.actuator_id(k)] = q[k];
  }
  for (int i = 0; i < 1000; ++i) mj_step(&arm.model(), d.get());
  testing::expect_no_warnings(*d);
  for (int k = 0; k < kArmJoints; ++k) {
    // Gravity sag of a position servo: tau / kp, well under a milliradian.
    EXPECT_NEAR(d->qpos[arm.qpos_adr(k)], q[k], 2e-3) << "joint " << k + 1;
  }
}

}  // namespace
}  // namespace proprio::robot

namespace proprio::robot {
namespace {

TEST(ArmModel, GripperOpensSymmetricallyWithoutWarnings) {
  const Arm& arm = testing::standard_arm();
  ASSERT_TRUE(arm.has_gripper());
  const mjModel& m = arm.model();
  DataPtr d = make_data(m);
  for (int k = 0; k < kArmJoints; ++k) d->ctrl[arm.actuator_id(k)] = 0.0;
  for (int a : arm.gripper_actuators()) d->ctrl[a] = 0.02;
  for (int i = 0; i < 500; ++i) mj_step(&m, d.get());
  testing::expect_no_warnings(*d);
  const int left = m.jnt_qposadr[arm.gripper_joints()[0]];
  const int right = m.jnt_qposadr[arm.gripper_joints()[1]];
  EXPECT_NEAR(d->qpos[left], 0.02, 1e-3);
  EXPECT_NEAR(d->qpos[right], 0.02, 1e-3);
  // The fingers move apart, mirror images about the pusher.
  const int lb = m.jnt_bodyid[arm.gripper_joints()[0]];
  const int rb = m.jnt_bodyid[arm.gripper_joints()[1]];
  const Eigen::Vector3d pl(d->xpos[3 * lb], d->xpos[3 * lb + 1], d->xpos[3 * lb + 2]);
  const Eigen::Vector3d pr(d->xpos[3 * rb], d->xpos[3 * rb + 1], d->xpos[3 * rb + 2]);
  EXPECT_NEAR((pl - pr).norm(), 2 * (0.02 + 0.02), 2e-3);
}

}  // namespace
}  // namespace proprio::robot
