// The interception planner (eqs 3.44-3.49): Gauss-Newton from a sparse sample, the priors, the
// choice of time against noise, and infeasible targets.
#include "proprio/planning/interception_planner.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "planning_test_support.hpp"

namespace proprio::planning {
namespace {
using testing::error_of;
using testing::exact_measurements;
using testing::grid_model;
using testing::internal_error_of;

constexpr double kDt = 0.04;

// A target that crosses the workspace 1.5 s after the plan (at frame 19).
TargetMotion crossing_target() {
  const GridSpec g;
  const Eigen::Vector3d crossing = g.start + Eigen::Vector3d(0.05, 0.12, 0);
  const Eigen::Vector3d v(0.08, 0.03, 0);
  return {crossing - v * (19 * kDt + 1.5), v};
}

TargetFilter filter_for(const TargetMotion& target, TransitionModel model) {
  FilterOptions o;
  o.transition = model;
  return TargetFilter(exact_measurements(target, 20, kDt), o);
}

TEST(Planner, GaussNewtonConvergesOnTheTargetsPath) {
  const TargetMotion target = crossing_target();
  const TargetFilter f = filter_for(target, TransitionModel::kLearned);
  const double t_now = f.estimate().t;
  const InterceptionPlan p = plan_interception(f, *grid_model(), t_now);
  ASSERT_TRUE(p.feasible) << p.why_not;
  EXPECT_LE(p.summary.final_objective, p.summary.initial_objective);
  EXPECT_GT(p.summary.iterations, 0);
  // The end point meets the (exactly predicted) target at the interception time.
  EXPECT_LT((p.end_point - target.position(p.t_intercept)).head<2>().norm(), 2e-4);
  EXPECT_LT((p.predicted_target - target.position(p.t_intercept)).norm(), 1e-6);
  EXPECT_GE(p.t_intercept, t_now + 1.0 - 1e-9);
  EXPECT_LE(p.t_intercept, t_now + 1.0 + 1.5 + 1e-9);
  EXPECT_NEAR(p.t_start, p.t_intercept - 1.0, 1e-12);
  // Its time is recorded (how fast is bench/'s to measure, not a test's to assert).
  EXPECT_TRUE(std::isfinite(p.summary.seconds));
  EXPECT_GE(p.summary.seconds, 0.0);
}

TEST(Planner, GaussNewtonFindsTheDenseSearchMinimum) {
  // Brute force over the interception time (theta and l aimed at the target, every gamma on a
  // fine grid): the planner's objective is at most the dense minimum.
  const TargetMotion target = crossing_target();
  const TargetFilter f = filter_for(target, TransitionModel::kConstantVelocity);
  const double t_now = f.estimate().t;
  const InterceptionPlan p = plan_interception(f, *grid_model(), t_now);
  ASSERT_TRUE(p.feasible) << p.why_not;
  PlannerOptions dense;
  dense.time_samples = 400;
  dense.max_iterations = 0;  // the sample alone
  const InterceptionPlan q = plan_interception(f, *grid_model(), t_now, dense);
  EXPECT_LE(p.objective, q.objective + 1e-3);
}

TEST(Planner, PriorsChangeTheArmsCovariance) {
  const TargetFilter f = filter_for(crossing_target(), TransitionModel::kConstantVelocity);
  PlannerOptions o;
  o.mode = PriorMode::kEnergy;
  const InterceptionPlan e = plan_interception(f, *grid_model(), f.estimate().t, o);
  ASSERT_TRUE(e.feasible);
  EXPECT_NEAR(e.arm_sigma, 0.01, 1e-12);  // energy only: the thesis's 0.01
  o.mode = PriorMode::kPrecision;
  const InterceptionPlan pr = plan_interception(f, *grid_model(), f.estimate().t, o);
  ASSERT_TRUE(pr.feasible);
  EXPECT_NEAR(pr.arm_sigma * pr.arm_sigma,
              grid_model()->arm_variance({pr.psi.theta, pr.psi.length, pr.psi.gamma}), 1e-15);
  EXPECT_EQ(prior_mode_from_string("precision"), PriorMode::kPrecision);
  EXPECT_NE(error_of([] { prior_mode_from_string("speed"); }).find("unknown prior"),
            std::string::npos);
}

TEST(Planner, MoreNoiseMeansEarlierInterception) {
  // The same target, measured with growing noise: the mean chosen time moves earlier (Fig 3-11).
  const InterceptionSimulator& sim = testing::simulator();
  TrialOptions o;
  o.filter.transition = TransitionModel::kConstantVelocity;
  const double t_plan = sim.plan_time(o);
  const TargetMotion target = crossing_target();
  auto mean_time = [&](double noise) {
    o.noise_cm = noise;
    double sum = 0;
    int n = 0;
    for (std::uint64_t seed = 1; seed <= 8; ++seed) {
      const InterceptionPlan p = sim.first_plan(target, o, seed);
      if (!p.feasible) continue;
      sum += p.t_intercept - t_plan;
      ++n;
    }
    EXPECT_GT(n, 4);
    return sum / n;
  };
  const double quiet = mean_time(0.0), noisy = mean_time(2.0);
  EXPECT_LT(noisy, quiet - 0.05) << "quiet " << quiet << " s, noisy " << noisy << " s";
}

TEST(Planner, UnreachableTargetIsAClearInfeasiblePlan) {
  // Far away and moving away: never within reach.
  const TargetMotion away{{1.5, 0.8, 0.05}, {0.1, 0.1, 0}};
  const TargetFilter f = filter_for(away, TransitionModel::kLearned);
  const InterceptionPlan p = plan_interception(f, *grid_model(), f.estimate().t);
  EXPECT_FALSE(p.feasible);
  EXPECT_NE(p.why_not.find("cannot be reached in time"), std::string::npos) << p.why_not;
  EXPECT_TRUE(p.end_point.allFinite() && std::isfinite(p.t_intercept) &&
              std::isfinite(p.objective));
}

TEST(Planner, TargetOffThePlaneIsInfeasible) {
  TargetMotion high = crossing_target();
  high.start.z() += 0.3;
  const TargetFilter f = filter_for(high, TransitionModel::kLearned);
  const InterceptionPlan p = plan_interception(f, *grid_model(), f.estimate().t);
  EXPECT_FALSE(p.feasible);
  EXPECT_NE(p.why_not.find("off the arm's plane"), std::string::npos) << p.why_not;
}

TEST(Planner, LatestTimeAndBadOptions) {
  const TargetFilter f = filter_for(crossing_target(), TransitionModel::kLearned);
  const double t = f.estimate().t;
  const InterceptionPlan late = plan_interception(f, *grid_model(), t, {}, t + 0.5);
  EXPECT_FALSE(late.feasible);
  EXPECT_NE(late.why_not.find("too late"), std::string::npos);
  const InterceptionPlan capped = plan_interception(f, *grid_model(), t, {}, t + 1.2);
  EXPECT_LE(capped.t_intercept, t + 1.2 + 1e-12);
  EXPECT_NE(
      internal_error_of([&] { plan_interception(f, *grid_model(), t - 1.0); }).find("plan time"),
      std::string::npos);
  PlannerOptions o;
  o.window = -1;
  EXPECT_NE(error_of([&] { plan_interception(f, *grid_model(), t, o); }).find("window"),
            std::string::npos);
}

TEST(Planner, TimeQuantumPutsTheInterceptionOnTheControlGrid) {
  const TargetFilter f = filter_for(crossing_target(), TransitionModel::kLearned);
  PlannerOptions o;
  o.time_quantum = 0.002;
  const InterceptionPlan p = plan_interception(f, *grid_model(), f.estimate().t, o);
  ASSERT_TRUE(p.feasible);
  const double k = p.t_intercept / 0.002;
  EXPECT_NEAR(k, std::round(k), 1e-6);
}

}  // namespace
}  // namespace proprio::planning
