#include "proprio/robot/dynamics.hpp"

#include <algorithm>
#include <cmath>

#include "proprio/core/error.hpp"
#include "text.hpp"

namespace proprio::robot {

using detail::cat;

JointVector inverse_dynamics(ArmState& state, const JointVector& q, const JointVector& qdot,
                             const JointVector& qddot) {
  const Arm& arm = state.arm();
  const mjModel& m = arm.model();
  mjData& d = state.data();
  std::fill(d.qvel, d.qvel + m.nv, 0.0);
  std::fill(d.qacc, d.qacc + m.nv, 0.0);
  for (int k = 0; k < kArmJoints; ++k) {
    d.qpos[arm.qpos_adr(k)] = q[k];
    d.qvel[arm.dof_adr(k)] = qdot[k];
    d.qacc[arm.dof_adr(k)] = qddot[k];
  }
  mj_inverse(&m, &d);
  JointVector tau;
  for (int k = 0; k < kArmJoints; ++k) tau[k] = d.qfrc_inverse[arm.dof_adr(k)];
  return tau;
}

std::vector<JointVector> inverse_dynamics(ArmState& state, const JointTrajectory& trajectory) {
  ensure(
      trajectory.qdot.size() == trajectory.size() && trajectory.qddot.size() == trajectory.size(),
      "joint trajectory: q, qdot and qddot differ in length");
  std::vector<JointVector> tau;
  tau.reserve(trajectory.size());
  for (std::size_t i = 0; i < trajectory.size(); ++i) {
    tau.push_back(
        inverse_dynamics(state, trajectory.q[i], trajectory.qdot[i], trajectory.qddot[i]));
  }
  return tau;
}

JointVector gravity_torque(ArmState& state, const JointVector& q) {
  const Arm& arm = state.arm();
  const mjModel& m = arm.model();
  mjData& d = state.data();
  std::fill(d.qvel, d.qvel + m.nv, 0.0);
  for (int k = 0; k < kArmJoints; ++k) d.qpos[arm.qpos_adr(k)] = q[k];
  mj_fwdPosition(&m, &d);
  mj_fwdVelocity(&m, &d);
  JointVector tau;
  for (int k = 0; k < kArmJoints; ++k) tau[k] = d.qfrc_bias[arm.dof_adr(k)];
  return tau;
}

Energy energy(const std::vector<JointVector>& torques, double dt) {
  require(std::isfinite(dt) && dt > 0, "energy: dt must be > 0 s");
  Energy e;
  for (std::size_t i = 0; i < torques.size(); ++i) {
    require(torques[i].allFinite(), "energy: torque is not finite");
    const double w = (i == 0 || i + 1 == torques.size()) ? 0.5 : 1.0;
    e.per_joint += w * dt * torques[i].cwiseAbs();
  }
  if (torques.size() < 2) e.per_joint.setZero();
  e.total = e.per_joint.sum();
  return e;
}

std::vector<JointVector> servo_commands(const Arm& arm, const JointTrajectory& trajectory,
                                        const std::vector<JointVector>& torques) {
  ensure(torques.size() == trajectory.size() && trajectory.qdot.size() == trajectory.size(),
         "servo commands: torques and trajectory differ in length");
  const mjModel& m = arm.model();
  for (int k = 0; k < kArmJoints; ++k) {
    const int a = arm.actuator_id(k);
    if (m.actuator_gaintype[a] != mjGAIN_FIXED || m.actuator_biastype[a] != mjBIAS_AFFINE ||
        m.actuator_dyntype[a] != mjDYN_NONE || m.actuator_gainprm[a * mjNGAIN] == 0 ||
        m.actuator_gear[6 * a] == 0) {
      throw Error::in_file(arm.source(),
                           cat({"actuator '", arm.names().actuators[static_cast<std::size_t>(k)],
                                "' is not a position servo (fixed gain, affine bias)"}));
    }
  }
  std::vector<JointVector> ctrl(trajectory.size());
  for (std::size_t i = 0; i < trajectory.size(); ++i) {
    for (int k = 0; k < kArmJoints; ++k) {
      const int a = arm.actuator_id(k);
      const double gear = m.actuator_gear[6 * a];
      const mjtNum* gain = m.actuator_gainprm + a * mjNGAIN;
      const mjtNum* bias = m.actuator_biasprm + a * mjNBIAS;
      // Joint transmission: length = gear q, velocity = gear qdot, joint torque = gear force.
      const double force = torques[i][k] / gear;
      double u = (force - bias[0] - bias[1] * gear * trajectory.q[i][k] -
                  bias[2] * gear * trajectory.qdot[i][k]) /
                 gain[0];
      if (m.actuator_ctrllimited[a]) {
        u = std::clamp(u, m.actuator_ctrlrange[2 * a], m.actuator_ctrlrange[2 * a + 1]);
      }
      ctrl[i][k] = u;
    }
  }
  return ctrl;
}

}  // namespace proprio::robot
