#include "proprio/geometry/visual_uncertainty.hpp"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <filesystem>
#include <numbers>
#include <opencv2/imgcodecs.hpp>

#include "proprio/core/error.hpp"
#include "proprio/geometry/triangulation.hpp"
#include "proprio/geometry/uncertainty_map.hpp"
#include "synthetic.hpp"

namespace proprio::geometry {
namespace {

TEST(ProjectionJacobian, MatchesFiniteDifferences) {
  const Camera cam = testing::robot_camera();
  core::Rng rng(1);
  for (const auto& X : testing::workspace_points(rng)) {
    for (double scale : {1.0, -0.01}) {
      const Matrix34d P = scale * cam.P();
      const Eigen::Matrix<double, 2, 3> J = projection_jacobian(P, X);
      Eigen::Matrix<double, 2, 3> fd;
      const double h = 1e-6;
      for (int k = 0; k < 3; ++k) {
        Eigen::Vector3d a = X, b = X;
        a(k) += h;
        b(k) -= h;
        fd.col(k) = (project(P, a) - project(P, b)) / (2 * h);
      }
      EXPECT_LT((J - fd).norm(), 1e-6 * J.norm());
    }
  }
}

TEST(LogPosterior, PeaksAtTheTruePointWithTheGaussianConstant) {
  const Camera c1 = testing::robot_camera(), c2 = testing::second_camera();
  const Eigen::Vector3d X(0.05, 0.2, 0.1);
  const Eigen::Vector2d x1 = c1.project(X), x2 = c2.project(X);
  Eigen::Matrix2d Sigma;
  Sigma << 2.0, 0.3, 0.3, 1.0;
  const double peak = log_posterior(c1.P(), c2.P(), x1, x2, X, Sigma);
  EXPECT_NEAR(peak, 2.0 * (-std::log(2.0 * std::numbers::pi) - 0.5 * std::log(Sigma.determinant())),
              1e-12);
  for (int k = 0; k < 3; ++k) {
    Eigen::Vector3d Y = X;
    Y(k) += 1e-3;
    EXPECT_LT(log_posterior(c1.P(), c2.P(), x1, x2, Y, Sigma), peak);
  }
  // Quadratic in the residual: one pixel off in camera 1 along u with Sigma = I costs 1/2.
  const double at_one =
      log_posterior(c1.P(), c2.P(), x1 + Eigen::Vector2d(1, 0), x2, X, Eigen::Matrix2d::Identity());
  const double at_zero = log_posterior(c1.P(), c2.P(), x1, x2, X, Eigen::Matrix2d::Identity());
  EXPECT_NEAR(at_zero - at_one, 0.5, 1e-12);
  EXPECT_THROW(log_posterior(c1.P(), c2.P(), x1, x2, X, -Sigma), Error);
}

TEST(TriangulationCovariance, MatchesMonteCarlo) {
  const Camera c1 = testing::robot_camera(), c2 = testing::second_camera();
  const Eigen::Vector3d X(-0.1, 0.35, 0.2);
  const double sigma_px = 1.0;
  const Eigen::Matrix3d cov = triangulation_covariance(
      c1.P(), c2.P(), X, sigma_px * sigma_px * Eigen::Matrix2d::Identity());

  core::Rng rng(2024);
  TriangulationOptions o;
  o.refine = true;
  const int n = 4000;
  std::vector<Eigen::Vector3d> samples;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector2d x1 =
        c1.project(X) + sigma_px * Eigen::Vector2d(rng.normal(), rng.normal());
    const Eigen::Vector2d x2 =
        c2.project(X) + sigma_px * Eigen::Vector2d(rng.normal(), rng.normal());
    samples.push_back(triangulate(c1.P(), c2.P(), x1, x2, o).X);
    mean += samples.back();
  }
  mean /= n;
  Eigen::Matrix3d mc = Eigen::Matrix3d::Zero();
  for (const auto& s : samples) mc += (s - mean) * (s - mean).transpose();
  mc /= n - 1;
  // Sampling error of a covariance from 4000 draws is about sqrt(2 / 4000) = 2%.
  EXPECT_LT((mc - cov).norm(), 0.08 * cov.norm()) << "linearised\n"
                                                  << cov << "\nMonte Carlo\n"
                                                  << mc;
  const double worst = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(cov).eigenvalues()(2);
  const double worst_mc = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(mc).eigenvalues()(2);
  EXPECT_NEAR(std::sqrt(worst_mc), std::sqrt(worst), 0.05 * std::sqrt(worst));
  EXPECT_LT((mean - X).norm(), 0.1 * std::sqrt(worst));  // nearly unbiased here
}

TEST(TriangulationCovariance, UnobservableOrHiddenPointsAreErrors) {
  const Camera c1 = testing::robot_camera(), c2 = testing::second_camera();
  const Eigen::Matrix2d I = Eigen::Matrix2d::Identity();
  // On the baseline, in front of both cameras? The baseline runs between the centres, which are
  // in each other's side view; a point beyond camera 2 on the line is in front of neither, so use
  // a custom rig: camera 2 straight ahead of camera 1 on its optical axis.
  const Camera a = testing::look_at({0, 0, 0}, {0, 1, 0});
  const Camera b = testing::look_at({0, 0.5, 0}, {0, 2, 0});
  EXPECT_THROW(triangulation_covariance(a.P(), b.P(), {0, 1.5, 0}, I), Error);
  EXPECT_NO_THROW(triangulation_covariance(a.P(), b.P(), {0.1, 1.5, 0.05}, I));
  EXPECT_THROW(triangulation_covariance(c1.P(), c2.P(), {0, -3.0, 0.8}, I), Error);  // behind
}

TEST(UncertaintyMap, GrowsWithDistanceAndRenders) {
  const Camera c1 = testing::robot_camera(), c2 = testing::second_camera();
  UncertaintyMapOptions o;
  o.range_a = {-0.6, 0.6};
  o.range_b = {-0.8, 1.2};
  o.cells_a = 60;
  o.cells_b = 100;
  o.slice_at = 0.1;
  const UncertaintyMap map = compute_uncertainty_map(c1, c2, o);
  const auto& s = map.summary;
  EXPECT_EQ(s.cells, 6000);
  EXPECT_EQ(s.valid_cells + s.behind_camera + s.outside_image + s.unobservable, s.cells);
  EXPECT_GT(s.valid_cells, 500);
  EXPECT_GT(s.outside_image, 0);
  EXPECT_LT(s.min_sigma, s.median_sigma);
  EXPECT_LT(s.median_sigma, s.max_sigma);
  // Each valid cell's value is the covariance's worst direction.
  for (int r = 0; r < o.cells_b; r += 7) {
    for (int c = 0; c < o.cells_a; c += 5) {
      if (!map.valid(r, c)) continue;
      const Eigen::Matrix3d cov = triangulation_covariance(c1.P(), c2.P(), map.cell_centre(r, c),
                                                           Eigen::Matrix2d::Identity());
      EXPECT_NEAR(map.sigma(r, c),
                  std::sqrt(Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(cov).eigenvalues()(2)),
                  1e-12);
      EXPECT_NEAR(map.cell_centre(r, c).z(), 0.1, 1e-15);
    }
  }
  // Farther from the cameras (larger y along the column through the rig) is less certain.
  double near = 0, far = 0;
  for (int r = 0; r < o.cells_b; ++r) {
    if (map.valid(r, 30)) {
      if (near == 0) near = map.sigma(r, 30);
      far = map.sigma(r, 30);
    }
  }
  EXPECT_GT(far, 2.0 * near);
  // Twice the pixel noise doubles every value.
  o.sigma_px = 2.0;
  const UncertaintyMap twice = compute_uncertainty_map(c1, c2, o);
  EXPECT_NEAR(twice.summary.max_sigma, 2.0 * s.max_sigma, 1e-9 * s.max_sigma);

  const cv::Mat img = render_uncertainty_map(map);
  ASSERT_EQ(img.type(), CV_8UC3);
  EXPECT_EQ(img.cols, 80 + 480 + 130);
  EXPECT_EQ(img.rows, 50 + 800 + 60);  // the map keeps the ranges' aspect
  // The colour bar runs from dark blue (low) to dark red (high).
  const cv::Vec3b top = img.at<cv::Vec3b>(52, 80 + 480 + 29);
  const cv::Vec3b bottom = img.at<cv::Vec3b>(50 + 800 - 2, 80 + 480 + 29);
  EXPECT_GT(top[2], top[0]);
  EXPECT_GT(bottom[0], bottom[2]);
  const auto path = std::filesystem::temp_directory_path() / "proprio_uncertainty_map_test.png";
  ASSERT_TRUE(cv::imwrite(path.string(), img));
  EXPECT_EQ(cv::imread(path.string()).size(), img.size());
  std::filesystem::remove(path);

  UncertaintyMapOptions nowhere = o;
  nowhere.slice_at = 5.0;  // far above both cameras' views
  EXPECT_THROW(compute_uncertainty_map(c1, c2, nowhere), Error);
  UncertaintyMapOptions bad = o;
  bad.range_a = {1.0, -1.0};
  EXPECT_THROW(compute_uncertainty_map(c1, c2, bad), Error);
}

}  // namespace
}  // namespace proprio::geometry
