// The stereo pair: camera construction, visibility, simulated measurements and their
// linearised covariance (eqs 3.20-3.21).
#include "proprio/planning/stereo_rig.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "planning_test_support.hpp"

namespace proprio::planning {
namespace {
using testing::error_of;

TEST(StereoRig, LookAtCameraCentresTheTargetWithYDown) {
  const Eigen::Vector3d eye(1.2, 0.3, 0.8), target(0.2, -0.1, 0.05);
  const geometry::Camera c = look_at_camera(eye, target, 500, 640, 480);
  EXPECT_LT((c.center() - eye).norm(), 1e-12);
  EXPECT_LT((c.project(target) - Eigen::Vector2d(319.5, 239.5)).norm(), 1e-9);
  EXPECT_NEAR(c.R.determinant(), 1, 1e-12);
  EXPECT_LT((c.R * c.R.transpose() - Eigen::Matrix3d::Identity()).norm(), 1e-12);
  // A point above the target appears higher in the image (smaller v): y points down.
  EXPECT_LT(c.project(target + Eigen::Vector3d(0, 0, 0.1)).y(), 239.5);
  EXPECT_GT(c.depth(target), 0);
}

TEST(StereoRig, LookAtCameraRejectsDegenerateViews) {
  EXPECT_NE(error_of([] {
              look_at_camera({0, 0, 1}, {0, 0, 1}, 500, 640, 480);
            }).find("coincide"),
            std::string::npos);
  EXPECT_NE(error_of([] {
              look_at_camera({0, 0, 1}, {0, 0, 0}, 500, 640, 480);
            }).find("vertical"),
            std::string::npos);
  EXPECT_NE(error_of([] {
              look_at_camera({1, 0, 1}, {0, 0, 0}, -1, 640, 480);
            }).find("focal"),
            std::string::npos);
}

TEST(StereoRig, DefaultPairSeesTheWholeInterceptionWorkspace) {
  const StereoRig rig = default_stereo_rig();
  const GridSpec grid;
  for (int i = 0; i < grid.size(); ++i) {
    EXPECT_TRUE(visible(rig, grid.end_point(grid.params(i)))) << i;
  }
  // And where the scenario's targets come from (up to about 0.5 m around the workspace).
  for (double x : {-0.2, 0.25, 0.7}) {
    for (double y : {-0.6, -0.15, 0.4}) EXPECT_TRUE(visible(rig, {x, y, 0.05})) << x << " " << y;
  }
  EXPECT_FALSE(visible(rig, {3.0, 0.0, 0.05}));  // behind the cameras
}

TEST(StereoRig, NoiseFreeMeasurementIsExact) {
  const StereoRig rig = default_stereo_rig();
  core::Rng rng(1);
  const Eigen::Vector3d X(0.3, -0.1, 0.05);
  const auto m = measure(rig, X, 0.0, rng);
  ASSERT_TRUE(m.has_value());
  EXPECT_LT((m->position - X).norm(), 1e-9);
  EXPECT_TRUE(m->covariance.isApprox(1e-12 * Eigen::Matrix3d::Identity()));
  EXPECT_FALSE(measure(rig, {3.0, 0, 0}, 0.0, rng).has_value());
  EXPECT_NE(error_of([&] { (void)measure(rig, X, -1.0, rng); }).find("noise"), std::string::npos);
}

TEST(StereoRig, MeasurementErrorsFollowTheLinearisedCovariance) {
  const StereoRig rig = default_stereo_rig();
  core::Rng rng(7);
  const Eigen::Vector3d X(0.25, -0.05, 0.05);
  const double px = 2.0;
  const int n = 3000;
  double mahalanobis = 0;
  Eigen::Matrix3d emp = Eigen::Matrix3d::Zero();
  for (int i = 0; i < n; ++i) {
    const auto m = measure(rig, X, px, rng);
    ASSERT_TRUE(m.has_value());
    const Eigen::Vector3d e = m->position - X;
    mahalanobis += e.dot(m->covariance.ldlt().solve(e));
    emp += e * e.transpose();
  }
  EXPECT_NEAR(mahalanobis / n, 3.0, 0.2);  // chi-square with 3 degrees of freedom
  const Eigen::Matrix3d model = measurement_covariance(rig, X, px);
  EXPECT_NEAR(std::sqrt((emp / n).trace()), std::sqrt(model.trace()),
              0.05 * std::sqrt(model.trace()));
  // Depth (along the cameras' view, mostly x here) is the least certain direction.
  EXPECT_GT(model(0, 0), model(1, 1));
}

TEST(StereoRig, PositionStdScalesWithPixelNoise) {
  const StereoRig rig = default_stereo_rig();
  const Eigen::Vector3d X(0.25, -0.05, 0.05);
  const double s1 = position_std_per_pixel(rig, X);
  EXPECT_GT(s1, 1e-4);
  EXPECT_LT(s1, 1e-2);
  EXPECT_NEAR(std::sqrt(measurement_covariance(rig, X, 3.0).trace() / 3), 3 * s1, 1e-12);
  // Farther from the cameras, less precise.
  EXPECT_GT(position_std_per_pixel(rig, {-0.2, -0.05, 0.05}), s1);
}

}  // namespace
}  // namespace proprio::planning
