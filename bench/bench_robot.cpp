// Timings of the robot layer on the standalone arm (docs/results/robot.md):
// forward kinematics, Jacobian, analytic and numerical IK, tracking and inverse dynamics of a
// 1 s trajectory at 500 Hz.

#include <benchmark/benchmark.h>

#include <vector>

#include "proprio/core/data_dir.hpp"
#include "proprio/robot/arm.hpp"
#include "proprio/robot/dynamics.hpp"
#include "proprio/robot/inverse_kinematics.hpp"
#include "proprio/robot/joint_tracking.hpp"
#include "proprio/robot/trajectory.hpp"

namespace {

using proprio::robot::Arm;
using proprio::robot::ArmState;
using proprio::robot::JointVector;

const Arm& arm() {
  static const Arm a = Arm::load(proprio::core::data_directory() / "models" / "arm_standalone.xml");
  return a;
}

JointVector rest_pose() {
  JointVector q;
  q << 0.0, 0.8, -1.4, -0.9, 0.0;
  return q;
}

/// Targets over the pushing workspace, table level to 15 cm up.
std::vector<Eigen::Vector3d> targets() {
  std::vector<Eigen::Vector3d> out;
  for (double x = 0.12; x <= 0.30; x += 0.03) {
    for (double y = -0.2; y <= 0.2; y += 0.05) {
      for (double z = 0.0; z <= 0.15; z += 0.05) out.emplace_back(x, y, z);
    }
  }
  return out;
}

std::vector<JointVector> configurations() {
  ArmState state(arm());
  std::vector<JointVector> out;
  for (const auto& p : targets()) out.push_back(proprio::robot::solve_ik(state, p, rest_pose()).q);
  return out;
}

void BM_ForwardKinematics(benchmark::State& bs) {
  ArmState state(arm());
  const auto qs = configurations();
  std::size_t i = 0;
  for (auto _ : bs) {
    benchmark::DoNotOptimize(state.ee_position(qs[i++ % qs.size()]));
  }
}
BENCHMARK(BM_ForwardKinematics);

void BM_Jacobian(benchmark::State& bs) {
  ArmState state(arm());
  const auto qs = configurations();
  std::size_t i = 0;
  for (auto _ : bs) {
    benchmark::DoNotOptimize(state.jacobian(qs[i++ % qs.size()]));
  }
}
BENCHMARK(BM_Jacobian);

void ik_bench(benchmark::State& bs, proprio::robot::IkMethod method, bool near_start) {
  ArmState state(arm());
  const auto ps = targets();
  const auto qs = configurations();
  proprio::robot::IkOptions options;
  options.method = method;
  std::size_t i = 0;
  long iterations = 0;
  for (auto _ : bs) {
    const std::size_t k = i++ % ps.size();
    // Near start: the previous control sample's solution, 1 mm away (tracking).
    JointVector start = rest_pose();
    Eigen::Vector3d p = ps[k];
    if (near_start) {
      start = qs[k];
      p += Eigen::Vector3d(0.001, 0.0, 0.0);
    }
    const auto r = proprio::robot::solve_ik(state, p, start, options);
    iterations += r.summary.iterations;
    benchmark::DoNotOptimize(r.q);
  }
  bs.counters["iterations"] =
      benchmark::Counter(static_cast<double>(iterations), benchmark::Counter::kAvgIterations);
}

void BM_AnalyticIK(benchmark::State& bs) {
  ik_bench(bs, proprio::robot::IkMethod::analytic, false);
}
BENCHMARK(BM_AnalyticIK);

void BM_NumericalIK_FromRestPose(benchmark::State& bs) {
  ik_bench(bs, proprio::robot::IkMethod::numerical, false);
}
BENCHMARK(BM_NumericalIK_FromRestPose);

void BM_NumericalIK_From1mmAway(benchmark::State& bs) {
  ik_bench(bs, proprio::robot::IkMethod::numerical, true);
}
BENCHMARK(BM_NumericalIK_From1mmAway);

proprio::robot::BezierTrajectory one_second_push() {
  return proprio::robot::straight_move({0.18, -0.10, 0.02}, {0.30, 0.06, 0.02}, 0.2);
}

void BM_TrackTrajectory_1s_500Hz(benchmark::State& bs) {
  ArmState state(arm());
  const auto path = one_second_push();
  for (auto _ : bs) {
    benchmark::DoNotOptimize(proprio::robot::track_trajectory(state, path, rest_pose()));
  }
}
BENCHMARK(BM_TrackTrajectory_1s_500Hz)->Unit(benchmark::kMillisecond);

void BM_InverseDynamics_1s_500Hz(benchmark::State& bs) {
  ArmState state(arm());
  const auto plan = proprio::robot::track_trajectory(state, one_second_push(), rest_pose());
  const double joules =
      proprio::robot::energy(proprio::robot::inverse_dynamics(state, plan.joints), plan.joints.dt)
          .total;
  for (auto _ : bs) {
    benchmark::DoNotOptimize(proprio::robot::inverse_dynamics(state, plan.joints));
  }
  bs.counters["samples"] = static_cast<double>(plan.joints.size());
  bs.counters["energy_Nms"] = joules;
}
BENCHMARK(BM_InverseDynamics_1s_500Hz)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
