#include "proprio/sim/scene_builder.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <numbers>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <system_error>

#include "proprio/core/error.hpp"
#include "proprio/core/text.hpp"
#include "proprio/geometry/image_file.hpp"

namespace proprio::sim {

namespace fs = std::filesystem;

namespace {

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

std::string vec(const Eigen::Ref<const Eigen::VectorXd>& v) {
  std::string out;
  for (Eigen::Index i = 0; i < v.size(); ++i) {
    if (i > 0) out += ' ';
    out += num(v[i]);
  }
  return out;
}

double deg(double rad) { return rad * 180.0 / std::numbers::pi; }

double part_volume(const ObjectPart& p) {
  const Eigen::Vector3d& s = p.size;
  constexpr double kPi = std::numbers::pi;
  switch (p.shape) {
    case PartShape::kBox:
      return 8.0 * s.x() * s.y() * s.z();
    case PartShape::kCylinder:
      return kPi * s.x() * s.x() * 2.0 * s.y();
    case PartShape::kCapsule:
      return kPi * s.x() * s.x() * 2.0 * s.y() + 4.0 / 3.0 * kPi * std::pow(s.x(), 3);
    case PartShape::kSphere:
      return 4.0 / 3.0 * kPi * std::pow(s.x(), 3);
    case PartShape::kEllipsoid:
      return 4.0 / 3.0 * kPi * s.x() * s.y() * s.z();
  }
  return 0.0;
}

std::string geom_size(const ObjectPart& p) {
  switch (p.shape) {
    case PartShape::kBox:
    case PartShape::kEllipsoid:
      return vec(p.size);
    case PartShape::kCylinder:
    case PartShape::kCapsule:
      return vec(p.size.head<2>());
    case PartShape::kSphere:
      return num(p.size.x());
  }
  return vec(p.size);
}

// MuJoCo camera axes (x right, y up in the image; the camera looks along -z) for a camera at
// `position` looking at `target`.
std::pair<Eigen::Vector3d, Eigen::Vector3d> camera_axes(const CameraSpec& c) {
  const Eigen::Vector3d forward = (c.target - c.position).normalized();
  const Eigen::Vector3d x = forward.cross(c.up).normalized();
  const Eigen::Vector3d y = x.cross(forward);
  return {x, y};
}

// Texture data from a photograph, resized to width x height, RGB.
cv::Mat rgb_texture(const cv::Mat& bgr, int width, int height) {
  cv::Mat resized;
  cv::resize(bgr, resized, cv::Size(width, height), 0, 0, cv::INTER_AREA);
  cv::Mat rgb;
  cv::cvtColor(resized, rgb, cv::COLOR_BGR2RGB);
  return rgb;
}

ObjectType resolve_type(const PlacedObject& o, const ObjectCatalogue& catalogue) {
  if (!o.custom) return catalogue.get(o.type);
  ObjectType t = *o.custom;
  if (!t.texture.empty() && t.texture.is_relative()) {
    std::error_code ec;
    if (!fs::is_regular_file(t.texture, ec) &&
        fs::is_regular_file(ObjectCatalogue::default_texture_dir() / t.texture, ec)) {
      t.texture = ObjectCatalogue::default_texture_dir() / t.texture;
    }
  }
  t.validate("scene");
  return t;
}

}  // namespace

std::string object_body_name(const std::string& instance_name) { return "obj_" + instance_name; }

cv::Mat read_image(const fs::path& path) { return geometry::read_image(path, cv::IMREAD_COLOR); }

cv::Mat cube_texture(const cv::Mat& bgr_photo, const Eigen::Vector3d& half_extents, int face_size) {
  assert(!bgr_photo.empty() && bgr_photo.type() == CV_8UC3 && face_size > 0);
  // (horizontal, vertical) extent of each face, seen from outside, in MuJoCo's cube order
  // +x, -x, +y, -y, +z, -z.
  const Eigen::Vector3d e = half_extents.cwiseMax(1e-6);
  const std::array<std::pair<double, double>, 6> faces = {{{e.y(), e.z()},
                                                           {e.y(), e.z()},
                                                           {e.x(), e.z()},
                                                           {e.x(), e.z()},
                                                           {e.x(), e.y()},
                                                           {e.x(), e.y()}}};
  cv::Mat out(6 * face_size, face_size, CV_8UC3);
  for (std::size_t k = 0; k < faces.size(); ++k) {
    const double aspect = faces[k].first / faces[k].second;  // width / height of the face
    const double photo_aspect = static_cast<double>(bgr_photo.cols) / bgr_photo.rows;
    cv::Rect crop(0, 0, bgr_photo.cols, bgr_photo.rows);
    if (photo_aspect > aspect) {
      crop.width = std::max(1, static_cast<int>(std::lround(bgr_photo.rows * aspect)));
      crop.x = (bgr_photo.cols - crop.width) / 2;
    } else {
      crop.height = std::max(1, static_cast<int>(std::lround(bgr_photo.cols / aspect)));
      crop.y = (bgr_photo.rows - crop.height) / 2;
    }
    const cv::Mat upright = rgb_texture(bgr_photo(crop), face_size, face_size);
    // MuJoCo samples cube textures as an OpenGL cube map indexed by the direction in the geom
    // frame; OpenGL's face layouts are meant to be seen from inside the cube. Turn each face so
    // that seen from outside it shows the photograph upright (side faces: image up = +z; top and
    // bottom: image up = +y) and unmirrored.
    cv::Mat face;
    switch (k) {
      case 0:  // +x: texture columns run along -z, rows along -y
        cv::flip(upright, face, 1);
        cv::transpose(face, face);
        break;
      case 1:  // -x: columns along +z, rows along -y
        cv::flip(upright, face, 0);
        cv::transpose(face, face);
        break;
      case 2:  // +y: columns along +x, rows along +z
        cv::flip(upright, face, -1);
        break;
      default:  // -y, +z, -z: already as seen from outside
        face = upright;
    }
    face.copyTo(out.rowRange(static_cast<int>(k) * face_size, static_cast<int>(k + 1) * face_size));
  }
  return out;
}

SceneModel build_scene(const SceneDescription& description, const ObjectCatalogue& catalogue) {
  description.validate();
  SceneModel scene;
  scene.description = description;
  const SceneDescription& d = description;

  // Objects: resolve types and unique instance names first (errors before any work).
  std::map<std::string, int> type_count;
  for (const PlacedObject& o : d.objects) ++type_count[o.custom ? o.custom->name : o.type];
  std::map<std::string, int> type_seen;
  for (std::size_t i = 0; i < d.objects.size(); ++i) {
    const PlacedObject& o = d.objects[i];
    SceneObject so;
    so.type = resolve_type(o, catalogue);
    so.id = static_cast<ObjectId>(i + 1);
    if (!o.name.empty()) {
      so.name = o.name;
    } else {
      const int n = ++type_seen[so.type.name];
      so.name =
          type_count[so.type.name] > 1 ? so.type.name + "_" + std::to_string(n) : so.type.name;
    }
    for (const SceneObject& other : scene.objects) {
      require(other.name != so.name, "scene: two objects are called '" + so.name + "'");
    }
    so.body = object_body_name(so.name);
    so.initial_position = {o.position.x(), o.position.y(), o.z.value_or(so.type.bottom())};
    so.initial_yaw = o.yaw;
    scene.objects.push_back(std::move(so));
  }

  int offwidth = 0;
  int offheight = 0;
  for (const CameraSpec& c : d.cameras) {
    offwidth = std::max(offwidth, c.width);
    offheight = std::max(offheight, c.height);
    for (const std::string& n : c.camera_names()) scene.camera_names.push_back(n);
  }

  std::ostringstream x;
  x << "<mujoco model=\"proprio_scene\">\n";
  if (!d.arm_model.empty()) {
    // The arm's own file references resolve beside it.
    const std::string dir =
        core::markup_escape(fs::absolute(d.arm_model).parent_path().string() + "/");
    x << "  <compiler meshdir=\"" << dir << "\" texturedir=\"" << dir << "\"/>\n";
  }
  x << "  <option timestep=\"" << num(d.timestep) << "\"/>\n";
  // No multisampling: the segmentation pass must give every pixel one geom's exact id colour.
  x << "  <visual>\n"
    << "    <global offwidth=\"" << offwidth << "\" offheight=\"" << offheight << "\"/>\n"
    << "    <quality offsamples=\"0\" shadowsize=\"" << d.shadow_map_size << "\"/>\n"
    << "    <headlight ambient=\"" << vec(Eigen::Vector3d::Constant(d.ambient))
    << "\" diffuse=\"0.15 0.15 0.15\" specular=\"0 0 0\"/>\n"
    << "    <map znear=\"0.02\" zfar=\"20\"/>\n"
    << "  </visual>\n";
  // extent 1: the near and far planes above are in metres.
  x << "  <statistic extent=\"1\" center=\""
    << vec(Eigen::Vector3d(d.table.center.x(), d.table.center.y(), 0.2)) << "\"/>\n";

  x << "  <asset>\n";
  x << "    <material name=\"table\" rgba=\"" << vec(d.table.rgb) << " 1\" reflectance=\""
    << num(d.table.reflectance) << "\" specular=\"0.2\" shininess=\"0.3\"/>\n";
  x << "    <material name=\"floor\" rgba=\"0.35 0.35 0.38 1\" specular=\"0\"/>\n";
  if (d.backdrop.enabled) {
    x << "    <texture name=\"" << kBackdropTexture << "\" type=\"2d\" builtin=\"flat\" width=\""
      << d.backdrop.texture_width << "\" height=\"" << d.backdrop.texture_height
      << "\" rgb1=\"0.6 0.6 0.6\"/>\n";
    // Partly emissive: a wall behind the table is lit by the room, not by the table's lamps.
    x << "    <material name=\"backdrop\" texture=\"" << kBackdropTexture
      << "\" texrepeat=\"1 1\" emission=\"0.4\" specular=\"0\"/>\n";
    cv::Mat image;
    if (d.backdrop.image.empty()) {
      image = cv::Mat(d.backdrop.texture_height, d.backdrop.texture_width, CV_8UC3,
                      cv::Scalar(150, 150, 150));
    } else {
      image = rgb_texture(read_image(d.backdrop.image), d.backdrop.texture_width,
                          d.backdrop.texture_height);
    }
    scene.textures.push_back({kBackdropTexture, image});
  }
  for (const SceneObject& o : scene.objects) {
    const int s = o.type.texture_size;
    x << "    <texture name=\"tex_" << o.name << "\" type=\"cube\" builtin=\"flat\" width=\"" << s
      << "\" height=\"" << s << "\" rgb1=\"0.5 0.5 0.5\"/>\n";
    x << "    <material name=\"mat_" << o.name << "\" texture=\"tex_" << o.name
      << "\" specular=\"0.25\" shininess=\"0.4\"/>\n";
    scene.textures.push_back(
        {"tex_" + o.name, cube_texture(read_image(o.type.texture), o.type.half_extents(), s)});
  }
  x << "  </asset>\n";

  if (!d.arm_model.empty()) {
    x << "  <include file=\"" << core::markup_escape(fs::absolute(d.arm_model).string())
      << "\"/>\n";
  }

  x << "  <worldbody>\n";
  for (std::size_t i = 0; i < d.lights.size(); ++i) {
    const LightSpec& l = d.lights[i];
    x << "    <light name=\"light" << i << "\" pos=\"" << vec(l.position) << "\" dir=\""
      << vec(l.direction.normalized()) << "\" diffuse=\"" << vec(l.diffuse)
      << "\" specular=\"0.2 0.2 0.2\" directional=\"" << (l.directional ? "true" : "false")
      << "\" castshadow=\"" << (l.cast_shadow ? "true" : "false") << "\" cutoff=\"70\"/>\n";
  }

  // Table: a box whose top is z = 0 (seen) over a plane at z = 0 (felt). The plane gives resting
  // objects several contacts (MuJoCo's box-cylinder test gives only one) and is hidden in group 3.
  const TableSpec& t = d.table;
  const double table_height = 0.75;
  x << "    <geom name=\"table_top\" type=\"box\" size=\""
    << vec(Eigen::Vector3d(t.size.x() / 2, t.size.y() / 2, t.thickness / 2)) << "\" pos=\""
    << vec(Eigen::Vector3d(t.center.x(), t.center.y(), -t.thickness / 2))
    << "\" material=\"table\" contype=\"0\" conaffinity=\"0\"/>\n";
  x << "    <geom name=\"table_plane\" type=\"plane\" size=\""
    << vec(Eigen::Vector3d(t.size.x() / 2, t.size.y() / 2, 0.01)) << "\" pos=\""
    << vec(Eigen::Vector3d(t.center.x(), t.center.y(), 0.0)) << "\" group=\"3\" friction=\""
    << num(t.friction) << " 0.005 0.0001\" rgba=\"1 1 1 0\" contype=\"1\" conaffinity=\"5\"/>\n";
  for (int k = 0; k < 4; ++k) {
    const double sx = (k % 2 == 0 ? 1.0 : -1.0) * (t.size.x() / 2 - 0.05);
    const double sy = (k / 2 == 0 ? 1.0 : -1.0) * (t.size.y() / 2 - 0.05);
    const double leg = (table_height - t.thickness) / 2;
    x << "    <geom name=\"table_leg" << k << "\" type=\"box\" size=\"0.025 0.025 " << num(leg)
      << "\" pos=\""
      << vec(Eigen::Vector3d(t.center.x() + sx, t.center.y() + sy, -t.thickness - leg))
      << "\" material=\"table\" contype=\"0\" conaffinity=\"0\"/>\n";
  }
  x << "    <geom name=\"floor\" type=\"plane\" size=\"4 4 0.1\" pos=\"" << num(t.center.x()) << " "
    << num(t.center.y()) << " " << num(-table_height)
    << "\" material=\"floor\" contype=\"0\" conaffinity=\"0\"/>\n";

  if (d.backdrop.enabled) {
    const BackdropSpec& b = d.backdrop;
    const Eigen::Vector2d f = b.facing.normalized();
    // Plane x axis horizontal (image right when seen from the front), y axis up, normal = facing.
    const Eigen::Vector3d bx(-f.y(), f.x(), 0.0);
    x << "    <geom name=\"backdrop\" type=\"plane\" size=\""
      << vec(Eigen::Vector3d(b.size.x() / 2, b.size.y() / 2, 0.01)) << "\" pos=\"" << vec(b.center)
      << "\" xyaxes=\"" << vec(bx) << " 0 0 1\" material=\"backdrop\""
      << " contype=\"0\" conaffinity=\"0\"/>\n";
  }

  for (const CameraSpec& c : d.cameras) {
    const auto [cx, cy] = camera_axes(c);
    const std::vector<std::string> names = c.camera_names();
    for (std::size_t k = 0; k < names.size(); ++k) {
      const Eigen::Vector3d pos = c.position + static_cast<double>(k) * c.stereo_baseline * cx;
      x << "    <camera name=\"" << names[k] << "\" pos=\"" << vec(pos) << "\" xyaxes=\"" << vec(cx)
        << " " << vec(cy) << "\" fovy=\"" << num(c.fovy_deg) << "\"/>\n";
    }
  }

  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    const SceneObject& o = scene.objects[i];
    const bool ghost = d.objects[i].ghost;
    double volume = 0.0;
    for (const ObjectPart& p : o.type.parts) volume += part_volume(p);
    const double density = o.type.mass / volume;
    x << "    <body name=\"" << o.body << "\" pos=\"" << vec(o.initial_position)
      << "\" euler=\"0 0 " << num(deg(o.initial_yaw)) << "\">\n";
    x << "      <freejoint name=\"" << o.body << "_free\"/>\n";
    for (std::size_t k = 0; k < o.type.parts.size(); ++k) {
      const ObjectPart& p = o.type.parts[k];
      x << "      <geom name=\"" << o.body << "_" << k << "\" type=\"" << to_string(p.shape)
        << "\" size=\"" << geom_size(p) << "\" pos=\"" << vec(p.position) << "\" euler=\""
        << vec(p.euler * (180.0 / std::numbers::pi)) << "\" material=\"mat_" << o.name
        << "\" density=\"" << num(density) << "\" friction=\"" << num(o.type.friction)
        << " 0.005 0.0001\" contype=\"" << (ghost ? 4 : 1) << "\" conaffinity=\"" << (ghost ? 0 : 1)
        << "\"/>\n";
    }
    x << "    </body>\n";
  }
  x << "  </worldbody>\n";
  if (!d.grasp_object.empty()) {
    const auto it = std::find_if(scene.objects.begin(), scene.objects.end(),
                                 [&](const SceneObject& o) { return o.name == d.grasp_object; });
    if (it == scene.objects.end()) {
      throw Error("scene: the grasp object '" + d.grasp_object + "' is not one of the objects");
    }
    if (d.arm_model.empty()) throw Error("scene: a grasp object needs the arm");
    // World::set_grasp fills in the relative pose at the moment of the grasp.
    x << "  <equality>\n    <weld name=\"" << kGraspConstraint << "\" body1=\"" << kGraspArmBody
      << "\" body2=\"" << it->body << "\" active=\"false\"/>\n  </equality>\n";
  }
  x << "</mujoco>\n";
  scene.xml = x.str();
  return scene;
}

}  // namespace proprio::sim
