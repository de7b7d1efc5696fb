#include "proprio/sim/world.hpp"

#include <algorithm>
#include <cassert>
#include <cstddef>
#include <cstring>
#include <opencv2/imgproc.hpp>
#include <utility>

#include "proprio/core/error.hpp"
#include "proprio/sim/camera_model.hpp"
#include "proprio/sim/mujoco_messages.hpp"

namespace proprio::sim {

namespace {

constexpr const char* kSceneName = "<generated scene>";

// The position and orientation of body `b` in the world.
Pose body_pose(const mjData& d, int b) {
  const mjtNum* pos = d.xpos + std::ptrdiff_t{3} * b;
  const mjtNum* quat = d.xquat + std::ptrdiff_t{4} * b;
  Pose p = Pose::Identity();
  p.translation() = Eigen::Vector3d(pos[0], pos[1], pos[2]);
  p.linear() =
      Eigen::Quaterniond(quat[0], quat[1], quat[2], quat[3]).normalized().toRotationMatrix();
  return p;
}

}  // namespace

World::World(World&&) noexcept = default;
World& World::operator=(World&&) noexcept = default;
World::~World() = default;

World World::build(const SceneDescription& description, const ObjectCatalogue& catalogue) {
  return compile(build_scene(description, catalogue));
}

World World::compile(SceneModel scene) {
  install_mujoco_handlers();
  World w;
  w.scene_ = std::move(scene);
  robot::ModelPtr model = robot::load_model_from_string(w.scene_.xml, kSceneName);
  w.model_ = std::shared_ptr<mjModel>(model.release(), robot::ModelDeleter{});
  mjModel& m = *w.model_;
  for (const TextureData& t : w.scene_.textures) {
    const int id = mj_name2id(&m, mjOBJ_TEXTURE, t.name.c_str());
    assert(id >= 0);
    const std::size_t bytes = static_cast<std::size_t>(m.tex_width[id]) * m.tex_height[id] * 3;
    assert(t.rgb.isContinuous() && t.rgb.type() == CV_8UC3 && t.rgb.total() * 3 == bytes);
    std::memcpy(m.tex_rgb + m.tex_adr[id], t.rgb.data, bytes);
  }
  w.data_ = robot::make_data(m);
  w.index_model();
  mj_forward(&m, w.data_.get());
  return w;
}

void World::index_model() {
  const mjModel& m = *model_;
  body_object_.assign(static_cast<std::size_t>(m.nbody), kBackgroundId);
  object_body_.assign(scene_.objects.size() + 1, -1);
  object_qpos_.assign(scene_.objects.size() + 1, -1);
  object_dof_.assign(scene_.objects.size() + 1, -1);
  for (const SceneObject& o : scene_.objects) {
    const int body = mj_name2id(&m, mjOBJ_BODY, o.body.c_str());
    assert(body > 0 && m.body_jntnum[body] == 1 && m.jnt_type[m.body_jntadr[body]] == mjJNT_FREE);
    object_body_[o.id] = body;
    object_qpos_[o.id] = m.jnt_qposadr[m.body_jntadr[body]];
    object_dof_[o.id] = m.jnt_dofadr[m.body_jntadr[body]];
  }
  // Every body below an object's (none, today) or the arm's root carries its id.
  const int arm_base = mj_name2id(&m, mjOBJ_BODY, "arm_base");
  for (int b = 1; b < m.nbody; ++b) {
    for (int a = b; a > 0; a = m.body_parentid[a]) {
      if (a == arm_base) {
        body_object_[static_cast<std::size_t>(b)] = kArmId;
        arm_bodies_.push_back(b);
        break;
      }
      const auto it = std::find(object_body_.begin(), object_body_.end(), a);
      if (it != object_body_.end()) {
        body_object_[static_cast<std::size_t>(b)] =
            static_cast<ObjectId>(std::distance(object_body_.begin(), it));
        break;
      }
    }
  }
  if (arm_base >= 0) arm_.emplace(shared_model(), robot::ArmNames{}, kSceneName);
}

void World::step(int steps) {
  assert(steps >= 0);
  for (int i = 0; i < steps; ++i) mj_step(model_.get(), data_.get());
  const std::vector<std::string> w = warnings();
  if (!w.empty()) {
    std::string message = "simulation: MuJoCo warned by t = " + std::to_string(data_->time) + " s:";
    for (const std::string& line : w) {
      message += " ";
      message += line;
    }
    throw Error(message);
  }
}

void World::forward() { mj_forward(model_.get(), data_.get()); }

void World::reset() {
  mj_resetData(model_.get(), data_.get());
  mj_forward(model_.get(), data_.get());
}

std::vector<std::string> World::warnings() const { return robot::warnings(*data_); }

const SceneObject& World::object(const std::string& name) const {
  for (const SceneObject& o : scene_.objects) {
    if (o.name == name) return o;
  }
  std::string known;
  for (const SceneObject& o : scene_.objects) {
    known += known.empty() ? "" : ", ";
    known += o.name;
  }
  throw Error("unknown object '" + name +
              "' in the scene (objects: " + (known.empty() ? "none" : known) + ")");
}

const SceneObject& World::object(ObjectId id) const {
  assert(id >= 1 && id <= scene_.objects.size());
  return scene_.objects[id - 1U];
}

Pose World::object_pose(ObjectId id) const {
  const int body = object_body_[object(id).id];
  return body_pose(*data_, body);
}

void World::set_object_pose(ObjectId id, const Pose& pose) {
  const int adr = object_qpos_[object(id).id];
  const int dof = object_dof_[id];
  const Eigen::Quaterniond q(pose.rotation());
  const Eigen::Vector3d p = pose.translation();
  assert(p.allFinite() && q.coeffs().allFinite());
  mjtNum* qpos = data_->qpos + adr;
  qpos[0] = p.x();
  qpos[1] = p.y();
  qpos[2] = p.z();
  qpos[3] = q.w();
  qpos[4] = q.x();
  qpos[5] = q.y();
  qpos[6] = q.z();
  std::fill_n(data_->qvel + dof, 6, 0.0);
  mj_forward(model_.get(), data_.get());
}

namespace {
// Weld constraint data in MuJoCo 2.2 (mjNEQDATA = 11): the anchor in body2's frame, the point
// in body1's frame that it must coincide with, body2's orientation in body1's frame (w x y z)
// and the torque scale.
constexpr int kWeldAnchor = 0;
constexpr int kWeldRelPos = 3;
constexpr int kWeldRelQuat = 6;

int grasp_equality(const mjModel& m) {
  const int id = mj_name2id(&m, mjOBJ_EQUALITY, kGraspConstraint);
  assert(id >= 0 && m.eq_type[id] == mjEQ_WELD && "the scene has no grasp object");
  return id;
}
}  // namespace

void World::set_grasp(bool on, const Eigen::Vector3d& anchor) {
  mjModel& m = *model_;
  const int id = grasp_equality(m);
  if (on) {
    const mjData& d = *data_;
    const Pose p1 = body_pose(d, m.eq_obj1id[id]);
    const Pose p2 = body_pose(d, m.eq_obj2id[id]);
    const Eigen::Vector3d relpos = p1.inverse() * (p2 * anchor);
    grasp_relquat_ = Eigen::Quaterniond(p1.linear().transpose() * p2.linear()).normalized();
    mjtNum* data = m.eq_data + std::ptrdiff_t{mjNEQDATA} * id;
    for (int k = 0; k < 3; ++k) {
      data[kWeldAnchor + k] = anchor[k];
      data[kWeldRelPos + k] = relpos[k];
    }
    set_grasp_rotation(Eigen::Matrix3d::Identity());
  }
  m.eq_active[id] = on ? 1 : 0;
  mj_forward(model_.get(), data_.get());
}

void World::set_grasp_rotation(const Eigen::Matrix3d& rotation) {
  mjModel& m = *model_;
  const int id = grasp_equality(m);
  const Eigen::Quaterniond q = (grasp_relquat_ * Eigen::Quaterniond(rotation)).normalized();
  mjtNum* data = m.eq_data + std::ptrdiff_t{mjNEQDATA} * id;
  data[kWeldRelQuat + 0] = q.w();
  data[kWeldRelQuat + 1] = q.x();
  data[kWeldRelQuat + 2] = q.y();
  data[kWeldRelQuat + 3] = q.z();
}

bool World::grasping() const {
  const int id = mj_name2id(model_.get(), mjOBJ_EQUALITY, kGraspConstraint);
  return id >= 0 && model_->eq_active[id] != 0;
}

Eigen::Vector3d World::object_velocity(ObjectId id) const {
  // A free joint's first three velocities are its body origin's, in the world frame.
  const mjtNum* v = data_->qvel + object_dof_[object(id).id];
  return {v[0], v[1], v[2]};
}

ObjectId World::body_object_id(int body) const {
  assert(body >= 0 && body < model_->nbody);
  return body_object_[static_cast<std::size_t>(body)];
}

ObjectId World::geom_object_id(int geom) const {
  assert(geom >= 0 && geom < model_->ngeom);
  return body_object_id(model_->geom_bodyid[geom]);
}

std::vector<int> World::geoms_of(ObjectId id) const {
  std::vector<int> out;
  for (int g = 0; g < model_->ngeom; ++g) {
    if (geom_object_id(g) == id) out.push_back(g);
  }
  return out;
}

const robot::Arm& World::arm() const {
  assert(arm_.has_value());
  return *arm_;
}

std::vector<LinkPose> World::arm_link_poses() const {
  std::vector<LinkPose> out;
  out.reserve(arm_bodies_.size());
  for (int b : arm_bodies_) {
    const char* name = mj_id2name(model_.get(), mjOBJ_BODY, b);
    out.push_back({name != nullptr ? name : "", body_pose(*data_, b)});
  }
  return out;
}

robot::JointVector World::arm_joints() const {
  robot::JointVector q;
  for (int k = 0; k < robot::kArmJoints; ++k) q[k] = data_->qpos[arm().qpos_adr(k)];
  return q;
}

void World::set_arm_targets(const robot::JointVector& q) {
  assert(q.allFinite());
  const robot::JointVector c = arm().clamp(q);
  for (int k = 0; k < robot::kArmJoints; ++k) data_->ctrl[arm().actuator_id(k)] = c[k];
}

void World::set_arm_configuration(const robot::JointVector& q) {
  const robot::JointVector c = arm().clamp(q);
  for (int k = 0; k < robot::kArmJoints; ++k) {
    data_->qpos[arm().qpos_adr(k)] = c[k];
    data_->qvel[arm().dof_adr(k)] = 0.0;
  }
  set_arm_targets(c);
  mj_forward(model_.get(), data_.get());
}

Eigen::Vector3d World::ee_position() const {
  return Eigen::Map<const Eigen::Vector3d>(data_->site_xpos + std::ptrdiff_t{3} * arm().ee_site());
}

bool World::touching(std::span<const int> geoms, int body) const {
  for (int i = 0; i < data_->ncon; ++i) {
    const mjContact& c = data_->contact[i];
    const bool g1 = std::find(geoms.begin(), geoms.end(), c.geom1) != geoms.end();
    const bool g2 = std::find(geoms.begin(), geoms.end(), c.geom2) != geoms.end();
    if ((g1 && model_->geom_bodyid[c.geom2] == body) ||
        (g2 && model_->geom_bodyid[c.geom1] == body)) {
      return true;
    }
  }
  return false;
}

bool World::arm_touches(ObjectId id) const {
  const ObjectId target = object(id).id;
  for (int i = 0; i < data_->ncon; ++i) {
    const mjContact& c = data_->contact[i];
    const ObjectId a = geom_object_id(c.geom1);
    const ObjectId b = geom_object_id(c.geom2);
    if ((a == kArmId && b == target) || (b == kArmId && a == target)) return true;
  }
  return false;
}

std::vector<ObjectId> World::objects_touched_by_arm() const {
  std::vector<ObjectId> out;
  for (int i = 0; i < data_->ncon; ++i) {
    const mjContact& c = data_->contact[i];
    const ObjectId a = geom_object_id(c.geom1);
    const ObjectId b = geom_object_id(c.geom2);
    if (a == kArmId && b != kArmId && b != kBackgroundId) out.push_back(b);
    if (b == kArmId && a != kArmId && a != kBackgroundId) out.push_back(a);
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

int World::camera_id(const std::string& name) const {
  const int id = mj_name2id(model_.get(), mjOBJ_CAMERA, name.c_str());
  if (id < 0) {
    std::string known;
    for (const std::string& n : scene_.camera_names) {
      known += known.empty() ? "" : ", ";
      known += n;
    }
    throw Error("unknown camera '" + name + "' (cameras: " + known + ")");
  }
  return id;
}

std::pair<int, int> World::camera_size(const std::string& name) const {
  (void)camera_id(name);  // throws for an unknown camera
  for (const CameraSpec& c : scene_.description.cameras) {
    for (const std::string& n : c.camera_names()) {
      if (n == name) return {c.width, c.height};
    }
  }
  throw Error("camera '" + name + "' is not one of the scene description's cameras");
}

geometry::Camera World::camera(const std::string& name) const {
  const auto [width, height] = camera_size(name);
  return camera_from_mujoco(*model_, *data_, camera_id(name), width, height);
}

int World::texture_id(const std::string& name) const {
  const int id = mj_name2id(model_.get(), mjOBJ_TEXTURE, name.c_str());
  if (id < 0) throw Error("the scene has no texture '" + name + "'");
  return id;
}

void World::set_texture_image(const std::string& texture, const cv::Mat& bgr) {
  const int id = texture_id(texture);
  mjModel& m = *model_;
  require(m.tex_type[id] == mjTEXTURE_2D, "texture '" + texture + "' is not a 2D texture");
  require(!bgr.empty() && bgr.type() == CV_8UC3,
          "texture '" + texture + "': the image must be a non-empty 8-bit BGR image");
  cv::Mat resized;
  cv::resize(bgr, resized, cv::Size(m.tex_width[id], m.tex_height[id]), 0, 0, cv::INTER_AREA);
  cv::Mat rgb(m.tex_height[id], m.tex_width[id], CV_8UC3, m.tex_rgb + m.tex_adr[id]);
  cv::cvtColor(resized, rgb, cv::COLOR_BGR2RGB);
}

}  // namespace proprio::sim
