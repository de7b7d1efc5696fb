#pragma once
// hold-3d (thesis 5.2): the target is held under the pusher and carried along a 3D curve, the
// hand turning it in its grip so that the views change in 3D. A MuJoCo weld equality constraint
// between the arm's last link and the object stands in for the grip (World::set_grasp).

#include <string>

#include "proprio/robot/trajectory.hpp"
#include "proprio/sim/recorder.hpp"
#include "proprio/sim/world.hpp"

namespace proprio::sim {

/// Makes the plan's move the carry of `target` (held, via, push_start, push_end,
/// scene.grasp_object).
void plan_hold(const std::string& target, ScenarioPlan& plan);

/// The carry: the quadratic Bezier of the plan at `speed` (m/s), at most kMaxCarrySpeed.
robot::BezierTrajectory carry_move(const ScenarioPlan& plan, double speed);

/// Grasps `target` where the arm now is: its top face just under the pusher tip, turned with the
/// arm; from then on the physics carries it.
void grasp_target(World& world, ObjectId target);

/// The hand's turn of the held object at time `t`, s (a slow wobble about z and x).
void turn_held(World& world, double t);

}  // namespace proprio::sim
