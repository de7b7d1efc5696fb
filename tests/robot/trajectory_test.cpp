#include "proprio/robot/trajectory.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

#include "proprio/core/error.hpp"
#include "test_arm.hpp"

namespace proprio::robot {
namespace {

using testing::error_of;

TEST(Shaping, ThesisFunctionAndCorrectedDerivatives) {
  // SPEC section 2: on [0, 1] the thesis's move stops short, f(1) = 0.990, f'(1) = 0.14.
  EXPECT_NEAR(shaping_function(1.0).value, 0.9897, 5e-5);
  EXPECT_NEAR(shaping_function(1.0).rate, 0.1414, 5e-4);
  EXPECT_NEAR(1.0 - shaping_function(kShapingEnd).value, 2e-7, 5e-8);
  EXPECT_EQ(shaping_function(0.0).value, 0.0);
  EXPECT_EQ(shaping_function(0.0).rate, 0.0);
  EXPECT_EQ(shaping_function(0.0).accel, 0.0);
  for (double alpha : {1.0, kShapingAlpha, 2.5}) {
    for (double tau : {0.1, 0.4, 0.7, 1.0, 1.3}) {
      constexpr double h = 1e-5;
      const Shaped f = shaping_function(tau, alpha);
      const Shaped fp = shaping_function(tau + h, alpha);
      const Shaped fm = shaping_function(tau - h, alpha);
      EXPECT_NEAR(f.rate, (fp.value - fm.value) / (2 * h), 1e-8) << alpha << " " << tau;
      EXPECT_NEAR(f.accel, (fp.rate - fm.rate) / (2 * h), 1e-7) << alpha << " " << tau;
    }
  }
}

TEST(Shaping, RescaledMoveEndsExactlyAndAtRest) {
  for (double T : {0.5, 1.0, 3.0}) {
    const TimeShaping s(T);
    EXPECT_EQ(s(0.0).value, 0.0);
    EXPECT_EQ(s(T).value, 1.0);  // exactly, by construction
    EXPECT_NEAR(s(T * (1 - 1e-12)).value, 1.0, 1e-9);
    // Velocity and acceleration vanish at both ends (to ~1e-5 of their peak).
    EXPECT_LT(std::abs(s(T * (1 - 1e-12)).rate) * T, 1e-5);
    EXPECT_LT(std::abs(s(T * (1 - 1e-12)).accel) * T * T, 1e-3);
    EXPECT_LT(std::abs(s(1e-9).rate), 1e-12);
    EXPECT_LT(std::abs(s(1e-9).accel), 1e-6);
    // Outside the move the arm rests.
    EXPECT_EQ(s(-1.0).value, 0.0);
    EXPECT_EQ(s(2 * T).value, 1.0);
    EXPECT_EQ(s(2 * T).rate, 0.0);
    for (double u : {0.1, 0.3, 0.5, 0.8}) {
      const double t = u * T;
      const double h = 1e-6 * T;
      EXPECT_NEAR(s(t).rate, (s(t + h).value - s(t - h).value) / (2 * h), 1e-6 / T);
      EXPECT_NEAR(s(t).accel, (s(t + h).rate - s(t - h).rate) / (2 * h), 1e-5 / (T * T));
    }
  }
  EXPECT_THROW(TimeShaping(0.0), Error);
  EXPECT_THROW(TimeShaping(std::numeric_limits<double>::quiet_NaN()), Error);
  EXPECT_THROW(TimeShaping(1.0, -1.0), Error);
}

TEST(Bezier, ChainRuleDerivativesMatchFiniteDifferences) {
  const BezierTrajectory b({0.2, -0.1, 0.05}, {0.35, 0.1, 0.2}, {0.25, 0.2, 0.05}, 1.7);
  EXPECT_EQ(b.sample(0).position, b.p0());
  EXPECT_EQ(b.sample(1.7).position, b.p2());
  EXPECT_LT(b.sample(0).velocity.norm(), 1e-15);
  EXPECT_LT(b.sample(1.7).velocity.norm(), 1e-15);  // t = T is the rest state
  EXPECT_LT(b.sample(1.7 * (1 - 1e-12)).velocity.norm(), 1e-5);
  EXPECT_LT((b.curve(0.5) - (0.25 * b.p0() + 0.5 * b.p1() + 0.25 * b.p2())).norm(), 1e-15);
  for (double t : {0.05, 0.4, 0.85, 1.3, 1.6}) {
    constexpr double h = 1e-6;
    const CartesianSample s = b.sample(t);
    const CartesianSample sp = b.sample(t + h);
    const CartesianSample sm = b.sample(t - h);
    EXPECT_LT((s.velocity - (sp.position - sm.position) / (2 * h)).norm(), 1e-7) << t;
    EXPECT_LT((s.acceleration - (sp.velocity - sm.velocity) / (2 * h)).norm(), 1e-6) << t;
    EXPECT_EQ(s.t, t);
  }
  for (double s : {0.2, 0.6}) {
    constexpr double h = 1e-6;
    EXPECT_LT((b.curve_derivative(s) - (b.curve(s + h) - b.curve(s - h)) / (2 * h)).norm(), 1e-8);
  }
  // Arc length against a fine polyline.
  double poly = 0;
  for (int i = 0; i < 20000; ++i)
    poly += (b.curve((i + 1) / 20000.0) - b.curve(i / 20000.0)).norm();
  EXPECT_NEAR(b.length(), poly, 1e-8);
  EXPECT_THROW(
      BezierTrajectory({0, 0, 0}, {std::numeric_limits<double>::infinity(), 0, 0}, {1, 0, 0}, 1),
      Error);
}

TEST(Bezier, StraightMoveStaysOnTheSegmentAtTheMeanSpeed) {
  const Eigen::Vector3d a(0.2, -0.1, 0.03);
  const Eigen::Vector3d b(0.3, 0.1, 0.03);
  const BezierTrajectory m = straight_move(a, b, 0.1);
  EXPECT_NEAR(m.duration(), (b - a).norm() / 0.1, 1e-15);
  EXPECT_NEAR(m.length(), (b - a).norm(), 1e-15);
  const Eigen::Vector3d dir = (b - a).normalized();
  for (double u = 0; u <= 1.0; u += 0.05) {
    const CartesianSample s = m.sample(u * m.duration());
    const Eigen::Vector3d off = s.position - a;
    EXPECT_LT((off - off.dot(dir) * dir).norm(), 1e-15);
    EXPECT_LT(s.velocity.cross(dir).norm(), 1e-15);
  }
  EXPECT_NE(error_of([&] { straight_move(a, a, 0.1); }).find("coincide"), std::string::npos);
  EXPECT_NE(error_of([&] { straight_move(a, b, 0.0); }).find("speed"), std::string::npos);
}

TEST(Bezier, PsiFamilyIsRelativeToTheStart) {
  const Eigen::Vector3d p0(0.25, 0.0, 0.03);
  const BezierTrajectory straight = psi_trajectory(p0, {0.0, 0.1, 0.0}, 1.0);
  EXPECT_LT((straight.p2() - (p0 + Eigen::Vector3d(0, 0.1, 0))).norm(), 1e-15);  // theta = 0: +y
  const BezierTrajectory bent = psi_trajectory(p0, {std::numbers::pi / 2, 0.2, 0.3}, 1.0);
  EXPECT_LT((bent.p2() - (p0 + Eigen::Vector3d(0.2, 0, 0))).norm(), 1e-15);
  // p1 = midpoint + gamma (p2 - p0)_perp, perp = +90 degrees about z.
  EXPECT_LT((bent.p1() - (p0 + Eigen::Vector3d(0.1, 0.06, 0))).norm(), 1e-15);
  EXPECT_EQ(bent.p0(), p0);
  EXPECT_THROW(psi_trajectory(p0, {0.0, 0.0, 0.0}, 1.0), Error);
  EXPECT_THROW(psi_trajectory(p0, {0.0, 0.1, 0.0}, -1.0), Error);
}

TEST(Bezier, UniformSamplingEndsExactly) {
  const BezierTrajectory m = straight_move({0.2, 0, 0.03}, {0.3, 0, 0.03}, 0.07);  // 1.4286 s
  const auto samples = sample_trajectory(m, 100);
  const double T = m.duration();
  ASSERT_EQ(samples.size(), static_cast<std::size_t>(std::ceil(T * 100)) + 1);
  EXPECT_EQ(samples.back().t, T);
  EXPECT_EQ(samples.back().position, m.p2());
  const double dt = samples[1].t - samples[0].t;
  EXPECT_LE(dt, 0.01);
  for (std::size_t i = 1; i < samples.size(); ++i)
    EXPECT_NEAR(samples[i].t - samples[i - 1].t, dt, 1e-12);
  EXPECT_THROW(sample_trajectory(m, 0.0), Error);
}

}  // namespace
}  // namespace proprio::robot
