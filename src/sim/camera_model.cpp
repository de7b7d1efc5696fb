#include "proprio/sim/camera_model.hpp"

#include <cassert>
#include <cmath>
#include <cstddef>
#include <numbers>

namespace proprio::sim {

Eigen::Matrix3d intrinsics_from_fovy(double fovy_deg, int width, int height) {
  assert(fovy_deg > 0.0 && fovy_deg < 180.0 && width > 0 && height > 0);
  const double f = 0.5 * height / std::tan(0.5 * fovy_deg * std::numbers::pi / 180.0);
  Eigen::Matrix3d K;
  K << f, 0.0, 0.5 * (width - 1), 0.0, f, 0.5 * (height - 1), 0.0, 0.0, 1.0;
  return K;
}

geometry::Camera camera_from_mujoco(const mjModel& m, const mjData& d, int camera_id, int width,
                                    int height) {
  assert(camera_id >= 0 && camera_id < m.ncam);
  geometry::Camera c;
  c.K = intrinsics_from_fovy(m.cam_fovy[camera_id], width, height);
  // cam_xmat is row-major with the camera's axes as columns (camera -> world).
  Eigen::Matrix3d world_from_mj;
  for (int r = 0; r < 3; ++r) {
    for (int col = 0; col < 3; ++col)
      world_from_mj(r, col) = d.cam_xmat[std::ptrdiff_t{9} * camera_id + 3 * r + col];
  }
  const Eigen::Vector3d position(
      Eigen::Map<const Eigen::Vector3d>(d.cam_xpos + std::ptrdiff_t{3} * camera_id));
  const Eigen::Matrix3d cv_from_mj = Eigen::Vector3d(1.0, -1.0, -1.0).asDiagonal();
  c.R = cv_from_mj * world_from_mj.transpose();
  c.t = -c.R * position;
  c.width = width;
  c.height = height;
  return c;
}

}  // namespace proprio::sim
