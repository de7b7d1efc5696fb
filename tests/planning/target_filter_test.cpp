// The target filter: the learned transition (eqs 3.22-3.24), prediction with growing covariance
// (3.25), the measurement update as the product of Gaussians (3.29), and bad input.
#include "proprio/planning/target_filter.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "planning_test_support.hpp"
#include "proprio/planning/gaussian.hpp"

namespace proprio::planning {
namespace {
using testing::error_of;
using testing::exact_measurements;

constexpr double kDt = 0.04;

TargetMotion crossing_target() { return {{0.05, -0.45, 0.05}, {0.06, 0.11, 0.0}}; }

StateMatrix cv_transition() {
  StateMatrix A = StateMatrix::Identity();
  A.topRightCorner<3, 3>() = kDt * Eigen::Matrix3d::Identity();
  return A;
}

TEST(TargetFilter, LearnsAConstantVelocityTransitionFromTenStates) {
  const auto ms = exact_measurements(crossing_target(), 11, kDt);
  std::vector<Eigen::Vector3d> z;
  for (const auto& m : ms) z.push_back(m.position);
  FilterOptions o;
  const TransitionFit fit = learn_transition(z, 0.0, o);
  // A constant-velocity target spans a plane of the state space: the fit is rank-deficient.
  EXPECT_EQ(fit.rank, 2);
  const auto s = measured_states(z, kDt);
  ASSERT_EQ(s.size(), 10u);
  for (std::size_t i = 0; i + 1 < s.size(); ++i) {
    EXPECT_LT((fit.A * s[i] - s[i + 1]).norm(), 1e-9) << i;           // eq 3.22
    EXPECT_LT(((fit.A - cv_transition()) * s[i]).norm(), 1e-9) << i;  // = the CV model there
  }
  EXPECT_LT(fit.residual_rms, 1e-9);
  EXPECT_LT(fit.Q.norm(), 1e-10);
}

TEST(TargetFilter, LearnsAGeneralLinearTransitionExactly) {
  // Positions driven by v_{t+1} = B z_t + C v_t, z_{t+1} = z_t + dt v_{t+1}: the measured
  // states (z, finite-difference v) follow A = [[I + dt B, dt C], [B, C]], of full rank.
  Eigen::Matrix3d B, C;
  B << 0.02, -0.3, 0.01, 0.25, 0.03, -0.02, 0.01, 0.02, -0.04;
  C << 0.95, 0.1, 0.0, -0.12, 0.97, 0.05, 0.02, -0.03, 0.9;
  StateMatrix A_true;
  A_true << Eigen::Matrix3d::Identity() + kDt * B, kDt * C, B, C;
  std::vector<Eigen::Vector3d> z = {{0.2, -0.1, 0.05}};
  Eigen::Vector3d v(0.1, 0.05, -0.02);
  for (int t = 0; t < 10; ++t) {
    const Eigen::Vector3d v_next = B * z.back() + C * v;
    z.push_back(z.back() + kDt * v_next);
    v = v_next;
  }
  const TransitionFit fit = learn_transition(z, 0.0, FilterOptions{});
  EXPECT_EQ(fit.rank, 6);
  EXPECT_LT((fit.A - A_true).norm(), 1e-6);
}

TEST(TargetFilter, NoiseFreePredictionsFollowTheTarget) {
  const TargetMotion target = crossing_target();
  const TargetFilter f(exact_measurements(target, 20, kDt), FilterOptions{});
  EXPECT_NEAR(f.estimate().t, 19 * kDt, 1e-12);
  const auto pred = f.predict(60);
  ASSERT_EQ(pred.size(), 60u);
  for (const auto& p : pred) {
    EXPECT_LT((p.position() - target.position(p.t)).norm(), 1e-6) << p.t;
  }
}

TEST(TargetFilter, PredictedCovarianceGrows) {
  const StereoRig rig = default_stereo_rig();
  for (TransitionModel model : {TransitionModel::kLearned, TransitionModel::kConstantVelocity}) {
    core::Rng rng(3);
    std::vector<PositionMeasurement> ms;
    const TargetMotion target = crossing_target();
    for (int i = 0; i < 20; ++i) {
      const double t = i * kDt;
      const auto m = measure(rig, target.position(t), 1.0, rng);
      ASSERT_TRUE(m.has_value());
      ms.push_back({t, m->position, m->covariance});
    }
    FilterOptions o;
    o.transition = model;
    const TargetFilter f(ms, o);
    const double start = f.estimate().position_cov().trace();
    double previous = start;
    const auto pred = f.predict(60);
    for (const auto& p : pred) {  // eq 3.25
      const double tr = p.position_cov().trace();
      if (model == TransitionModel::kConstantVelocity) {
        EXPECT_GT(tr, previous) << " at " << p.t;
      } else {
        // A transition learned from noisy states contracts (its eigenvalues fall below 1), so
        // the covariance grows towards the bound M = A M A^T + Q instead of without bound.
        EXPECT_GE(tr, previous * (1 - 1e-12)) << " at " << p.t;
      }
      EXPECT_TRUE(p.mean.allFinite());
      previous = tr;
    }
    EXPECT_GT(pred.back().position_cov().trace(), 2 * start) << to_string(model);
  }
}

TEST(TargetFilter, NoiseFreeLearnedPredictionStillGrowsItsCovariance) {
  const TargetFilter f(exact_measurements(crossing_target(), 20, kDt), FilterOptions{});
  double previous = f.estimate().position_cov().trace();
  for (const auto& p : f.predict(60)) {
    EXPECT_GT(p.position_cov().trace(), previous) << p.t;
    previous = p.position_cov().trace();
  }
}

TEST(TargetFilter, UpdateIsTheProductOfPredictionAndCamera) {
  const TargetMotion target = crossing_target();
  auto ms = exact_measurements(target, 15, kDt, 1e-6);
  FilterOptions o;
  o.transition = TransitionModel::kConstantVelocity;
  TargetFilter f(ms, o);
  const TargetEstimate prior = f.predict(1).front();
  PositionMeasurement m{prior.t, target.position(prior.t) + Eigen::Vector3d(0.003, -0.002, 0.001),
                        Eigen::Vector3d(4e-6, 1e-6, 9e-6).asDiagonal()};
  f.update(m);
  const GaussianProduct<3> p = product(Gaussian<3>{prior.position(), prior.position_cov()},
                                       Gaussian<3>{m.position, m.covariance});  // eq 3.29
  EXPECT_LT((f.estimate().position() - p.gaussian.mean).norm(), 1e-12);
  EXPECT_LT((f.estimate().position_cov() - p.gaussian.cov).norm(), 1e-15);
  EXPECT_EQ(f.summary().updates, 16);
}

TEST(TargetFilter, ConstantVelocityFilterIsConsistentOnStereoMeasurements) {
  const StereoRig rig = default_stereo_rig();
  core::Rng rng(11);
  FilterOptions o;
  o.transition = TransitionModel::kConstantVelocity;
  double nees = 0;
  const int runs = 300;
  for (int k = 0; k < runs; ++k) {
    const TargetMotion target{{0.1 + 0.2 * rng.uniform(), -0.4, 0.05},
                              {rng.uniform(-0.1, 0.1), rng.uniform(0.05, 0.15), 0}};
    std::vector<PositionMeasurement> ms;
    for (int i = 0; i < 20; ++i) {
      const double t = i * kDt;
      const auto m = measure(rig, target.position(t), 2.0, rng);
      ms.push_back({t, m->position, m->covariance});
    }
    const TargetEstimate p = TargetFilter(ms, o).predict(25).back();
    const Eigen::Vector2d e = (p.position() - target.position(p.t)).head<2>();
    nees += e.dot(p.position_cov().topLeftCorner<2, 2>().ldlt().solve(e));
  }
  EXPECT_NEAR(nees / runs, 2.0, 0.35);  // chi-square, 2 degrees of freedom
}

TEST(TargetFilter, LearnedTransitionOnNoisyDataStaysFiniteAndDropsNoiseDirections) {
  const StereoRig rig = default_stereo_rig();
  core::Rng rng(5);
  std::vector<PositionMeasurement> ms;
  const TargetMotion target = crossing_target();
  for (int i = 0; i < 20; ++i) {
    const double t = i * kDt;
    const auto m = measure(rig, target.position(t), 2.0, rng);
    ms.push_back({t, m->position, m->covariance});
  }
  const TargetFilter f(ms, FilterOptions{});
  EXPECT_LT(f.summary().fit.rank, 6);
  EXPECT_GT(f.summary().fit.tolerance, 0);
  for (const auto& p : f.predict(80)) EXPECT_TRUE(p.mean.allFinite() && p.cov.allFinite());
}

TEST(TargetFilter, RejectsBadMeasurements) {
  const TargetMotion target = crossing_target();
  FilterOptions o;
  EXPECT_NE(error_of([&] {
              TargetFilter(exact_measurements(target, 10, kDt), o);
            }).find("needs at least 11 measurements"),
            std::string::npos);
  auto gap = exact_measurements(target, 15, kDt);
  gap[5].t += kDt;
  EXPECT_NE(error_of([&] { TargetFilter(gap, o); }).find("consecutive frames"), std::string::npos);
  auto nan = exact_measurements(target, 15, kDt);
  nan[12].position.x() = std::nan("");
  EXPECT_NE(error_of([&] { TargetFilter(nan, o); }).find("not finite"), std::string::npos);
  auto singular = exact_measurements(target, 15, kDt);
  singular[3].covariance.setZero();
  EXPECT_NE(error_of([&] { TargetFilter(singular, o); }).find("positive definite"),
            std::string::npos);
  TargetFilter f(exact_measurements(target, 15, kDt), o);
  PositionMeasurement past{0.1, target.position(0.1), 1e-6 * Eigen::Matrix3d::Identity()};
  EXPECT_NE(error_of([&] { f.update(past); }).find("not a frame after"), std::string::npos);
  PositionMeasurement off_grid{f.estimate().t + 0.5 * kDt, target.position(0.1),
                               1e-6 * Eigen::Matrix3d::Identity()};
  EXPECT_NE(error_of([&] { f.update(off_grid); }).find("not a frame after"), std::string::npos);
  o.learn_states = 2;
  EXPECT_NE(error_of([&] { o.validate(); }).find("learn_states"), std::string::npos);
  EXPECT_NE(error_of([] { transition_model_from_string("kalman"); }).find("unknown transition"),
            std::string::npos);
  EXPECT_EQ(transition_model_from_string("constant-velocity"), TransitionModel::kConstantVelocity);
}

TEST(TargetFilter, MissedFramesArePredictedThrough) {
  const TargetMotion target = crossing_target();
  auto ms = exact_measurements(target, 20, kDt);
  ms.erase(ms.begin() + 14);  // after the learning window
  const TargetFilter f(ms, FilterOptions{});
  EXPECT_EQ(f.summary().missed_steps, 1);
  EXPECT_LT((f.estimate().position() - target.position(f.estimate().t)).norm(), 1e-6);
}

}  // namespace
}  // namespace proprio::planning
