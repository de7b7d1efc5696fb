#pragma once
// Turns a SceneDescription into MJCF text plus the texture images that go with it. MuJoCo 2.2
// cannot read JPEG textures and would smear a 2D texture over a box, so objects get cube textures
// (one face per side of the object, texel data filled in after compilation from these images).

#include <cstdint>
#include <filesystem>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "proprio/sim/object_catalogue.hpp"
#include "proprio/sim/scene_description.hpp"

namespace proprio::sim {

/// Object ids in masks and in World: 0 is background (table, backdrop, floor), objects count from
/// 1 in the order of SceneDescription::objects, the arm (every body below `arm_base`) is kArmId.
using ObjectId = std::uint16_t;
inline constexpr ObjectId kBackgroundId = 0;
inline constexpr ObjectId kArmId = 0xFFFF;

/// The MuJoCo body name of an object instance.
std::string object_body_name(const std::string& instance_name);

/// One object as built into the scene.
struct SceneObject {
  ObjectId id = 0;
  std::string name;  ///< unique instance name
  ObjectType type;   ///< its type, with the texture path resolved
  std::string body;  ///< MuJoCo body name (object_body_name(name))
  Eigen::Vector3d initial_position = Eigen::Vector3d::Zero();  ///< world, metres
  double initial_yaw = 0.0;                                    ///< radians about world z
};

/// Texel data for one texture of the model, laid out as MuJoCo stores it: RGB rows top to bottom;
/// cube textures are 6 square faces stacked (+x, -x, +y, -y, +z, -z).
struct TextureData {
  std::string name;
  cv::Mat rgb;  ///< CV_8UC3 in RGB order
};

struct SceneModel {
  std::string xml;  ///< the MJCF document
  std::vector<TextureData> textures;
  std::vector<SceneObject> objects;
  std::vector<std::string> camera_names;
  SceneDescription description;  ///< what it was built from (validated)
};

/// Builds the scene: validates the description, resolves object types (unknown type names throw
/// Error "unknown object 'NAME' (known: ...)"), reads and lays out every photograph (an
/// unreadable image throws Error naming the file) and writes the MJCF.
SceneModel build_scene(const SceneDescription& description, const ObjectCatalogue& catalogue);

/// The six faces of a cube texture for an object whose axis-aligned half extents are
/// `half_extents`: the photograph is centre-cropped to each face's aspect ratio (so that it is not
/// stretched on the face) and resized to face_size x face_size. Result: 6*face_size rows, RGB.
cv::Mat cube_texture(const cv::Mat& bgr_photo, const Eigen::Vector3d& half_extents, int face_size);

/// Reads an image as BGR; throws Error naming the file when it is missing or not an image.
cv::Mat read_image(const std::filesystem::path& path);

}  // namespace proprio::sim
