#pragma once
// Depth images of boxes standing on the table, ray-cast from an oblique camera: the known scenes of
// the tests that find objects in depth (the push planner's depth split, the singulation check).

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "proprio/geometry/camera.hpp"

namespace proprio::test {

/// A box standing on the table (z = 0): footprint centre (x, y), half sides along its own axes,
/// height (its top), m; turned by `yaw` rad about the vertical; its bottom `z0` above the table
/// (0: on it; above 0, held up there, as a bicycle's frame between its wheels).
struct DepthBox {
  Eigen::Vector2d c;
  double hx = 0.0;
  double hy = 0.0;
  double h = 0.0;
  double yaw = 0.0;
  double z0 = 0.0;
};

/// A pinhole camera at `eye` looking at `target` (base frame, m; never straight down), OpenCV
/// axes (x right, y down, z forward), focal length `focal` px, principal point at the centre
/// of a `width` x `height` image: the oblique view of the simulated table's camera.
inline geometry::Camera look_at_camera(const Eigen::Vector3d& eye, const Eigen::Vector3d& target,
                                       double focal, int width, int height) {
  const Eigen::Vector3d z = (target - eye).normalized();
  const Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ()).normalized();
  const Eigen::Vector3d y = z.cross(x);
  geometry::Camera c;
  c.K << focal, 0, width / 2.0, 0, focal, height / 2.0, 0, 0, 1;
  c.R.row(0) = x.transpose();
  c.R.row(1) = y.transpose();
  c.R.row(2) = z.transpose();
  c.t = -c.R * eye;
  c.width = width;
  c.height = height;
  return c;
}

/// The depth image (metres along the optical axis; 0 where the ray meets nothing) of the table
/// top and `boxes`: each pixel's ray against every box (slabs in the box's frame) and the table
/// plane, the nearest hit.
inline cv::Mat1f render_boxes_depth(const geometry::Camera& cam,
                                    const std::vector<DepthBox>& boxes) {
  cv::Mat1f depth(cam.height, cam.width, 0.0F);
  const Eigen::Matrix3d ray = cam.R.transpose() * cam.K.inverse();
  const Eigen::Vector3d eye = cam.center();
  for (int v = 0; v < cam.height; ++v) {
    for (int u = 0; u < cam.width; ++u) {
      const Eigen::Vector3d d = ray * Eigen::Vector3d(u, v, 1.0);
      double s = d.z() < 0 ? -eye.z() / d.z() : std::numeric_limits<double>::infinity();
      for (const DepthBox& b : boxes) {
        const Eigen::Matrix2d to_box = Eigen::Rotation2Dd(-b.yaw).toRotationMatrix();
        Eigen::Vector3d o;
        o << to_box * (eye.head<2>() - b.c), eye.z();
        Eigen::Vector3d dir;
        dir << to_box * d.head<2>(), d.z();
        const double lo[3] = {-b.hx, -b.hy, b.z0};
        const double hi[3] = {b.hx, b.hy, b.h};
        double enter = 0;
        double leave = std::numeric_limits<double>::infinity();
        for (int k = 0; k < 3; ++k) {
          if (std::abs(dir[k]) < 1e-12) {
            if (o[k] < lo[k] || o[k] > hi[k]) leave = -1;
            continue;
          }
          const double a = (lo[k] - o[k]) / dir[k];
          const double e = (hi[k] - o[k]) / dir[k];
          enter = std::max(enter, std::min(a, e));
          leave = std::min(leave, std::max(a, e));
        }
        if (enter <= leave && enter > 0) s = std::min(s, enter);
      }
      if (std::isfinite(s)) depth(v, u) = static_cast<float>((cam.R * (eye + s * d) + cam.t).z());
    }
  }
  return depth;
}

}  // namespace proprio::test
