#include "proprio/sim/scene_description.hpp"

#include <Eigen/Geometry>
#include <cctype>
#include <cmath>
#include <set>
#include <system_error>

#include "proprio/core/error.hpp"

namespace proprio::sim {

namespace {

bool valid_name(const std::string& name) {
  if (name.empty()) return false;
  for (char c : name) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_') return false;
  }
  return true;
}

void require_finite(const Eigen::Ref<const Eigen::VectorXd>& v, const std::string& what) {
  require(v.allFinite(), "scene: " + what + " is not finite");
}

}  // namespace

std::vector<std::string> CameraSpec::camera_names() const {
  if (stereo_baseline > 0.0) return {name + "_left", name + "_right"};
  return {name};
}

void SceneDescription::validate() const {
  require_finite(table.center, "table centre");
  require_finite(table.size, "table size");
  require(table.size.minCoeff() > 0.05 && table.size.maxCoeff() <= 10.0,
          "scene: table size must be in (0.05, 10] metres");
  require(std::isfinite(table.thickness) && table.thickness > 0.0 && table.thickness <= 0.5,
          "scene: table thickness must be in (0, 0.5] metres");
  require(std::isfinite(table.friction) && table.friction > 0.0,
          "scene: table friction must be > 0");
  require(std::isfinite(table.reflectance) && table.reflectance >= 0.0 && table.reflectance <= 1.0,
          "scene: table reflectance must be in [0, 1]");
  if (backdrop.enabled) {
    require_finite(backdrop.center, "backdrop centre");
    require(backdrop.size.allFinite() && backdrop.size.minCoeff() > 0.0,
            "scene: backdrop size must be positive");
    require(backdrop.facing.allFinite() && backdrop.facing.norm() > 1e-9,
            "scene: backdrop facing direction must be a non-zero horizontal vector");
    require(backdrop.texture_width >= 8 && backdrop.texture_width <= 4096 &&
                backdrop.texture_height >= 8 && backdrop.texture_height <= 4096,
            "scene: backdrop texture size must be in [8, 4096] texels");
  }
  require(!cameras.empty(), "scene: no camera");
  std::set<std::string> camera_names_seen;
  for (const CameraSpec& c : cameras) {
    require(valid_name(c.name),
            "scene: camera name '" + c.name + "' must be non-empty letters, digits, '-' or '_'");
    require(c.width >= 16 && c.width <= 8192 && c.height >= 16 && c.height <= 8192,
            "scene: camera '" + c.name + "' image size must be in [16, 8192] pixels");
    require(std::isfinite(c.fovy_deg) && c.fovy_deg > 1.0 && c.fovy_deg < 170.0,
            "scene: camera '" + c.name + "' fovy must be in (1, 170) degrees");
    require_finite(c.position, "camera '" + c.name + "' position");
    require_finite(c.target, "camera '" + c.name + "' target");
    require_finite(c.up, "camera '" + c.name + "' up");
    const Eigen::Vector3d forward = c.target - c.position;
    require(forward.norm() > 1e-6, "scene: camera '" + c.name + "' target equals its position");
    require(forward.normalized().cross(c.up).norm() > 1e-6,
            "scene: camera '" + c.name + "' looks along its up direction");
    require(std::isfinite(c.stereo_baseline) && c.stereo_baseline >= 0.0 && c.stereo_baseline < 5,
            "scene: camera '" + c.name + "' stereo baseline must be in [0, 5) metres");
    for (const std::string& n : c.camera_names()) {
      require(camera_names_seen.insert(n).second, "scene: two cameras are called '" + n + "'");
    }
  }
  require(lights.size() <= 8, "scene: at most 8 lights (OpenGL's fixed-function limit)");
  for (const LightSpec& l : lights) {
    require_finite(l.position, "light position");
    require(l.direction.allFinite() && l.direction.norm() > 1e-9,
            "scene: a light direction must be a non-zero vector");
    require(l.diffuse.allFinite() && l.diffuse.minCoeff() >= 0.0, "scene: light colour < 0");
  }
  for (const PlacedObject& o : objects) {
    require(o.position.allFinite() && std::isfinite(o.yaw),
            "scene: object '" + (o.name.empty() ? o.type : o.name) + "' pose is not finite");
    require(!o.z.has_value() || std::isfinite(*o.z), "scene: object height is not finite");
    require(o.custom.has_value() || !o.type.empty(),
            "scene: an object has neither type nor custom");
    require(o.name.empty() || valid_name(o.name),
            "scene: object name '" + o.name + "' must be letters, digits, '-' or '_'");
  }
  require(objects.size() < kMaxObjects, "scene: too many objects");
  require(std::isfinite(timestep) && timestep >= 1e-5 && timestep <= 0.05,
          "scene: timestep must be in [1e-5, 0.05] seconds");
  require(std::isfinite(ambient) && ambient >= 0.0 && ambient <= 1.0,
          "scene: ambient must be in [0, 1]");
  require(shadow_map_size >= 64 && shadow_map_size <= 8192,
          "scene: shadow_map_size must be in [64, 8192] texels");
  if (!arm_model.empty()) {
    std::error_code ec;
    require(std::filesystem::is_regular_file(arm_model, ec),
            arm_model.string() + ": no such arm model file");
  }
}

SceneDescription default_scene() {
  SceneDescription s;
  const std::filesystem::path data = ObjectCatalogue::default_data_dir();
  s.backdrop.image = ObjectCatalogue::default_texture_dir() / "leuvenA.jpg";
  LightSpec key;  // above and in front of the arm, casting the shadows
  LightSpec fill;
  fill.position = {1.2, -1.0, 1.2};
  fill.direction = {-0.6, 0.6, -0.6};
  fill.diffuse = {0.3, 0.3, 0.3};
  fill.cast_shadow = false;
  s.lights = {key, fill};
  std::error_code ec;
  const std::filesystem::path arm = data / "models" / "arm.xml";
  if (std::filesystem::is_regular_file(arm, ec)) s.arm_model = arm;
  return s;
}

}  // namespace proprio::sim
