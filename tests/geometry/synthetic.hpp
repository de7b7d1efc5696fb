#pragma once
// Synthetic cameras and workspaces shared by the geometry tests.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "proprio/core/random.hpp"
#include "proprio/geometry/camera.hpp"

namespace proprio::geometry::testing {

/// A 640x480 camera at `centre` looking at `target`, image x along world-horizontal (z is up).
inline Camera look_at(const Eigen::Vector3d& centre, const Eigen::Vector3d& target,
                      double focal = 800.0) {
  Camera c;
  c.K << focal, 0.0, 319.5, 0.0, 1.02 * focal, 241.0, 0.0, 0.0, 1.0;
  const Eigen::Vector3d z = (target - centre).normalized();
  const Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ()).normalized();
  const Eigen::Vector3d y = z.cross(x);
  c.R.row(0) = x.transpose();
  c.R.row(1) = y.transpose();
  c.R.row(2) = z.transpose();
  c.t = -c.R * centre;
  c.width = 640;
  c.height = 480;
  return c;
}

/// The robot's camera of the tests: 1.2 m in front of the table, 0.8 m up, looking at the
/// workspace.
inline Camera robot_camera() { return look_at({0.1, -1.2, 0.8}, {0.0, 0.2, 0.15}); }

/// A stereo rig: robot_camera() and a second one 0.4 m to its right.
inline Camera second_camera() { return look_at({0.5, -1.1, 0.8}, {0.0, 0.2, 0.15}); }

/// A 5x5x4 grid over the workspace [-0.3, 0.3] x [0, 0.5] x [0, 0.4] m, jittered.
inline std::vector<Eigen::Vector3d> workspace_points(core::Rng& rng) {
  std::vector<Eigen::Vector3d> pts;
  for (int i = 0; i < 5; ++i) {
    for (int j = 0; j < 5; ++j) {
      for (int k = 0; k < 4; ++k) {
        pts.emplace_back(-0.3 + 0.15 * i + rng.uniform(-0.02, 0.02),
                         0.125 * j + rng.uniform(-0.02, 0.02),
                         0.4 / 3 * k + rng.uniform(-0.02, 0.02));
      }
    }
  }
  return pts;
}

/// P scaled to unit Frobenius norm with the sign of `reference`, for comparisons up to scale.
inline Matrix34d aligned(const Matrix34d& P, const Matrix34d& reference) {
  Matrix34d Q = P / P.norm();
  if ((Q.array() * reference.array()).sum() < 0) Q = -Q;
  return Q;
}

}  // namespace proprio::geometry::testing
