#include "proprio/geometry/backprojection.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "proprio/core/error.hpp"
#include "proprio/geometry/depth_pixels.hpp"
#include "synthetic.hpp"

namespace proprio::geometry {
namespace {

std::string error_of(const Matrix34d& P, const Eigen::Vector2d& x, const Plane& plane) {
  try {
    back_project_to_plane(P, x, plane);
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

TEST(BackProjection, ProjectThenBackProjectReturnsThePoint) {
  const Camera cam = testing::robot_camera();
  core::Rng rng(9);
  // The table top, and a tilted plane through the workspace with a non-unit normal.
  const Plane table{Eigen::Vector3d::UnitZ(), 0.0};
  const Plane tilted{Eigen::Vector3d(0.2, -0.5, 2.0), 0.3};
  for (const Plane& plane : {table, tilted}) {
    for (int i = 0; i < 50; ++i) {
      // A point on the plane: pick x, y and solve for z.
      const double x = rng.uniform(-0.3, 0.3);
      const double y = rng.uniform(0.0, 0.5);
      const double z = (plane.kappa - plane.n.x() * x - plane.n.y() * y) / plane.n.z();
      const Eigen::Vector3d X(x, y, z);
      for (double scale : {1.0, -3.0}) {  // P at any scale and sign
        const BackProjection b = back_project_to_plane(scale * cam.P(), cam.project(X), plane);
        EXPECT_LT((b.X - X).norm(), 1e-9);
        EXPECT_NEAR(b.depth, cam.depth(X), 1e-9);
        EXPECT_GT(b.incidence_cos, 0.1);
      }
    }
  }
}

TEST(BackProjection, ImpossibleGeometryIsAnError) {
  // A camera 0.5 m up looking horizontally along +y.
  const Camera cam = testing::look_at({0, 0, 0.5}, {0, 1, 0.5});
  const Plane table{Eigen::Vector3d::UnitZ(), 0.0};
  // The principal row is the horizon: parallel to the table.
  const Eigen::Vector2d horizon(cam.K(0, 2) + 40, cam.K(1, 2));
  EXPECT_EQ(error_of(cam.P(), horizon, table),
            "back-projection: the viewing ray is parallel to the plane");
  // Above the horizon the ray meets the table behind the camera.
  EXPECT_NE(error_of(cam.P(), {320, 100}, table).find("behind the camera"), std::string::npos);
  // Below the horizon it meets the table in front.
  EXPECT_NO_THROW(back_project_to_plane(cam.P(), {320, 400}, table));
  // A camera on the plane.
  EXPECT_EQ(error_of(cam.P(), {320, 400}, Plane{Eigen::Vector3d::UnitZ(), 0.5}),
            "back-projection: the camera centre lies on the plane");
  EXPECT_THROW(back_project_to_plane(cam.P(), {320, 400}, Plane{Eigen::Vector3d::Zero(), 1.0}),
               Error);
  EXPECT_THROW(back_project_to_plane(cam.P(), {std::nan(""), 400}, table), Error);
}

TEST(DepthPixels, APixelAtItsDepthIsTheWorldPointThatProjectsThere) {
  const Camera cam = testing::robot_camera();
  const DepthPixels pixels(cam);
  core::Rng rng(11);
  for (int i = 0; i < 50; ++i) {
    const Eigen::Vector3d X(rng.uniform(-0.3, 0.3), rng.uniform(0.0, 0.5), rng.uniform(0.0, 0.2));
    // A pixel near X's and the depth of the point that projects there.
    const Eigen::Vector2d x = cam.project(X);
    const int u = static_cast<int>(std::lround(x.x()));
    const int v = static_cast<int>(std::lround(x.y()));
    const double d = cam.depth(X);
    const Eigen::Vector3d W = pixels.world(u, v, d);
    EXPECT_LT((cam.project(W) - Eigen::Vector2d(u, v)).norm(), 1e-9);
    EXPECT_NEAR(cam.depth(W), d, 1e-12);
    // The same operations, to the bit, as the depth finders had written them.
    const Eigen::Matrix3d k_inv = cam.K.inverse();
    const Eigen::Matrix3d r_t = cam.R.transpose();
    const Eigen::Vector3d same = r_t * (d * (k_inv * Eigen::Vector3d(u, v, 1.0)) - cam.t);
    EXPECT_EQ(W, same);
  }
  EXPECT_TRUE(depth_measured(0.5));
  for (const double d : {0.0, -0.1, std::nan(""), std::numeric_limits<double>::infinity()}) {
    EXPECT_FALSE(depth_measured(d)) << d;
  }
}

}  // namespace
}  // namespace proprio::geometry
