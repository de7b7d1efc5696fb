// Closed-form Gaussian products and overlaps (eqs 3.29, 3.48) against numerical integration.
#include "proprio/planning/gaussian.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <numbers>

namespace proprio::planning {
namespace {

Gaussian<2> make(double mx, double my, double sxx, double sxy, double syy) {
  Gaussian<2> g;
  g.mean << mx, my;
  g.cov << sxx, sxy, sxy, syy;
  return g;
}

TEST(Gaussian, LogDensityMatchesTheFormulaIn1D) {
  Gaussian<1> g;
  g.mean << 0.3;
  g.cov << 0.04;
  Eigen::Matrix<double, 1, 1> x;
  x << 0.5;
  const double expected = -0.5 * (0.2 * 0.2 / 0.04) - 0.5 * std::log(2 * std::numbers::pi * 0.04);
  EXPECT_NEAR(log_density(g, x), expected, 1e-12);
}

TEST(Gaussian, ProductAndOverlapMatchNumericalIntegration) {
  const Gaussian<2> a = make(0.10, -0.05, 0.0040, 0.0010, 0.0020);
  const Gaussian<2> b = make(0.16, 0.02, 0.0010, -0.0004, 0.0030);
  // Integrate N(x|a) N(x|b) and its first two moments on a fine grid.
  const double lo = -0.4, hi = 0.6, h = 0.002;
  double mass = 0;
  Eigen::Vector2d m1 = Eigen::Vector2d::Zero();
  Eigen::Matrix2d m2 = Eigen::Matrix2d::Zero();
  for (double x = lo; x < hi; x += h) {
    for (double y = lo; y < hi; y += h) {
      const Eigen::Vector2d p(x, y);
      const double w = std::exp(log_density(a, p) + log_density(b, p)) * h * h;
      mass += w;
      m1 += w * p;
      m2 += w * p * p.transpose();
    }
  }
  const GaussianProduct<2> prod = product(a, b);
  EXPECT_NEAR(std::log(mass), log_overlap(a, b), 1e-6);  // eq 3.48
  EXPECT_NEAR(prod.log_scale, log_overlap(a, b), 1e-12);
  const Eigen::Vector2d mean = m1 / mass;
  const Eigen::Matrix2d cov = m2 / mass - mean * mean.transpose();
  EXPECT_LT((prod.gaussian.mean - mean).norm(), 1e-8);  // eq 3.29, normalised
  EXPECT_LT((prod.gaussian.cov - cov).norm(), 1e-8);
  // The information form gives the same.
  const Eigen::Matrix2d info = a.cov.inverse() + b.cov.inverse();
  EXPECT_LT((prod.gaussian.cov - info.inverse()).norm(), 1e-12);
  EXPECT_LT(
      (prod.gaussian.mean - info.inverse() * (a.cov.inverse() * a.mean + b.cov.inverse() * b.mean))
          .norm(),
      1e-12);
}

TEST(Gaussian, ProductWithAVeryNarrowGaussianTakesItsMean) {
  const Gaussian<2> wide = make(0, 0, 1, 0, 1);
  const Gaussian<2> narrow = make(0.3, -0.2, 1e-14, 0, 1e-14);
  const GaussianProduct<2> p = product(wide, narrow);
  EXPECT_LT((p.gaussian.mean - narrow.mean).norm(), 1e-12);
  EXPECT_LT(p.gaussian.cov.norm(), 1.5e-14);  // |1e-14 I| = 1.41e-14
  EXPECT_TRUE(p.gaussian.cov.allFinite());
}

}  // namespace
}  // namespace proprio::planning
