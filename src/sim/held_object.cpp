#include "held_object.hpp"

#include <algorithm>
#include <cmath>

namespace proprio::sim {

namespace {

// The carry's top speed, m/s: a faster RecordOptions::push_speed is capped to it.
constexpr double kMaxCarrySpeed = 0.06;
// The gap between the pusher tip and the held object's top face at the grasp, m.
constexpr double kGripGap = 0.01;
// The hand's turn: about z, kYawAmplitude * sin(kYawRate * t); about x, kTiltAmplitude *
// sin(kTiltRate * t) (rad, rad/s); two different rates, so that the
// pair of angles does not soon repeat.
constexpr double kYawAmplitude = 0.6;
constexpr double kYawRate = 0.9;
constexpr double kTiltAmplitude = 0.15;
constexpr double kTiltRate = 1.3;

}  // namespace

void plan_hold(const std::string& target, ScenarioPlan& plan) {
  plan.held = true;
  // The curve's start, control point and end (pusher tip, m, robot frame): within the arm's
  // reach, from low at the right to high in the middle and back down.
  plan.push_start = {0.18, -0.08, 0.13};
  plan.via = {0.24, 0.06, 0.21};
  plan.push_end = {0.27, -0.04, 0.15};
  plan.scene.grasp_object = target;
}

robot::BezierTrajectory carry_move(const ScenarioPlan& plan, double speed) {
  return {plan.push_start, plan.via, plan.push_end,
          ((plan.via - plan.push_start).norm() + (plan.push_end - plan.via).norm()) /
              std::min(speed, kMaxCarrySpeed)};
}

// The fingers do not close on the object: the arm's jaws span the pusher, not an object below
// it, so the weld stands in for the grip.
void grasp_target(World& world, ObjectId target) {
  const ObjectType& type = world.object(target).type;
  const Eigen::Vector3d ee = world.ee_position();
  const Eigen::Vector3d he = type.half_extents();
  const Eigen::Vector3d ce = type.center();
  Pose p = Pose::Identity();
  p.linear() =
      Eigen::AngleAxisd(std::atan2(ee.y(), ee.x()), Eigen::Vector3d::UnitZ()).toRotationMatrix();
  p.translation() = ee - Eigen::Vector3d(0, 0, kGripGap + he.z()) - p.linear() * ce;
  world.set_object_pose(target, p);
  world.set_grasp(true, ce);
}

void turn_held(World& world, double t) {
  world.set_grasp_rotation(
      (Eigen::AngleAxisd(kYawAmplitude * std::sin(kYawRate * t), Eigen::Vector3d::UnitZ()) *
       Eigen::AngleAxisd(kTiltAmplitude * std::sin(kTiltRate * t), Eigen::Vector3d::UnitX()))
          .toRotationMatrix());
}

}  // namespace proprio::sim
