#pragma once
// The simulated world: the compiled MuJoCo model of a scene (constant, shared) and its state
// (mutable), with the ground truth the experiments are scored against: object poses, arm link
// poses, contacts and which object every geom belongs to.
//
// Frames: the world frame is the robot base frame (metres, z up, table top z = 0).

#include <mujoco/mujoco.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "proprio/geometry/camera.hpp"
#include "proprio/robot/arm.hpp"
#include "proprio/robot/mujoco_ptr.hpp"
#include "proprio/sim/object_catalogue.hpp"
#include "proprio/sim/scene_builder.hpp"
#include "proprio/sim/scene_description.hpp"

namespace proprio::sim {

/// A rigid pose in the world frame: x_world = rotation * x_body + position.
using Pose = Eigen::Isometry3d;

/// The pose of one body of the arm.
struct LinkPose {
  std::string body;
  Pose pose;
};

class World {
 public:
  /// Builds the scene (build_scene), compiles it and fills in the textures. Throws Error when the
  /// description is invalid, an object is unknown, a photograph unreadable, or MuJoCo rejects the
  /// model (or warns while compiling it).
  static World build(const SceneDescription& description, const ObjectCatalogue& catalogue);
  /// Compiles an already built scene.
  static World compile(SceneModel scene);

  World(World&&) noexcept;
  World& operator=(World&&) noexcept;
  World(const World&) = delete;
  World& operator=(const World&) = delete;
  ~World();

  // --- model and state -------------------------------------------------------------------------
  [[nodiscard]] const mjModel& model() const { return *model_; }
  /// The model, shared (e.g. with robot::Arm). Only texture data ever changes after build().
  [[nodiscard]] std::shared_ptr<const mjModel> shared_model() const { return model_; }
  [[nodiscard]] mjData& data() { return *data_; }
  [[nodiscard]] const mjData& data() const { return *data_; }
  [[nodiscard]] const SceneModel& scene() const { return scene_; }
  [[nodiscard]] double time() const { return data_->time; }
  [[nodiscard]] double timestep() const { return model_->opt.timestep; }

  /// Advances the physics by `steps` steps of timestep() (mj_step). Throws Error when MuJoCo
  /// reports a warning (unstable simulation, too many contacts...), naming the warning.
  void step(int steps = 1);
  /// Recomputes positions, contacts and sensors without advancing time (mj_forward).
  void forward();
  /// Back to the initial state: objects where the description put them, arm at its reference
  /// configuration, time 0.
  void reset();
  /// MuJoCo's run-time warnings since the last reset (robot::warnings), empty when none.
  [[nodiscard]] std::vector<std::string> warnings() const;

  // --- objects ---------------------------------------------------------------------------------
  [[nodiscard]] const std::vector<SceneObject>& objects() const { return scene_.objects; }
  /// The object called `name`; throws Error "unknown object 'NAME' in the scene (objects: ...)".
  [[nodiscard]] const SceneObject& object(const std::string& name) const;
  /// Object `id` (1..objects().size()); asserts it exists.
  [[nodiscard]] const SceneObject& object(ObjectId id) const;
  /// Pose of the object's frame in the world.
  [[nodiscard]] Pose object_pose(ObjectId id) const;
  /// Moves the object (teleport): sets its free joint to `pose`, zeroes its velocity and runs
  /// mj_forward so that every derived quantity agrees.
  void set_object_pose(ObjectId id, const Pose& pose);
  /// Linear velocity of the object's origin, world frame, m/s.
  [[nodiscard]] Eigen::Vector3d object_velocity(ObjectId id) const;

  /// Mask id of the body, of the geom: an object id, kArmId or kBackgroundId.
  [[nodiscard]] ObjectId body_object_id(int body) const;
  [[nodiscard]] ObjectId geom_object_id(int geom) const;
  /// Geoms of an object (or of the arm for kArmId).
  [[nodiscard]] std::vector<int> geoms_of(ObjectId id) const;

  // --- arm ---------------------------------------------------------------------------------------
  [[nodiscard]] bool has_arm() const { return arm_.has_value(); }
  /// The arm read from this world's model (shares it); asserts has_arm().
  [[nodiscard]] const robot::Arm& arm() const;
  /// Poses of every arm body (arm_base and all its descendants), in model order.
  [[nodiscard]] std::vector<LinkPose> arm_link_poses() const;
  /// Current arm joint angles j1..j5 (rad).
  [[nodiscard]] robot::JointVector arm_joints() const;
  /// Position-actuator targets for j1..j5 (rad), clamped to the joint limits.
  void set_arm_targets(const robot::JointVector& q);
  /// Puts the arm at q at once (qpos and actuator targets), zero joint velocity, then mj_forward.
  void set_arm_configuration(const robot::JointVector& q);
  /// End-effector site position, world (metres).
  [[nodiscard]] Eigen::Vector3d ee_position() const;

  // --- contacts ----------------------------------------------------------------------------------
  /// Whether any geom in `geoms` is in contact with a geom of `body` in the current contact list
  /// (mjData::contact, found by the last step() or forward()).
  [[nodiscard]] bool touching(std::span<const int> geoms, int body) const;
  /// Whether the arm touches object `id` now.
  [[nodiscard]] bool arm_touches(ObjectId id) const;
  /// Ids of the objects the arm touches now (ascending).
  [[nodiscard]] std::vector<ObjectId> objects_touched_by_arm() const;

  // --- grasp (SceneDescription::grasp_object) ---------------------------------------------------
  /// Grasps or releases the scene's grasp object with MuJoCo's weld equality constraint
  /// kGraspConstraint: on, it holds the object's current pose relative to the arm's last link
  /// (the relative pose is written into the model's eq_data, and eq_active set), so that the
  /// physics carries the object with the arm (a soft constraint: it sags a little under load);
  /// off, the object is free again. `anchor` (object frame, m) is the point the weld pins and
  /// set_grasp_rotation turns about. Asserts that the scene has a grasp object. Changes the
  /// model, which is this world's own (the arm shares it, and ignores equality constraints).
  void set_grasp(bool on, const Eigen::Vector3d& anchor = Eigen::Vector3d::Zero());
  /// While grasped: the object held turned by `rotation` (object frame, about the anchor)
  /// relative to its pose at set_grasp(true), as a hand turning it in its fingers would.
  void set_grasp_rotation(const Eigen::Matrix3d& rotation);
  [[nodiscard]] bool grasping() const;

  // --- cameras and textures ----------------------------------------------------------------------
  [[nodiscard]] const std::vector<std::string>& camera_names() const { return scene_.camera_names; }
  /// MuJoCo id of a camera; throws Error naming the unknown camera.
  [[nodiscard]] int camera_id(const std::string& name) const;
  /// Image size of a camera, from its CameraSpec.
  [[nodiscard]] std::pair<int, int> camera_size(const std::string& name) const;
  /// The camera as a pinhole model (camera_from_mujoco) in its current pose.
  [[nodiscard]] geometry::Camera camera(const std::string& name) const;

  /// Replaces the texels of a 2D texture (e.g. kBackdropTexture with a video frame), resizing
  /// `bgr` to the texture's size. The renderer shows it after Renderer::upload_texture. Throws
  /// Error when the texture does not exist or is not 2D, or the image is empty.
  void set_texture_image(const std::string& texture, const cv::Mat& bgr);
  /// MuJoCo id of a texture; throws Error when missing.
  [[nodiscard]] int texture_id(const std::string& name) const;

 private:
  World() = default;
  void index_model();

  SceneModel scene_;
  std::shared_ptr<mjModel> model_;
  Eigen::Quaterniond grasp_relquat_ = Eigen::Quaterniond::Identity();
  robot::DataPtr data_;
  std::optional<robot::Arm> arm_;
  std::vector<ObjectId> body_object_;  // per body
  std::vector<int> object_body_;       // per object id (index 0 unused)
  std::vector<int> object_qpos_;       // qpos address of each object's free joint
  std::vector<int> object_dof_;        // dof address of each object's free joint
  std::vector<int> arm_bodies_;
};

}  // namespace proprio::sim
