#include "proprio/geometry/triangulation.hpp"

#include <gtest/gtest.h>

#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

#include "proprio/core/error.hpp"
#include "synthetic.hpp"

namespace proprio::geometry {
namespace {

struct Rig {
  Camera c1 = testing::robot_camera();
  Camera c2 = testing::second_camera();
  Matrix34d P1 = c1.P();
  Matrix34d P2 = c2.P();
};

double cost(const Rig& rig, const Eigen::Vector2d& x1, const Eigen::Vector2d& x2,
            const Eigen::Vector3d& X) {
  return (project(rig.P1, X) - x1).squaredNorm() + (project(rig.P2, X) - x2).squaredNorm();
}

TEST(Triangulation, ExactPixelsGiveThePoint) {
  const Rig rig;
  core::Rng rng(3);
  for (const auto& X : testing::workspace_points(rng)) {
    for (bool refine : {false, true}) {
      TriangulationOptions o;
      o.refine = refine;
      const Triangulation t = triangulate(rig.P1, rig.P2, rig.c1.project(X), rig.c2.project(X), o);
      EXPECT_LT((t.X - X).norm(), 1e-9);
      EXPECT_LT(t.rms_px, 1e-6);
    }
  }
}

TEST(Triangulation, LinearAgreesWithOpenCV) {
  const Rig rig;
  core::Rng rng(11);
  const auto world = testing::workspace_points(rng);
  std::vector<Eigen::Vector2d> x1, x2;
  cv::Mat a(2, static_cast<int>(world.size()), CV_64F),
      b(2, static_cast<int>(world.size()), CV_64F);
  for (size_t i = 0; i < world.size(); ++i) {
    x1.push_back(rig.c1.project(world[i]) + Eigen::Vector2d(rng.normal(0, 2), rng.normal(0, 2)));
    x2.push_back(rig.c2.project(world[i]) + Eigen::Vector2d(rng.normal(0, 2), rng.normal(0, 2)));
    const int c = static_cast<int>(i);
    a.at<double>(0, c) = x1[i].x();
    a.at<double>(1, c) = x1[i].y();
    b.at<double>(0, c) = x2[i].x();
    b.at<double>(1, c) = x2[i].y();
  }
  cv::Mat P1, P2, X4;
  cv::eigen2cv(rig.P1, P1);
  cv::eigen2cv(rig.P2, P2);
  cv::triangulatePoints(P1, P2, a, b, X4);
  const BatchTriangulation ours = triangulate(rig.P1, rig.P2, x1, x2);
  ASSERT_EQ(ours.points.size(), world.size());
  double max_diff = 0.0;
  for (size_t i = 0; i < world.size(); ++i) {
    const int c = static_cast<int>(i);
    const Eigen::Vector3d Xcv(X4.at<double>(0, c), X4.at<double>(1, c), X4.at<double>(2, c));
    max_diff = std::max(max_diff, (Xcv / X4.at<double>(3, c) - ours.points[i]).norm());
  }
  EXPECT_LT(max_diff, 1e-9);  // metres: the same algorithm, so rounding only
  EXPECT_EQ(ours.summary.num_points, 100);
  EXPECT_FALSE(ours.summary.refined);
  EXPECT_EQ(ours.summary.total_iterations, 0);
  EXPECT_DOUBLE_EQ(ours.summary.final_rms_px, ours.summary.linear_rms_px);
}

TEST(Triangulation, RefinementReachesTheReprojectionMinimum) {
  const Rig rig;
  core::Rng rng(5);
  TriangulationOptions o;
  o.refine = true;
  double linear_error = 0.0;
  double refined_error = 0.0;
  for (const auto& X : testing::workspace_points(rng)) {
    const Eigen::Vector2d x1 =
        rig.c1.project(X) + Eigen::Vector2d(rng.normal(0, 1), rng.normal(0, 1));
    const Eigen::Vector2d x2 =
        rig.c2.project(X) + Eigen::Vector2d(rng.normal(0, 1), rng.normal(0, 1));
    const Triangulation lin = triangulate(rig.P1, rig.P2, x1, x2);
    const Triangulation ref = triangulate(rig.P1, rig.P2, x1, x2, o);
    EXPECT_LE(ref.rms_px, lin.rms_px + 1e-12);
    EXPECT_EQ(ref.summary.termination, TriangulationTermination::kConverged);
    EXPECT_GE(ref.summary.iterations, 1);
    // A local minimum: no small step in any direction lowers the cost.
    const double c0 = cost(rig, x1, x2, ref.X);
    for (int k = 0; k < 3; ++k) {
      for (double h : {-1e-5, 1e-5}) {
        Eigen::Vector3d Y = ref.X;
        Y(k) += h;
        EXPECT_GE(cost(rig, x1, x2, Y), c0 - 1e-12);
      }
    }
    linear_error += (lin.X - X).squaredNorm();
    refined_error += (ref.X - X).squaredNorm();
  }
  // The maximum-likelihood point is no farther from the truth on average.
  EXPECT_LE(refined_error, linear_error * 1.02);
}

// Issue 16: the same calibration given as both cameras turned every point into the camera centre.
TEST(Triangulation, TwoViewsFromOneCentreAreRefused) {
  const Camera c = testing::robot_camera();
  const Matrix34d P = c.P();
  const Eigen::Vector2d x1(300, 200);
  const Eigen::Vector2d x2(310, 205);
  try {
    (void)triangulate(P, P, x1, x2);
    FAIL() << "triangulated with no baseline";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("the same centre"), std::string::npos) << e.what();
  }
  // Also through a scaled copy of P (the same camera written at another scale).
  EXPECT_THROW((void)triangulate(P, -2.5 * P, std::vector<Eigen::Vector2d>{x1},
                                 std::vector<Eigen::Vector2d>{x2}),
               Error);
}

TEST(Triangulation, BadInputIsAnError) {
  // Two cameras with the same orientation, both looking at the principal point: parallel rays.
  Camera c1;
  c1.K << 500, 0, 320, 0, 500, 240, 0, 0, 1;
  Camera c2 = c1;
  c2.t = Eigen::Vector3d(-0.2, 0, 0);
  const Eigen::Vector2d pp(320, 240);
  EXPECT_THROW(triangulate(c1.P(), c2.P(), pp, pp), Error);
  try {
    triangulate(c1.P(), c2.P(), std::vector<Eigen::Vector2d>{{300, 200}, pp},
                std::vector<Eigen::Vector2d>{{250, 200}, pp});
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()),
              "point 2: triangulation: the rays are parallel (point at infinity)");
  }
  // One camera twice: the rays coincide and the depth along them is undetermined (refused
  // before the rays are formed: the cameras share a centre).
  try {
    triangulate(c1.P(), c1.P(), Eigen::Vector2d(300, 200), Eigen::Vector2d(300, 200));
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("the same centre"), std::string::npos) << e.what();
  }
  EXPECT_THROW(triangulate(c1.P(), c2.P(), Eigen::Vector2d(std::nan(""), 1.0), pp), Error);
  EXPECT_THROW(triangulate(c1.P(), c2.P(), std::vector<Eigen::Vector2d>(2, pp),
                           std::vector<Eigen::Vector2d>(3, pp)),
               Error);
  TriangulationOptions o;
  o.max_evaluations = 0;
  EXPECT_THROW(o.validate(), Error);
}

}  // namespace
}  // namespace proprio::geometry
