#pragma once
// MuJoCo's cameras as geometry::Camera (OpenCV conventions: x right, y down, z forward, pixel
// centres at integer coordinates, P = K [R | t], world = robot base frame).

#include <mujoco/mujoco.h>

#include "proprio/geometry/camera.hpp"

namespace proprio::sim {

/// K of a MuJoCo camera rendered at width x height: MuJoCo's frustum is symmetric with vertical
/// field of view fovy and square pixels, so fx = fy = (height / 2) / tan(fovy / 2) and the
/// principal point is the image centre ((width - 1) / 2, (height - 1) / 2).
Eigen::Matrix3d intrinsics_from_fovy(double fovy_deg, int width, int height);

/// The pinhole model of camera `camera_id` in its current pose (d->cam_xpos, d->cam_xmat after
/// mj_forward). MuJoCo cameras look along their -z axis with y up; the OpenCV camera frame is
/// that frame turned by pi about x: R = diag(1, -1, -1) cam_xmat^T, t = -R cam_xpos; so that
/// P = K [R | t] (eq 3.7) maps world points to pixels.
geometry::Camera camera_from_mujoco(const mjModel& m, const mjData& d, int camera_id, int width,
                                    int height);

}  // namespace proprio::sim
