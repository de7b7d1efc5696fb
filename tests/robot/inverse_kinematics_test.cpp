#include "proprio/robot/inverse_kinematics.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "proprio/core/error.hpp"
#include "proprio/core/files.hpp"
#include "proprio/core/random.hpp"
#include "test_arm.hpp"

namespace proprio::robot {
namespace {

using testing::error_of;
using testing::standard_arm;
constexpr double kPi = std::numbers::pi;

/// Points in front of and beside the arm, from the table top up, that the arm can reach.
std::vector<Eigen::Vector3d> reachable_grid(const Arm& arm) {
  const ArmGeometry& g = arm.geometry();
  std::vector<Eigen::Vector3d> out;
  for (double x = -0.1; x <= 0.46; x += 0.04) {
    for (double y = -0.35; y <= 0.351; y += 0.07) {
      for (double z = 0.0; z <= 0.45; z += 0.05) {
        const Eigen::Vector3d p(x, y, z);
        const double r = p.head<2>().norm();
        if (r < g.base_radius + 0.02) continue;
        if (Eigen::Vector2d(r, z - g.shoulder.y()).norm() > g.reach - 0.01) continue;
        out.push_back(p);
      }
    }
  }
  return out;
}

JointVector rest_pose() {
  JointVector q;
  q << 0.0, 0.8, -1.4, -0.9, 0.0;
  return q;
}

TEST(InverseKinematics, AnalyticRoundTripOverTheWorkspace) {
  ArmState state(standard_arm());
  const auto grid = reachable_grid(state.arm());
  ASSERT_GT(grid.size(), 300u);
  IkOptions options;
  options.method = IkMethod::analytic;
  int at_requested_pitch = 0;
  for (const Eigen::Vector3d& p : grid) {
    const IkResult r = solve_ik(state, p, rest_pose(), options);
    EXPECT_TRUE(r.q.allFinite());
    EXPECT_LT((state.ee_position(r.q) - p).norm(), 1e-9) << p.transpose();
    EXPECT_TRUE(state.arm().within_limits(r.q, 0.0)) << p.transpose() << " -> " << r.q.transpose();
    EXPECT_EQ(r.summary.method, IkMethod::analytic);
    const double radial = p.head<2>().norm();
    if (radial >= 0.12 && radial <= 0.30 && p.z() <= 0.1) {
      // The pushing workspace: here the pusher can point straight down.
      EXPECT_TRUE(r.summary.pitch_met) << p.transpose();
      ++at_requested_pitch;
    }
  }
  EXPECT_GT(at_requested_pitch, 30);
}

TEST(InverseKinematics, PointsDownOnTheTableAndUsesTheConvexElbow) {
  ArmState state(standard_arm());
  for (double x : {0.12, 0.2, 0.28}) {
    const Eigen::Vector3d p(x, 0.05, 0.02);
    const IkResult r = solve_ik(state, p, rest_pose());
    EXPECT_TRUE(r.summary.pitch_met);
    EXPECT_NEAR(r.pitch, -kPi / 2, 1e-9);
    EXPECT_TRUE(r.summary.elbow_up);
    // Elbow up: the elbow lies above the line from the shoulder to the wrist (wrist above ee).
    const auto& g = state.arm().geometry();
    const double r_el = g.upper_arm * std::cos(r.q[1]);
    const double z_el = g.shoulder.y() + g.upper_arm * std::sin(r.q[1]);
    const double r_wr = p.head<2>().norm();
    const double z_wr = p.z() + g.hand;
    const double line_z = g.shoulder.y() + (z_wr - g.shoulder.y()) * r_el / r_wr;
    EXPECT_GT(z_el, line_z);
    EXPECT_NEAR(r.q[0], std::atan2(0.05, x), 1e-12);
  }
}

TEST(InverseKinematics, StrictPitchIsMetOrRefused) {
  ArmState state(standard_arm());
  IkOptions options;
  options.strict_pitch = true;
  options.pitch = -0.3;
  const IkResult r = solve_ik(state, {0.35, -0.1, 0.1}, rest_pose(), options);
  EXPECT_NEAR(r.pitch, -0.3, 1e-9);
  // At the far rim only a level hand reaches: pointing down is impossible there.
  options.pitch = -kPi / 2;
  const std::string e = error_of([&] { solve_ik(state, {0.50, 0.0, 0.2}, rest_pose(), options); });
  EXPECT_NE(e.find("pitch"), std::string::npos) << e;
  options.strict_pitch = false;
  const IkResult loose = solve_ik(state, {0.50, 0.0, 0.2}, rest_pose(), options);
  EXPECT_FALSE(loose.summary.pitch_met);
  EXPECT_LT(loose.summary.residual, 1e-9);
}

TEST(InverseKinematics, NumericalAgreesWithAnalytic) {
  ArmState state(standard_arm());
  const auto grid = reachable_grid(state.arm());
  core::Rng rng(11);
  IkOptions analytic;
  analytic.method = IkMethod::analytic;
  IkOptions numerical;
  numerical.method = IkMethod::numerical;
  int compared = 0;
  for (std::size_t i = 0; i < grid.size(); i += 7) {
    const IkResult a = solve_ik(state, grid[i], rest_pose(), analytic);
    JointVector start = a.q;
    for (int k = 0; k < kArmJoints; ++k) start[k] += rng.uniform(-0.05, 0.05);
    start = state.arm().clamp(start);
    const IkResult n = solve_ik(state, grid[i], start, numerical);
    EXPECT_LT((state.ee_position(n.q) - grid[i]).norm(), 1e-9) << grid[i].transpose();
    EXPECT_TRUE(state.arm().within_limits(n.q, 0.0));
    EXPECT_EQ(n.summary.method, IkMethod::numerical);
    if (a.summary.pitch_met) {
      // Same position and pitch, nearby start: the same joints (j5 stays where it started).
      EXPECT_LT((n.q.head<4>() - a.q.head<4>()).norm(), 1e-6) << grid[i].transpose() << "\n"
                                                              << n.q.transpose() << "\n"
                                                              << a.q.transpose();
      EXPECT_NEAR(n.q[4], start[4], 1e-15);
      ++compared;
    }
  }
  EXPECT_GT(compared, 20);
}

TEST(InverseKinematics, NumericalFromAFarStartReachesTheTarget) {
  ArmState state(standard_arm());
  IkOptions numerical;
  numerical.method = IkMethod::numerical;
  for (const Eigen::Vector3d& p : {Eigen::Vector3d(0.3, 0.2, 0.05), Eigen::Vector3d(0.1, -0.3, 0.3),
                                   Eigen::Vector3d(0.45, 0, 0.3)}) {
    const IkResult r = solve_ik(state, p, JointVector::Zero(), numerical);
    EXPECT_LT(r.summary.residual, 1e-9) << p.transpose() << ": " << r.summary.message;
    EXPECT_GT(r.summary.iterations, 0);
  }
}

TEST(InverseKinematics, UnreachableTargetsThrowWithTheReason) {
  ArmState state(standard_arm());
  for (const IkMethod method : {IkMethod::analytic, IkMethod::numerical}) {
    IkOptions o;
    o.method = method;
    const JointVector q0 = rest_pose();
    EXPECT_NE(error_of([&] {
                solve_ik(state, {0.9, 0.0, 0.2}, q0, o);
              }).find("out of reach"),
              std::string::npos);
    EXPECT_NE(error_of([&] {
                solve_ik(state, {0.3, 0.0, -0.01}, q0, o);
              }).find("below the table"),
              std::string::npos);
    EXPECT_NE(error_of([&] {
                solve_ik(state, {0.03, 0.02, 0.1}, q0, o);
              }).find("inside the arm's base"),
              std::string::npos);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    EXPECT_NE(error_of([&] {
                solve_ik(state, {0.3, nan, 0.1}, q0, o);
              }).find("not finite"),
              std::string::npos);
  }
  // Directly behind the base: yaw cannot turn there (+-169 deg) and the shoulder cannot lean back
  // far enough to reach over.
  const std::string behind = error_of([&] {
    solve_ik(state, {-0.45, 0.0, 0.05}, rest_pose(), IkOptions{});
  });
  EXPECT_NE(behind.find("joint limits"), std::string::npos) << behind;
  EXPECT_NE(behind.find("(-0.4500, 0.0000, 0.0500) m"), std::string::npos) << behind;
}

TEST(InverseKinematics, TargetOnTheYawAxisKeepsTheCurrentYaw) {
  ArmState state(standard_arm());
  JointVector start = rest_pose();
  start[0] = 0.7;
  const IkResult r = solve_ik(state, {0.0, 0.0, 0.45}, start);
  EXPECT_NEAR(r.q[0], 0.7, 1e-12);
  EXPECT_LT(r.summary.residual, 1e-9);
}

TEST(InverseKinematics, OptionsAreValidated) {
  ArmState state(standard_arm());
  IkOptions o;
  o.tolerance = 0;
  EXPECT_NE(error_of([&] {
              solve_ik(state, {0.3, 0, 0.1}, rest_pose(), o);
            }).find("tolerance"),
            std::string::npos);
  o = IkOptions{};
  o.max_iterations = 0;
  EXPECT_THROW(solve_ik(state, {0.3, 0, 0.1}, rest_pose(), o), Error);
}

/// The arm with its roll axis turned off the ee point: no analytic solution, numerical only.
Arm skewed_arm() {
  std::string xml = core::read_file(test::data_dir() / "models" / "arm.xml");
  const std::string from = "<joint name=\"j5\" axis=\"1 0 0\"";
  const auto at = xml.find(from);
  EXPECT_NE(at, std::string::npos);
  xml.replace(at, from.size(), "<joint name=\"j5\" axis=\"0 0 1\"");
  ModelPtr m = load_model_from_string(xml, "skewed_arm.xml");
  return Arm(std::shared_ptr<const mjModel>(m.release(), ModelDeleter{}), ArmNames{},
             "skewed_arm.xml");
}

TEST(InverseKinematics, ArmWithoutAnalyticStructureUsesTheNumericalSolver) {
  ArmState state(skewed_arm());
  EXPECT_FALSE(state.arm().geometry().analytic);
  EXPECT_NE(state.arm().geometry().why_not_analytic.find("j5"), std::string::npos);
  IkOptions o;
  o.method = IkMethod::analytic;
  EXPECT_NE(error_of([&] {
              solve_ik(state, {0.3, 0, 0.1}, rest_pose(), o);
            }).find("no analytic inverse kinematics"),
            std::string::npos);
  const IkResult r = solve_ik(state, {0.3, 0.1, 0.1}, rest_pose());
  EXPECT_EQ(r.summary.method, IkMethod::numerical);
  EXPECT_LT(r.summary.residual, 1e-9);
  // Without a reach bound the numerical solver itself reports the failure.
  const std::string far = error_of([&] { solve_ik(state, {1.2, 0, 0.2}, rest_pose()); });
  EXPECT_NE(far.find("was not reached by the numerical IK"), std::string::npos) << far;
}

}  // namespace
}  // namespace proprio::robot
