#pragma once
// The pose a scripted mover gives an object each frame: standing on the table at (x, y), turned
// by yaw about the vertical.

#include <Eigen/Geometry>

#include "proprio/sim/world.hpp"

namespace proprio::sim {

/// Height above the table top at which scripted objects are put, m: a millimetre clear of it, so
/// that a pose set from a script never starts a frame sunk into the table.
inline constexpr double kScriptedLift = 0.001;

/// An object of `type` standing on the table at (x, y), m, turned by `yaw`, rad.
inline Pose on_table(const ObjectType& type, double x, double y, double yaw) {
  Pose p = Pose::Identity();
  p.translation() = Eigen::Vector3d(x, y, type.bottom() + kScriptedLift);
  p.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return p;
}

}  // namespace proprio::sim
