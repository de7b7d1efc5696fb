#pragma once
// What a simulated world contains: the table, the arm, the objects on the table, lights, cameras
// and a backdrop. Frames: the world frame is the robot base frame (metres, z up); the table top is
// the plane z = 0 and the arm works over it toward +x.

#include <Eigen/Core>
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "proprio/sim/object_catalogue.hpp"

namespace proprio::sim {

struct TableSpec {
  Eigen::Vector2d center{0.30, 0.0};  ///< centre of the top, world x y (metres)
  Eigen::Vector2d size{1.10, 1.00};   ///< full extent along x and y (metres)
  double thickness = 0.04;            ///< the top is z = 0, the underside z = -thickness
  Eigen::Vector3d rgb{0.72, 0.60, 0.45};
  double friction = 0.8;
  /// Mirror-like reflection of the top (MuJoCo material reflectance, 0..1; shown only when the
  /// renderer draws reflections).
  double reflectance = 0.08;
};

/// A vertical plane behind the table seen past the objects; a photograph or, frame by frame, a
/// video (World::set_texture_image on kBackdropTexture).
struct BackdropSpec {
  bool enabled = true;
  Eigen::Vector3d center{0.30, 0.62, 0.45};  ///< world position of the plane's centre (metres)
  Eigen::Vector2d size{2.40, 1.35};          ///< full width and height (metres)
  /// Horizontal direction the plane faces (toward the camera), normalised on use.
  Eigen::Vector2d facing{0.0, -1.0};
  std::filesystem::path image;  ///< empty = grey; relative paths as for object textures
  int texture_width = 512;      ///< texels; a video background is resized to this
  int texture_height = 288;
};

struct CameraSpec {
  std::string name = "camera";
  int width = 640;
  int height = 480;
  double fovy_deg = 45.0;                       ///< vertical field of view (MuJoCo's fovy)
  Eigen::Vector3d position{0.35, -0.80, 0.60};  ///< optical centre, world (metres)
  Eigen::Vector3d target{0.35, 0.05, 0.0};      ///< point on the optical axis
  Eigen::Vector3d up{0.0, 0.0, 1.0};            ///< world direction that appears up in the image
  /// > 0: a stereo pair NAME_left (at `position`) and NAME_right (shifted by the baseline along
  /// the image x axis), parallel optical axes; 0: one camera called NAME.
  double stereo_baseline = 0.0;

  /// Names of the MuJoCo cameras this spec makes.
  [[nodiscard]] std::vector<std::string> camera_names() const;
};

struct LightSpec {
  Eigen::Vector3d position{0.3, -0.3, 1.6};
  Eigen::Vector3d direction{0.0, 0.15, -1.0};
  Eigen::Vector3d diffuse{0.7, 0.7, 0.7};
  bool directional = false;
  bool cast_shadow = true;
};

/// An object of the scene: an instance of a catalogue type (or a user type) resting on the table.
struct PlacedObject {
  std::string type;  ///< catalogue name; ignored when `custom` is set
  std::string name;  ///< unique instance name; empty = the type's name (numbered if repeated)
  Eigen::Vector2d position = Eigen::Vector2d::Zero();  ///< world x y of the object's origin
  double yaw = 0.0;                                    ///< rotation about world z (radians)
  /// Height of the origin above the table; empty = resting on the table (ObjectType::bottom()).
  std::optional<double> z;
  std::optional<ObjectType> custom;
  /// Felt by the table only: it passes through the other objects and the arm (a scripted
  /// distractor, moved by its script rather than by contacts). Its geoms get MuJoCo contype 4,
  /// conaffinity 0; the table's plane has conaffinity 5 (the arm has contype 2).
  bool ghost = false;
};

/// Texture names in the compiled model (for World::set_texture_image).
inline constexpr const char* kBackdropTexture = "backdrop";
/// The weld equality constraint of a grasp (SceneDescription::grasp_object) and the arm body it
/// holds the object with (the last link: palm and pusher).
inline constexpr const char* kGraspConstraint = "grasp";
inline constexpr const char* kGraspArmBody = "arm_link5";
/// Object ids are 16-bit mask values with the top one reserved for the arm.
inline constexpr std::size_t kMaxObjects = 1000;

struct SceneDescription {
  TableSpec table;
  BackdropSpec backdrop;
  std::vector<CameraSpec> cameras{CameraSpec{}};
  std::vector<LightSpec> lights{LightSpec{}};
  std::vector<PlacedObject> objects;
  /// The arm's MJCF fragment (<include>d; its own includes resolve relative to its directory);
  /// empty = no arm.
  std::filesystem::path arm_model;
  /// Instance name of an object the arm can grasp (hold-3d): the model gets a weld equality
  /// constraint "grasp" between the arm's last link and that object, inactive until
  /// World::set_grasp turns it on. Empty = none. Needs the arm.
  std::string grasp_object;
  double timestep = 0.002;  ///< physics step (seconds)
  /// Ambient light of MuJoCo's headlight (0..1 per channel); the rest comes from `lights`.
  double ambient = 0.25;
  /// Side of the shadow map in texels: sharper shadows cost time (software GL renders the map
  /// every frame: 1024 -> ~5 ms, 4096 -> ~80 ms at 640x480).
  int shadow_map_size = 1024;

  /// Checks sizes, names and numbers; throws Error naming the problem.
  void validate() const;
};

/// The default world: table, backdrop (leuvenA.jpg), one 640x480 camera looking at the workspace
/// in front of the arm, two lights, data/models/arm.xml when it exists, no objects.
SceneDescription default_scene();

}  // namespace proprio::sim
