// The position-controlled arm in MuJoCo follows a commanded push path.

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>

#include "proprio/robot/dynamics.hpp"
#include "proprio/robot/joint_tracking.hpp"
#include "test_arm.hpp"

namespace proprio::robot {
namespace {

using testing::standard_arm;

struct SimRun {
  double max_error = 0;    ///< m, simulated ee vs commanded path
  double final_error = 0;  ///< m, after the move has settled
};

/// Steps the arm from rest at the path's first configuration, sending ctrl[i] at step i.
SimRun simulate(const Arm& arm, const TrackResult& plan, const std::vector<JointVector>& ctrl) {
  const mjModel& m = arm.model();
  DataPtr d = make_data(m);
  for (int k = 0; k < kArmJoints; ++k) d->qpos[arm.qpos_adr(k)] = plan.joints.q.front()[k];
  mj_forward(&m, d.get());
  SimRun run;
  const int ee = arm.ee_site();
  auto ee_error = [&](std::size_t i) {
    return (Eigen::Vector3d(d->site_xpos[3 * ee], d->site_xpos[3 * ee + 1],
                            d->site_xpos[3 * ee + 2]) -
            plan.path[std::min(i, plan.path.size() - 1)].position)
        .norm();
  };
  const std::size_t n = plan.path.size();
  for (std::size_t i = 0; i + 1 < n + 250; ++i) {
    const JointVector& u = ctrl[std::min(i, n - 1)];
    for (int k = 0; k < kArmJoints; ++k) d->ctrl[arm.actuator_id(k)] = u[k];
    mj_step(&m, d.get());  // state now at t_{i+1}
    mj_kinematics(&m, d.get());
    run.max_error = std::max(run.max_error, ee_error(i + 1));
  }
  run.final_error = ee_error(n);
  testing::expect_no_warnings(*d);
  return run;
}

TEST(Simulation, PositionServosTrackAStraightPushWithinMillimetres) {
  const Arm& arm = standard_arm();
  ArmState state(arm);
  const double step = arm.model().opt.timestep;
  // 20 cm across the table at 0.1 m/s (2 s), pusher down, 2 cm above the table.
  const BezierTrajectory path = straight_move({0.18, -0.10, 0.02}, {0.30, 0.06, 0.02}, 0.1);
  TrackOptions options;
  options.rate_hz = 1.0 / step;
  const TrackResult plan = track_trajectory(state, path, arm.clamp(JointVector::Zero()), options);
  ASSERT_NEAR(plan.joints.dt, step, 1e-9);

  // Plain setpoints: the servo lags (damping) and sags (gravity) by a little.
  const SimRun plain = simulate(arm, plan, plan.joints.q);
  EXPECT_LT(plain.max_error, 3e-3);
  EXPECT_LT(plain.final_error, 1.5e-3);
  // Inverse dynamics fed forward through the servos: near exact.
  const auto ctrl = servo_commands(arm, plan.joints, inverse_dynamics(state, plan.joints));
  const SimRun ff = simulate(arm, plan, ctrl);
  EXPECT_LT(ff.max_error, 2e-4);
  EXPECT_LT(ff.final_error, 1e-4);
  std::printf(
      "ee tracking error: setpoints max %.2f mm (final %.2f mm), feed-forward max %.3f mm\n",
      plain.max_error * 1e3, plain.final_error * 1e3, ff.max_error * 1e3);
}

}  // namespace
}  // namespace proprio::robot
