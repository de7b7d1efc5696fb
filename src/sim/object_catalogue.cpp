#include "proprio/sim/object_catalogue.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <system_error>
#include <utility>

#include "proprio/core/data_dir.hpp"
#include "proprio/core/error.hpp"

namespace proprio::sim {

namespace fs = std::filesystem;

std::string to_string(PartShape shape) {
  switch (shape) {
    case PartShape::kBox:
      return "box";
    case PartShape::kCylinder:
      return "cylinder";
    case PartShape::kCapsule:
      return "capsule";
    case PartShape::kSphere:
      return "sphere";
    case PartShape::kEllipsoid:
      return "ellipsoid";
  }
  return "?";
}

namespace {

// Rotation of MuJoCo's default euler sequence "xyz" (intrinsic rotations about x, then the new y,
// then the new z).
Eigen::Matrix3d euler_xyz(const Eigen::Vector3d& e) {
  return (Eigen::AngleAxisd(e.x(), Eigen::Vector3d::UnitX()) *
          Eigen::AngleAxisd(e.y(), Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(e.z(), Eigen::Vector3d::UnitZ()))
      .toRotationMatrix();
}

// Half extents of the part's own bounding box, in the part frame.
Eigen::Vector3d part_local_half_extents(const ObjectPart& p) {
  const Eigen::Vector3d& s = p.size;
  switch (p.shape) {
    case PartShape::kBox:
    case PartShape::kEllipsoid:
      return s;
    case PartShape::kCylinder:
      return {s.x(), s.x(), s.y()};
    case PartShape::kCapsule:
      return {s.x(), s.x(), s.y() + s.x()};
    case PartShape::kSphere:
      return {s.x(), s.x(), s.x()};
  }
  return s;
}

// Half extents of the part's bounding box in the object frame (rotated box around the part).
Eigen::Vector3d part_half_extents(const ObjectPart& p) {
  return euler_xyz(p.euler).cwiseAbs() * part_local_half_extents(p);
}

PartShape parse_shape(const std::string& name, const fs::path& file, const std::string& object) {
  for (PartShape s : {PartShape::kBox, PartShape::kCylinder, PartShape::kCapsule,
                      PartShape::kSphere, PartShape::kEllipsoid}) {
    if (to_string(s) == name) return s;
  }
  throw Error::in_file(file, "object '" + object + "': unknown shape '" + name +
                                 "' (expected box, cylinder, capsule, sphere or ellipsoid)");
}

Eigen::Vector3d parse_vector(const core::Json& j, const std::string& key, std::size_t min_size,
                             const fs::path& file, const std::string& object) {
  const auto it = j.find(key);
  const std::string where = "object '" + object + "': '" + key + "'";
  if (it == j.end() || !it->is_array() || it->size() < min_size || it->size() > 3) {
    throw Error::in_file(file, where + " must be an array of " + std::to_string(min_size) +
                                   (min_size < 3 ? " to 3" : "") + " numbers");
  }
  Eigen::Vector3d v = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < it->size(); ++i) {
    if (!(*it)[i].is_number()) throw Error::in_file(file, where + " must hold numbers");
    v[static_cast<Eigen::Index>(i)] = (*it)[i].get<double>();
    if (!std::isfinite(v[static_cast<Eigen::Index>(i)])) {
      throw Error::in_file(file, where + " is not finite");
    }
  }
  return v;
}

ObjectPart parse_part(const core::Json& j, const fs::path& file, const std::string& object) {
  ObjectPart part;
  part.shape = parse_shape(core::json_get<std::string>(j, "shape", file), file, object);
  part.size = parse_vector(j, "size", 1, file, object);
  if (j.contains("pos")) part.position = parse_vector(j, "pos", 3, file, object);
  if (j.contains("euler")) part.euler = parse_vector(j, "euler", 3, file, object);
  return part;
}

std::size_t size_entries(PartShape shape) {
  switch (shape) {
    case PartShape::kBox:
    case PartShape::kEllipsoid:
      return 3;
    case PartShape::kCylinder:
    case PartShape::kCapsule:
      return 2;
    case PartShape::kSphere:
      return 1;
  }
  return 3;
}

}  // namespace

double ObjectType::bottom() const {
  double lowest = 0.0;
  bool first = true;
  for (const ObjectPart& p : parts) {
    const double z = p.position.z() - part_half_extents(p).z();
    lowest = first ? z : std::min(lowest, z);
    first = false;
  }
  return -lowest;
}

double ObjectType::footprint_radius() const {
  double r = 0.0;
  for (const ObjectPart& p : parts) {
    const Eigen::Vector3d h = part_half_extents(p);
    r = std::max(r, std::hypot(std::abs(p.position.x()) + h.x(), std::abs(p.position.y()) + h.y()));
  }
  return r;
}

namespace {

// The axis-aligned box around all parts: (low corner, high corner), object frame.
std::pair<Eigen::Vector3d, Eigen::Vector3d> bounds(const std::vector<ObjectPart>& parts) {
  Eigen::Vector3d lo = Eigen::Vector3d::Zero();
  Eigen::Vector3d hi = Eigen::Vector3d::Zero();
  bool first = true;
  for (const ObjectPart& p : parts) {
    const Eigen::Vector3d h = part_half_extents(p);
    lo = first ? Eigen::Vector3d(p.position - h) : lo.cwiseMin(p.position - h);
    hi = first ? Eigen::Vector3d(p.position + h) : hi.cwiseMax(p.position + h);
    first = false;
  }
  return {lo, hi};
}

}  // namespace

Eigen::Vector3d ObjectType::half_extents() const {
  const auto [lo, hi] = bounds(parts);
  return 0.5 * (hi - lo);
}

Eigen::Vector3d ObjectType::center() const {
  const auto [lo, hi] = bounds(parts);
  return 0.5 * (hi + lo);
}

void ObjectType::validate(const std::string& where) const {
  const std::string what = where + ": object '" + name + "': ";
  require(!name.empty(), where + ": an object has no name");
  for (char c : name) {
    const bool ok = std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_';
    require(ok, what + "names may hold only letters, digits, '-' and '_'");
  }
  require(!parts.empty(), what + "has no parts");
  for (const ObjectPart& p : parts) {
    for (Eigen::Index i = 0; i < static_cast<Eigen::Index>(size_entries(p.shape)); ++i) {
      require(std::isfinite(p.size[i]) && p.size[i] > 0.0 && p.size[i] <= 2.0,
              what + to_string(p.shape) + " size must be in (0, 2] metres");
    }
    require(p.position.allFinite() && p.euler.allFinite(), what + "part pose is not finite");
  }
  require(std::isfinite(mass) && mass > 0.0 && mass <= 100.0, what + "mass must be in (0, 100] kg");
  require(std::isfinite(friction) && friction > 0.0 && friction <= 5.0,
          what + "friction must be in (0, 5]");
  require(texture_size >= 8 && texture_size <= 2048, what + "texture_size must be in [8, 2048]");
  require(!texture.empty(), what + "has no texture");
}

ObjectType parse_object_type(const core::Json& j, const fs::path& file,
                             const std::vector<fs::path>& texture_dirs) {
  if (!j.is_object()) throw Error::in_file(file, "an object must be a JSON object");
  ObjectType type;
  type.name = core::json_get<std::string>(j, "name", file);
  if (j.contains("parts")) {
    const core::Json& parts = j.at("parts");
    if (!parts.is_array() || parts.empty()) {
      throw Error::in_file(file, "object '" + type.name + "': 'parts' must be a non-empty array");
    }
    for (const core::Json& p : parts) type.parts.push_back(parse_part(p, file, type.name));
  } else {
    type.parts.push_back(parse_part(j, file, type.name));
  }
  for (const ObjectPart& p : type.parts) {
    // A size array shorter than the shape needs leaves zeros, caught here with the object named.
    for (Eigen::Index i = 0; i < static_cast<Eigen::Index>(size_entries(p.shape)); ++i) {
      if (p.size[i] <= 0.0) {
        throw Error::in_file(file, "object '" + type.name + "': a " + to_string(p.shape) +
                                       " needs " + std::to_string(size_entries(p.shape)) +
                                       " positive size entries");
      }
    }
  }
  type.mass = core::json_get<double>(j, "mass", file);
  type.friction = core::json_get<double>(j, "friction", file);
  if (j.contains("texture_size")) type.texture_size = core::json_get<int>(j, "texture_size", file);

  const fs::path texture = core::json_get<std::string>(j, "texture", file);
  if (texture.is_absolute()) {
    type.texture = texture;
  } else {
    std::string looked;
    for (const fs::path& dir : texture_dirs) {
      std::error_code ec;
      if (fs::is_regular_file(dir / texture, ec)) {
        type.texture = dir / texture;
        break;
      }
      looked += looked.empty() ? "" : ", ";
      looked += dir.string();
    }
    if (type.texture.empty()) {
      throw Error::in_file(file, "object '" + type.name + "': texture '" + texture.string() +
                                     "' not found (looked in " + looked + ")");
    }
  }
  type.validate(file.string());
  return type;
}

ObjectCatalogue::ObjectCatalogue(std::vector<ObjectType> types) {
  for (ObjectType& t : types) add(std::move(t));
}

ObjectCatalogue ObjectCatalogue::load(const fs::path& file,
                                      std::vector<fs::path> extra_texture_dirs) {
  const core::Json j = core::read_json(file);
  const auto format = core::json_get<std::string>(j, "format", file);
  if (format != "proprio.object_catalogue") {
    throw Error::in_file(file, "format is '" + format + "', expected 'proprio.object_catalogue'");
  }
  const int version = core::json_get<int>(j, "version", file);
  if (version != 1) {
    throw Error::in_file(file, "unsupported catalogue version " + std::to_string(version));
  }
  const auto objects = j.find("objects");
  if (objects == j.end() || !objects->is_array()) {
    throw Error::in_file(file, "'objects' must be an array");
  }
  std::vector<fs::path> dirs{file.parent_path().empty() ? fs::path(".") : file.parent_path()};
  dirs.insert(dirs.end(), extra_texture_dirs.begin(), extra_texture_dirs.end());
  ObjectCatalogue catalogue;
  for (const core::Json& o : *objects) {
    ObjectType type = parse_object_type(o, file, dirs);
    if (catalogue.contains(type.name)) {
      throw Error::in_file(file, "object '" + type.name + "' is defined twice");
    }
    catalogue.types_.push_back(std::move(type));
  }
  return catalogue;
}

ObjectCatalogue ObjectCatalogue::load_default() {
  return load(default_data_dir() / "objects" / "catalogue.json");
}

const ObjectType& ObjectCatalogue::get(const std::string& name) const {
  for (const ObjectType& t : types_) {
    if (t.name == name) return t;
  }
  std::string known;
  for (const ObjectType& t : types_) {
    known += known.empty() ? "" : ", ";
    known += t.name;
  }
  throw Error("unknown object '" + name + "' (known: " + (known.empty() ? "none" : known) + ")");
}

bool ObjectCatalogue::contains(const std::string& name) const {
  return std::any_of(types_.begin(), types_.end(),
                     [&](const ObjectType& t) { return t.name == name; });
}

std::vector<std::string> ObjectCatalogue::names() const {
  std::vector<std::string> out;
  out.reserve(types_.size());
  for (const ObjectType& t : types_) out.push_back(t.name);
  return out;
}

void ObjectCatalogue::add(ObjectType type) {
  type.validate("object catalogue");
  require(!contains(type.name), "object '" + type.name + "' is already in the catalogue");
  types_.push_back(std::move(type));
}

fs::path ObjectCatalogue::default_data_dir() { return core::data_directory(); }

fs::path ObjectCatalogue::default_texture_dir() { return PROPRIO_SIM_TEXTURE_DIR; }

}  // namespace proprio::sim
