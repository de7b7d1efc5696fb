#pragma once
// Arm dynamics on the MuJoCo model (thesis 3.5): joint torques along a joint trajectory by inverse
// dynamics (the thesis used DySim's Lagrangian model), the energy cost of eq 3.41, and servo
// commands that feed those torques forward through the position actuators.

#include <vector>

#include "proprio/robot/arm.hpp"
#include "proprio/robot/joint_tracking.hpp"

namespace proprio::robot {

/// The torque on each arm joint (N m) that produces acceleration qddot at (q, qdot), by
/// mj_inverse: inertia (with rotor armature), Coriolis and centrifugal terms, gravity, and the
/// joint damping the motors must overcome. Other degrees of freedom of the model (gripper
/// fingers, free objects) are held at their current positions with zero velocity and
/// acceleration; contacts in the scene at that moment contribute their forces.
JointVector inverse_dynamics(ArmState& state, const JointVector& q, const JointVector& qdot,
                             const JointVector& qddot);

/// Torques at every sample of `trajectory` (same indexing).
std::vector<JointVector> inverse_dynamics(ArmState& state, const JointTrajectory& trajectory);

/// The torque that holds the arm still at q: MuJoCo's bias force qfrc_bias at zero velocity
/// (gravity only), N m.
JointVector gravity_torque(ArmState& state, const JointVector& q);

/// Energy cost of eq 3.41: E_k = integral of |tau_k(t)| dt for each joint (trapezoid rule over
/// samples dt apart), N m s, and their sum over all joints.
struct Energy {
  JointVector per_joint = JointVector::Zero();
  double total = 0;
};
Energy energy(const std::vector<JointVector>& torques, double dt);

/// Position-actuator commands (the ctrl values of a1..a5) under which each servo exerts
/// `torques[i]` while the arm is at trajectory.q[i], trajectory.qdot[i]: the inverse of MuJoCo's
/// affine actuator force, gain ctrl + b0 + b1 length + b2 velocity, times the gear. Feeding the
/// inverse dynamics forward this way removes the servo's tracking lag and gravity sag. Commands
/// are clamped to the actuators' control ranges. Throws Error when an arm actuator is not an
/// affine (position-type) servo.
std::vector<JointVector> servo_commands(const Arm& arm, const JointTrajectory& trajectory,
                                        const std::vector<JointVector>& torques);

}  // namespace proprio::robot
