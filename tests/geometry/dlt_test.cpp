#include "proprio/geometry/dlt.hpp"

#include <gtest/gtest.h>

#include "proprio/core/error.hpp"
#include "synthetic.hpp"

namespace proprio::geometry {
namespace {
using testing::aligned;

struct Data {
  Camera camera = testing::robot_camera();
  std::vector<Eigen::Vector3d> world;
  std::vector<Eigen::Vector2d> pixels;
};

Data make_data(double noise_px, std::uint64_t seed = 7) {
  core::Rng rng(seed);
  Data d;
  d.world = testing::workspace_points(rng);
  for (const auto& X : d.world) {
    d.pixels.push_back(d.camera.project(X) +
                       Eigen::Vector2d(rng.normal(0.0, noise_px), rng.normal(0.0, noise_px)));
  }
  return d;
}

std::string error_of(const std::vector<Eigen::Vector3d>& world,
                     const std::vector<Eigen::Vector2d>& pixels) {
  try {
    calibrate_dlt(world, pixels);
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

TEST(Dlt, ExactDataGivesTheCamera) {
  const Data d = make_data(0.0);
  const DltResult r = calibrate_dlt(d.world, d.pixels);
  const Matrix34d truth = d.camera.P() / d.camera.P().norm();
  EXPECT_LT((aligned(r.P, truth) - truth).norm(), 1e-9);
  EXPECT_NEAR(r.P.norm(), 1.0, 1e-12);
  EXPECT_GT(r.P.leftCols<3>().determinant(), 0.0);
  EXPECT_LT(r.rms_px, 1e-8);
  EXPECT_LT((r.camera.K - d.camera.K).norm(), 1e-6);
  EXPECT_LT((r.camera.R - d.camera.R).norm(), 1e-9);
  EXPECT_LT((r.camera.t - d.camera.t).norm(), 1e-9);
  EXPECT_EQ(r.summary.num_points, 100);
  EXPECT_EQ(r.summary.points_behind, 0);
  EXPECT_LT(r.summary.sigma12_ratio, 1e-12);
  EXPECT_GT(r.summary.sigma11_ratio, 1e-6);
  ASSERT_EQ(r.residuals_px.size(), 100u);
}

TEST(Dlt, NoisyDataWithinTolerance) {
  // 0.5 px Gaussian noise per axis: expected RMS distance sqrt(2) * 0.5 = 0.71 px.
  const Data d = make_data(0.5);
  const DltResult r = calibrate_dlt(d.world, d.pixels);
  EXPECT_LT(r.rms_px, 0.85);
  EXPECT_GT(r.rms_px, 0.5);
  const Matrix34d truth = d.camera.P() / d.camera.P().norm();
  EXPECT_LT((aligned(r.P, truth) - truth).norm(), 0.01);
  double sq = 0.0;
  for (double e : r.residuals_px) sq += e * e;
  EXPECT_NEAR(r.rms_px, std::sqrt(sq / 100.0), 1e-12);
  EXPECT_NEAR(r.summary.max_residual_px,
              *std::max_element(r.residuals_px.begin(), r.residuals_px.end()), 1e-12);
}

TEST(Dlt, NormalisationIsUnitInvariant) {
  // The same scene in millimetres gives the same camera (t in mm): Hartley normalisation makes
  // DLT independent of the world unit.
  Data d = make_data(0.3);
  const DltResult m = calibrate_dlt(d.world, d.pixels);
  for (auto& X : d.world) X *= 1000.0;
  const DltResult mm = calibrate_dlt(d.world, d.pixels);
  EXPECT_NEAR(mm.rms_px, m.rms_px, 1e-9);
  EXPECT_LT((mm.camera.K - m.camera.K).norm(), 1e-6);
  EXPECT_LT((mm.camera.t / 1000.0 - m.camera.t).norm(), 1e-9);
}

TEST(Dlt, SixPointsAreEnough) {
  Data d = make_data(0.0);
  const std::vector<size_t> pick = {0, 13, 27, 41, 66, 99};
  std::vector<Eigen::Vector3d> w;
  std::vector<Eigen::Vector2d> p;
  for (size_t i : pick) {
    w.push_back(d.world[i]);
    p.push_back(d.pixels[i]);
  }
  const DltResult r = calibrate_dlt(w, p);
  const Matrix34d truth = d.camera.P() / d.camera.P().norm();
  EXPECT_LT((aligned(r.P, truth) - truth).norm(), 1e-8);
}

TEST(Dlt, DegenerateInputIsAnError) {
  Data d = make_data(0.0);
  EXPECT_EQ(
      error_of({d.world.begin(), d.world.begin() + 5}, {d.pixels.begin(), d.pixels.begin() + 5}),
      "DLT needs at least 6 point pairs, got 5");

  // Coplanar: the table top.
  std::vector<Eigen::Vector3d> plane;
  std::vector<Eigen::Vector2d> plane_px;
  for (int i = 0; i < 20; ++i) {
    plane.emplace_back(0.03 * i, 0.1 * (i % 4), 0.0);
    plane_px.push_back(d.camera.project(plane.back()) + Eigen::Vector2d(0.1 * (i % 3), 0.0));
  }
  EXPECT_NE(error_of(plane, plane_px).find("coplanar"), std::string::npos)
      << error_of(plane, plane_px);

  // Collinear.
  std::vector<Eigen::Vector3d> line;
  std::vector<Eigen::Vector2d> line_px;
  for (int i = 0; i < 10; ++i) {
    line.emplace_back(0.1 * i, 0.2 * i, 0.05 * i);
    line_px.push_back(d.camera.project(line.back()));
  }
  EXPECT_NE(error_of(line, line_px).find("collinear"), std::string::npos);

  // Five distinct points repeated: non-coplanar but too few constraints (rank 10).
  std::vector<Eigen::Vector3d> five;
  std::vector<Eigen::Vector2d> five_px;
  for (int k = 0; k < 3; ++k) {
    for (size_t i : {0u, 17u, 38u, 61u, 99u}) {
      five.push_back(d.world[i]);
      five_px.push_back(d.pixels[i]);
    }
  }
  EXPECT_NE(error_of(five, five_px).find("rank < 11"), std::string::npos)
      << error_of(five, five_px);

  // Not finite.
  d.pixels[3].x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(error_of(d.world, d.pixels), "DLT: point 4 is not finite");

  DltOptions bad;
  bad.min_points = 4;
  EXPECT_THROW(bad.validate(), Error);
}

TEST(Dlt, WithoutNormalisationStillSolvesExactData) {
  const Data d = make_data(0.0);
  DltOptions o;
  o.normalize = false;
  const DltResult r = calibrate_dlt(d.world, d.pixels, o);
  EXPECT_FALSE(r.summary.normalized);
  EXPECT_LT(r.rms_px, 1e-5);
}

}  // namespace
}  // namespace proprio::geometry
