// Interception trials executed in MuJoCo: the no-noise miss, determinism by seed, re-planning,
// and bad input.
#include "proprio/planning/interception_trial.hpp"

#include <gtest/gtest.h>

#include "planning_test_support.hpp"
#include "proprio/robot/mujoco_ptr.hpp"

namespace proprio::planning {
namespace {
using testing::error_of;
using testing::simulator;

TEST(Trial, NoNoiseTrialsMissByLessThanTwoAndAHalfMillimetres) {
  for (TransitionModel model : {TransitionModel::kLearned, TransitionModel::kConstantVelocity}) {
    ExperimentOptions o;
    o.trials = 4;
    o.trial.filter.transition = model;
    const ExperimentResult r = run_experiment(simulator(), o);
    EXPECT_EQ(r.summary.executed, 4) << to_string(model);
    for (const TrialResult& t : r.trials) {
      ASSERT_TRUE(t.executed) << t.why_not;
      EXPECT_LT(t.miss, 2.5e-3) << to_string(model);
      EXPECT_TRUE(t.mujoco_warnings.empty());
      // The arm reached its aim; the miss is the aim's error.
      EXPECT_LT((t.ee_at - t.aim).norm(), 1e-4);
    }
    EXPECT_LT(r.summary.mean_miss, 2.5e-3);
    EXPECT_GT(r.summary.mean_plan_ms, 0);
  }
}

TEST(Trial, SameSeedSameResultsOtherSeedOtherTargets) {
  ExperimentOptions o;
  o.trials = 3;
  o.trial.noise_cm = 1.0;
  const ExperimentResult a = run_experiment(simulator(), o);
  const ExperimentResult b = run_experiment(simulator(), o);
  for (std::size_t k = 0; k < a.trials.size(); ++k) {
    EXPECT_EQ(a.trials[k].executed, b.trials[k].executed);
    EXPECT_EQ(a.trials[k].miss, b.trials[k].miss);
    EXPECT_EQ(a.trials[k].t_intercept, b.trials[k].t_intercept);
    EXPECT_EQ(a.trials[k].target.start, b.trials[k].target.start);
  }
  o.seed = 2;
  const ExperimentResult c = run_experiment(simulator(), o);
  EXPECT_NE(a.trials[0].target.start, c.trials[0].target.start);
}

TEST(Trial, FirstPlanAloneMatchesTheTrialsFirstPlan) {
  TrialOptions o;
  o.noise_cm = 0.8;
  core::Rng rng(4);
  const TargetMotion target =
      random_target(simulator().model().grid(), simulator().plan_time(o), o.scenario, rng);
  const TrialResult t = simulator().run(target, o, 99);
  const InterceptionPlan p = simulator().first_plan(target, o, 99);
  EXPECT_EQ(p.feasible, t.first_plan.feasible);
  EXPECT_EQ(p.t_intercept, t.first_plan.t_intercept);
  EXPECT_EQ(p.end_point, t.first_plan.end_point);
}

TEST(Trial, ReplanningWithVisualFeedbackReducesTheMiss) {
  ExperimentOptions o;
  o.trials = 5;
  o.seed = 3;
  o.trial.noise_cm = 1.0;
  o.trial.filter.transition = TransitionModel::kConstantVelocity;
  const ExperimentResult open = run_experiment(simulator(), o);
  o.trial.replan = true;
  const ExperimentResult closed = run_experiment(simulator(), o);
  ASSERT_EQ(open.summary.executed, 5);
  ASSERT_EQ(closed.summary.executed, 5);
  EXPECT_LT(closed.summary.mean_miss, open.summary.mean_miss);
  EXPECT_GT(closed.summary.mean_reaims, 1);
  EXPECT_LT(closed.summary.mean_predicted_sigma, open.summary.mean_predicted_sigma);
}

TEST(Trial, RecordsWhatTheFiguresNeed) {
  TrialOptions o;
  o.noise_cm = 0.5;
  o.record = true;
  core::Rng rng(1);
  const TargetMotion target =
      random_target(simulator().model().grid(), simulator().plan_time(o), o.scenario, rng);
  const TrialResult t = simulator().run(target, o, 5);
  ASSERT_TRUE(t.executed) << t.why_not;
  EXPECT_GE(t.record.measurements.size(), 20u);
  EXPECT_FALSE(t.record.forecast.empty());
  EXPECT_EQ(t.record.executed.size(), t.record.commanded.size());
  EXPECT_EQ(t.record.aims.size(), 1u);
}

TEST(Trial, UnseenTargetIsTooFewMeasurements) {
  const TargetMotion unseen{{3.0, 0.0, 0.05}, {0.0, 0.1, 0}};  // behind the cameras
  const TrialResult t = simulator().run(unseen, TrialOptions{}, 1);
  EXPECT_FALSE(t.executed);
  EXPECT_NE(t.why_not.find("needs at least 11 measurements"), std::string::npos) << t.why_not;
}

TEST(Trial, UnreachableTargetIsReportedNotExecuted) {
  const TargetMotion away{{0.6, 0.3, 0.05}, {0.05, 0.05, 0}};  // seen, but moving away
  const TrialResult t = simulator().run(away, TrialOptions{}, 1);
  EXPECT_FALSE(t.executed);
  EXPECT_NE(t.why_not.find("cannot be reached"), std::string::npos) << t.why_not;
  const ExperimentSummary s = summarise({t});
  EXPECT_EQ(s.executed, 0);
  EXPECT_EQ(s.not_planned, 1);
  EXPECT_EQ(s.mean_miss, 0);  // no NaN from an empty set
}

TEST(Trial, BadInputIsAnError) {
  TrialOptions o;
  o.camera_rate_hz = 30;  // 16.7 simulation steps per frame
  const TargetMotion target{{0.2, -0.4, 0.05}, {0, 0.1, 0}};
  EXPECT_NE(error_of([&] { (void)simulator().run(target, o, 1); }).find("whole number"),
            std::string::npos);
  o = {};
  o.observe_frames = 8;
  EXPECT_NE(error_of([&] { (void)simulator().run(target, o, 1); }).find("observe_frames"),
            std::string::npos);
  o = {};
  o.noise_cm = -1;
  EXPECT_NE(error_of([&] { (void)simulator().run(target, o, 1); }).find("noise"),
            std::string::npos);
  // A scene without the target body.
  const robot::Arm standalone =
      robot::Arm::load(test::data_dir() / "models" / "arm_standalone.xml");
  EXPECT_NE(error_of([&] {
              InterceptionSimulator s(standalone, testing::grid_model(), default_stereo_rig());
            }).find("no target body"),
            std::string::npos);
  EXPECT_NE(error_of([&] {
              InterceptionSimulator s(testing::scene_arm(), testing::grid_model(),
                                      default_stereo_rig(), "floor");
            }).find("no target body 'floor'"),
            std::string::npos);
}

}  // namespace
}  // namespace proprio::planning
