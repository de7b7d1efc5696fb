#pragma once
// The arm (thesis 3.1.1): a constant model part, Arm, read from an MJCF, and a mutable workspace,
// ArmState, that evaluates forward kinematics and Jacobians with MuJoCo (as Pinocchio's Model and
// Data). The arm and its names are described in docs/formats/arm-model.md.
//
// Frames: the world frame is the robot base frame (metres, z up, +x forward, table top z = 0).
// Joint vectors hold j1..j5 in radians, in the order of ArmNames::joints.

#include <mujoco/mujoco.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <filesystem>
#include <memory>
#include <string>

#include "proprio/robot/mujoco_ptr.hpp"

namespace proprio::robot {

inline constexpr int kArmJoints = 5;
using JointVector = Eigen::Matrix<double, kArmJoints, 1>;
/// d(ee position)/dq, 3 x 5 (eq 3.3).
using PositionJacobian = Eigen::Matrix<double, 3, kArmJoints>;

/// The MJCF names the robot layer relies on (defaults: data/models/arm.xml).
struct ArmNames {
  std::array<std::string, kArmJoints> joints = {"j1", "j2", "j3", "j4", "j5"};
  std::array<std::string, kArmJoints> actuators = {"a1", "a2", "a3", "a4", "a5"};
  std::string ee_site = "ee";
  std::string base_body = "arm_base";
  /// Optional parts: an empty name, or a name the model lacks, leaves the part absent.
  std::array<std::string, 2> gripper_joints = {"g_left", "g_right"};
  std::array<std::string, 2> gripper_actuators = {"ag_left", "ag_right"};
  std::string marker_geom = "marker";
};

/// Kinematic structure read from the model at q = 0, as used by the analytic inverse kinematics
/// (Appendix A): a yaw joint j1 about the vertical, three parallel horizontal pitch joints j2..j4
/// moving the links in one vertical plane through the yaw axis, and a roll joint j5 whose axis
/// passes through the end-effector. Angles in the arm's vertical plane are elevations above the
/// horizontal, positive upwards, measured in (outward, up) coordinates.
struct ArmGeometry {
  bool analytic = false;          ///< the structure above holds (otherwise numerical IK only)
  std::string why_not_analytic;   ///< which check failed, when !analytic
  Eigen::Vector2d base_xy{0, 0};  ///< where the yaw axis meets the table plane, m
  double yaw_sign = 1;            ///< +1 when a positive j1 turns counter-clockwise seen from above
  double yaw_zero = 0;            ///< azimuth of the arm's plane at j1 = 0, rad
  std::array<double, 3> pitch_sign{1, 1, 1};  ///< +1 when a positive j2/j3/j4 raises the link
  Eigen::Vector2d shoulder{0, 0};  ///< j2 axis in (outward, up) coordinates of the plane, m
  double upper_arm = 0;            ///< |j2 -> j3|, m
  double forearm = 0;              ///< |j3 -> j4|, m
  double hand = 0;                 ///< |j4 -> ee|, m
  std::array<double, 3> link_zero{0, 0, 0};  ///< elevation of the three links at q = 0, rad
  double reach = 0;        ///< upper_arm + forearm + hand: farthest ee distance from the shoulder
  double base_radius = 0;  ///< keep-out cylinder around the yaw axis (base and first link), m
  double base_top = 0;     ///< height of that cylinder's top, m
};

/// The constant part of the arm: its MuJoCo model (shared, never modified), the ids of its named
/// parts, joint limits, and its geometry. Cheap to copy. Works on the standalone arm model and on
/// a larger scene that includes arm.xml.
class Arm {
 public:
  /// Loads an MJCF and reads the arm from it. Throws Error naming the file when the model does
  /// not compile or lacks a required part.
  static Arm load(const std::filesystem::path& mjcf, const ArmNames& names = {});

  /// Reads the arm from an already compiled model. `source` names the model in error messages.
  /// Throws Error when a required joint, actuator or site is missing, a joint is not a limited
  /// hinge, or an actuator does not drive its joint.
  explicit Arm(std::shared_ptr<const mjModel> model, const ArmNames& names = {},
               std::string source = "model");

  [[nodiscard]] const mjModel& model() const { return *model_; }
  [[nodiscard]] const std::shared_ptr<const mjModel>& shared_model() const { return model_; }
  [[nodiscard]] const std::string& source() const { return source_; }
  [[nodiscard]] const ArmNames& names() const { return names_; }

  [[nodiscard]] int joint_id(int k) const { return joint_id_[idx(k)]; }
  [[nodiscard]] int qpos_adr(int k) const { return qpos_adr_[idx(k)]; }
  [[nodiscard]] int dof_adr(int k) const { return dof_adr_[idx(k)]; }
  [[nodiscard]] int actuator_id(int k) const { return actuator_id_[idx(k)]; }
  [[nodiscard]] int ee_site() const { return ee_site_; }
  [[nodiscard]] int base_body() const { return base_body_; }
  /// -1 when absent.
  [[nodiscard]] int marker_geom() const { return marker_geom_; }
  [[nodiscard]] bool has_gripper() const { return gripper_joint_id_[0] >= 0; }
  /// Joint and actuator ids of the gripper fingers (left, right); -1 when absent.
  [[nodiscard]] const std::array<int, 2>& gripper_joints() const { return gripper_joint_id_; }
  [[nodiscard]] const std::array<int, 2>& gripper_actuators() const { return gripper_act_id_; }

  /// Joint limits, rad.
  [[nodiscard]] const JointVector& lower() const { return lower_; }
  [[nodiscard]] const JointVector& upper() const { return upper_; }
  [[nodiscard]] bool within_limits(const JointVector& q, double tolerance = 1e-9) const;
  [[nodiscard]] JointVector clamp(const JointVector& q) const;

  [[nodiscard]] const ArmGeometry& geometry() const { return geometry_; }

 private:
  static std::size_t idx(int k) { return static_cast<std::size_t>(k); }
  void read_geometry();

  std::shared_ptr<const mjModel> model_;
  ArmNames names_;
  std::string source_;
  std::array<int, kArmJoints> joint_id_{};
  std::array<int, kArmJoints> qpos_adr_{};
  std::array<int, kArmJoints> dof_adr_{};
  std::array<int, kArmJoints> actuator_id_{};
  std::array<int, 2> gripper_joint_id_{-1, -1};
  std::array<int, 2> gripper_act_id_{-1, -1};
  int ee_site_ = -1;
  int base_body_ = -1;
  int marker_geom_ = -1;
  JointVector lower_ = JointVector::Zero();
  JointVector upper_ = JointVector::Zero();
  ArmGeometry geometry_;
};

/// End-effector pose: the ee site's position and orientation in the world frame. The site's x
/// axis points along the last link (out of the pusher).
struct EePose {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  /// Elevation of the pointing direction above the horizontal, rad (-pi/2 = straight down).
  [[nodiscard]] double pitch() const;
};

/// The mutable workspace of one arm: an mjData for its model. Not thread-safe; use one per thread.
/// Holds a copy of the Arm (which shares the model), so it never dangles.
class ArmState {
 public:
  explicit ArmState(Arm arm);

  [[nodiscard]] const Arm& arm() const { return arm_; }
  [[nodiscard]] mjData& data() { return *data_; }
  [[nodiscard]] const mjData& data() const { return *data_; }

  /// Writes q into qpos (other joints keep their values) and runs mj_kinematics and mj_comPos.
  void set_joints(const JointVector& q);
  /// The arm joints' current qpos.
  [[nodiscard]] JointVector joints() const;

  /// Forward kinematics q -> ee position (eq 3.2), m.
  Eigen::Vector3d ee_position(const JointVector& q);
  /// Forward kinematics q -> ee position and orientation.
  EePose ee_pose(const JointVector& q);
  /// Position Jacobian d(ee)/dq at q (eq 3.3), by mj_jacSite.
  PositionJacobian jacobian(const JointVector& q);
  /// Rotational Jacobian (angular velocity of the ee frame per joint rate) at q.
  PositionJacobian rotation_jacobian(const JointVector& q);

 private:
  Arm arm_;
  DataPtr data_;
};

}  // namespace proprio::robot
