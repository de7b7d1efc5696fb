#pragma once
// The objects of the thesis's experiments (book, mug, bottle, spirit level, rabbit, CD, calculator,
// giraffe, bike, box), described as compositions of MuJoCo primitives, each covered with one
// photograph so that objects look distinct and carry SIFT features. The catalogue is a JSON file
// (data/objects/catalogue.json, format in data/objects/README.md); user objects use the same
// fields.

#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

#include "proprio/core/json_io.hpp"

namespace proprio::sim {

enum class PartShape { kBox, kCylinder, kCapsule, kSphere, kEllipsoid };

/// "box", "cylinder", "capsule", "sphere", "ellipsoid".
std::string to_string(PartShape shape);

/// One primitive of an object, in the object's frame (metres, z up; the parts place the origin,
/// and ObjectType::bottom() says how high it sits when the object rests on the table).
struct ObjectPart {
  PartShape shape = PartShape::kBox;
  /// MuJoCo's geom size: box half extents (x, y, z); cylinder and capsule (radius, half length
  /// along the part's z); sphere (radius); ellipsoid semi-axes. Unused entries are 0.
  Eigen::Vector3d size = Eigen::Vector3d::Zero();
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  /// Rotation of the part, x-y-z Euler angles in radians (MuJoCo's default euler sequence "xyz").
  Eigen::Vector3d euler = Eigen::Vector3d::Zero();
};

/// A kind of object: its shape, look and physical properties.
struct ObjectType {
  std::string name;
  std::vector<ObjectPart> parts;
  /// The photograph covering the object. Absolute after loading from a catalogue.
  std::filesystem::path texture;
  double mass = 0.2;      ///< kg, spread over the parts by volume
  double friction = 0.8;  ///< sliding friction coefficient against the table and other objects
  /// Side of each texture face in texels (the photograph is cropped to every face's aspect ratio,
  /// so it is not stretched).
  int texture_size = 256;

  /// Height of the lowest point of the parts below the object's origin (>= 0 when the origin is
  /// above the bottom): placing the origin at z = bottom() puts the object on the table.
  [[nodiscard]] double bottom() const;
  /// Radius of a vertical cylinder about the origin containing every part's bounding box (metres;
  /// an upper bound on the footprint, for keeping objects apart).
  [[nodiscard]] double footprint_radius() const;
  /// Half extents of the axis-aligned box around all parts, in the object's frame.
  [[nodiscard]] Eigen::Vector3d half_extents() const;
  /// Centre of that box, in the object's frame.
  [[nodiscard]] Eigen::Vector3d center() const;

  /// Checks sizes, mass, friction and texture size; throws Error naming `where` (a file, or a
  /// description of the source) and the object.
  void validate(const std::string& where) const;
};

/// Parses one object from JSON: {"name", "texture", "mass", "friction", optional "texture_size",
/// and either "shape" + "size" (+ optional "pos", "euler") for one part or "parts": [...] }.
/// Relative texture paths are resolved against `texture_dirs` in order; throws Error naming
/// `file` and the object when a field is missing or wrong or the texture cannot be found.
ObjectType parse_object_type(const core::Json& j, const std::filesystem::path& file,
                             const std::vector<std::filesystem::path>& texture_dirs);

/// The named objects of a catalogue file.
class ObjectCatalogue {
 public:
  ObjectCatalogue() = default;
  explicit ObjectCatalogue(std::vector<ObjectType> types);

  /// Reads a catalogue {"format": "proprio.object_catalogue", "version": 1, "objects": [...]}.
  /// Relative texture paths are looked up beside the file, then in `extra_texture_dirs`
  /// (by default the opencv-doc sample images). Throws Error naming the file.
  static ObjectCatalogue load(const std::filesystem::path& file,
                              std::vector<std::filesystem::path> extra_texture_dirs = {
                                  default_texture_dir()});
  /// data/objects/catalogue.json of default_data_dir().
  static ObjectCatalogue load_default();

  /// The type called `name`; throws Error "unknown object 'NAME' (known: ...)".
  [[nodiscard]] const ObjectType& get(const std::string& name) const;
  [[nodiscard]] bool contains(const std::string& name) const;
  [[nodiscard]] const std::vector<ObjectType>& types() const { return types_; }
  [[nodiscard]] std::vector<std::string> names() const;
  /// Adds a user object; throws Error when the name is taken or the type is invalid.
  void add(ObjectType type);

  /// proprio's data directory: core::data_directory() ($PROPRIO_DATA_DIR, else the installed or
  /// build tree's share/proprio).
  static std::filesystem::path default_data_dir();
  /// The opencv-doc sample images (where the catalogue's photographs come from).
  static std::filesystem::path default_texture_dir();

 private:
  std::vector<ObjectType> types_;
};

}  // namespace proprio::sim
