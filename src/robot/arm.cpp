#include "proprio/robot/arm.hpp"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "proprio/core/error.hpp"
#include "text.hpp"

namespace proprio::robot {
namespace {

using detail::cat;
constexpr double kGeometryTolerance = 1e-9;

Eigen::Vector3d vec3(const mjtNum* p) { return {p[0], p[1], p[2]}; }

int find_id(const mjModel& m, mjtObj type, const std::string& name) {
  if (name.empty()) return -1;
  return mj_name2id(&m, type, name.c_str());
}

}  // namespace

Arm Arm::load(const std::filesystem::path& mjcf, const ArmNames& names) {
  ModelPtr model = load_model(mjcf);
  return Arm(std::shared_ptr<const mjModel>(model.release(), ModelDeleter{}), names, mjcf.string());
}

Arm::Arm(std::shared_ptr<const mjModel> model, const ArmNames& names, std::string source)
    : model_(std::move(model)), names_(names), source_(std::move(source)) {
  if (!model_) throw Error::in_file(source_, "no model");
  const mjModel& m = *model_;
  auto missing = [&](const std::string& what, const std::string& name) {
    std::string message = "the arm model has no ";
    message += what;
    message += " named '";
    message += name;
    message += "' (see docs/formats/arm-model.md)";
    return Error::in_file(source_, message);
  };
  for (int k = 0; k < kArmJoints; ++k) {
    const std::string& jname = names_.joints[idx(k)];
    const int j = find_id(m, mjOBJ_JOINT, jname);
    if (j < 0) throw missing("joint", jname);
    if (m.jnt_type[j] != mjJNT_HINGE) {
      throw Error::in_file(source_, cat({"arm joint '", jname, "' is not a hinge joint"}));
    }
    if (!m.jnt_limited[j]) {
      throw Error::in_file(source_, cat({"arm joint '", jname, "' has no limits (set range)"}));
    }
    for (int i = 0; i < k; ++i) {
      if (joint_id_[idx(i)] == j) throw Error::in_file(source_, "arm joint names repeat");
    }
    joint_id_[idx(k)] = j;
    qpos_adr_[idx(k)] = m.jnt_qposadr[j];
    dof_adr_[idx(k)] = m.jnt_dofadr[j];
    lower_[k] = m.jnt_range[2 * j];
    upper_[k] = m.jnt_range[2 * j + 1];
    if (!(lower_[k] < upper_[k])) {
      throw Error::in_file(source_, cat({"arm joint '", jname, "' has an empty range"}));
    }

    const std::string& aname = names_.actuators[idx(k)];
    const int a = find_id(m, mjOBJ_ACTUATOR, aname);
    if (a < 0) throw missing("actuator", aname);
    if (m.actuator_trntype[a] != mjTRN_JOINT || m.actuator_trnid[2 * a] != j) {
      throw Error::in_file(source_,
                           cat({"actuator '", aname, "' does not drive joint '", jname, "'"}));
    }
    actuator_id_[idx(k)] = a;
  }
  ee_site_ = find_id(m, mjOBJ_SITE, names_.ee_site);
  if (ee_site_ < 0) throw missing("site", names_.ee_site);
  base_body_ = find_id(m, mjOBJ_BODY, names_.base_body);
  if (base_body_ < 0) throw missing("body", names_.base_body);
  marker_geom_ = find_id(m, mjOBJ_GEOM, names_.marker_geom);
  for (std::size_t f = 0; f < 2; ++f) {
    gripper_joint_id_[f] = find_id(m, mjOBJ_JOINT, names_.gripper_joints[f]);
    gripper_act_id_[f] = find_id(m, mjOBJ_ACTUATOR, names_.gripper_actuators[f]);
  }
  read_geometry();
}

bool Arm::within_limits(const JointVector& q, double tolerance) const {
  return ((q.array() >= lower_.array() - tolerance) && (q.array() <= upper_.array() + tolerance))
      .all();
}

JointVector Arm::clamp(const JointVector& q) const { return q.cwiseMax(lower_).cwiseMin(upper_); }

void Arm::read_geometry() {
  const mjModel& m = *model_;
  DataPtr data = make_data(m);
  mjData& d = *data;
  for (int k = 0; k < kArmJoints; ++k) d.qpos[qpos_adr_[idx(k)]] = 0.0;
  mj_kinematics(&m, &d);

  std::array<Eigen::Vector3d, kArmJoints> anchor;
  std::array<Eigen::Vector3d, kArmJoints> axis;
  for (std::size_t k = 0; k < kArmJoints; ++k) {
    anchor[k] = vec3(d.xanchor + 3 * joint_id_[k]);
    axis[k] = vec3(d.xaxis + 3 * joint_id_[k]).normalized();
  }
  const Eigen::Vector3d ee = vec3(d.site_xpos + 3 * ee_site_);
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  ArmGeometry& g = geometry_;
  g.base_xy = anchor[0].head<2>();
  const Eigen::Vector3d yaw_point(g.base_xy.x(), g.base_xy.y(), 0.0);

  // Keep-out cylinder: the geoms of the base and of the first (yaw) link.
  const int yaw_body = m.jnt_bodyid[joint_id_[0]];
  for (int i = 0; i < m.ngeom; ++i) {
    const int b = m.geom_bodyid[i];
    if (b != base_body_ && b != yaw_body) continue;
    const Eigen::Vector3d c = vec3(d.geom_xpos + 3 * i);
    const double radial = (c - yaw_point).head<2>().norm();
    const bool vertical_cylinder =
        m.geom_type[i] == mjGEOM_CYLINDER && std::abs(d.geom_xmat[9 * i + 8]) > 1 - 1e-9;
    const double extent_r = vertical_cylinder ? m.geom_size[3 * i] : m.geom_rbound[i];
    const double extent_z = vertical_cylinder ? m.geom_size[3 * i + 1] : m.geom_rbound[i];
    g.base_radius = std::max(g.base_radius, radial + extent_r);
    g.base_top = std::max(g.base_top, c.z() + extent_z);
  }

  auto fail = [&](const std::string& why) {
    g.analytic = false;
    g.why_not_analytic = why;
  };
  if (std::abs(axis[0].dot(up)) < 1 - kGeometryTolerance) return fail("j1 axis is not vertical");
  g.yaw_sign = axis[0].z() > 0 ? 1.0 : -1.0;
  if (std::abs(axis[1].z()) > kGeometryTolerance) return fail("j2 axis is not horizontal");
  // The arm's plane: spanned by the vertical and the outward direction o0, normal to the pitch
  // axes; o0 points from the yaw axis towards the end-effector (or the nearest off-axis joint).
  Eigen::Vector3d o0 = axis[1].cross(up).normalized();
  for (const Eigen::Vector3d& p : {ee, anchor[3], anchor[2]}) {
    const double along = (p - yaw_point).dot(o0);
    if (std::abs(along) > 1e-6) {
      if (along < 0) o0 = -o0;
      break;
    }
  }
  const Eigen::Vector3d y0 = up.cross(o0);
  for (std::size_t k = 1; k <= 3; ++k) {
    const double c = axis[k].dot(y0);
    if (std::abs(c) < 1 - kGeometryTolerance) {
      return fail(cat({"j", std::to_string(k + 1), " axis is not parallel to j2"}));
    }
    // Turning about +y0 = up x o0 by a positive angle lowers o0 towards -z.
    g.pitch_sign[k - 1] = c > 0 ? -1.0 : 1.0;
  }
  if (std::abs((ee - yaw_point).dot(y0)) > kGeometryTolerance) {
    return fail("the ee site lies off the plane through the yaw axis");
  }
  const Eigen::Vector3d to_ee = ee - anchor[4];
  if ((to_ee - to_ee.dot(axis[4]) * axis[4]).norm() > kGeometryTolerance) {
    return fail("the ee site is not on the j5 (roll) axis");
  }
  auto planar = [&](const Eigen::Vector3d& p) {
    return Eigen::Vector2d((p - yaw_point).dot(o0), p.z());
  };
  const Eigen::Vector2d s = planar(anchor[1]);
  const Eigen::Vector2d e = planar(anchor[2]);
  const Eigen::Vector2d w = planar(anchor[3]);
  const Eigen::Vector2d t = planar(ee);
  g.shoulder = s;
  g.upper_arm = (e - s).norm();
  g.forearm = (w - e).norm();
  g.hand = (t - w).norm();
  if (g.upper_arm < 1e-6 || g.forearm < 1e-6 || g.hand < 1e-6) {
    return fail("a link between j2, j3, j4 and the ee has zero length");
  }
  g.link_zero = {std::atan2(e.y() - s.y(), e.x() - s.x()), std::atan2(w.y() - e.y(), w.x() - e.x()),
                 std::atan2(t.y() - w.y(), t.x() - w.x())};
  g.yaw_zero = std::atan2(o0.y(), o0.x());
  g.reach = g.upper_arm + g.forearm + g.hand;
  g.analytic = true;
  g.why_not_analytic.clear();
}

double EePose::pitch() const {
  // atan2 keeps full precision at +-pi/2, where asin(d_z) does not.
  return std::atan2(rotation(2, 0), std::hypot(rotation(0, 0), rotation(1, 0)));
}

ArmState::ArmState(Arm arm) : arm_(std::move(arm)), data_(make_data(arm_.model())) {
  mj_kinematics(&arm_.model(), data_.get());
  mj_comPos(&arm_.model(), data_.get());
}

void ArmState::set_joints(const JointVector& q) {
  for (int k = 0; k < kArmJoints; ++k) data_->qpos[arm_.qpos_adr(k)] = q[k];
  mj_kinematics(&arm_.model(), data_.get());
  mj_comPos(&arm_.model(), data_.get());
}

JointVector ArmState::joints() const {
  JointVector q;
  for (int k = 0; k < kArmJoints; ++k) q[k] = data_->qpos[arm_.qpos_adr(k)];
  return q;
}

Eigen::Vector3d ArmState::ee_position(const JointVector& q) {
  set_joints(q);
  return vec3(data_->site_xpos + 3 * arm_.ee_site());
}

EePose ArmState::ee_pose(const JointVector& q) {
  set_joints(q);
  EePose pose;
  pose.position = vec3(data_->site_xpos + 3 * arm_.ee_site());
  pose.rotation = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(
      data_->site_xmat + 9 * arm_.ee_site());
  return pose;
}

namespace {

PositionJacobian site_jacobian(const Arm& arm, const mjData& d, bool rotational) {
  const mjModel& m = arm.model();
  std::vector<mjtNum> jac(3 * static_cast<std::size_t>(m.nv));
  if (rotational) {
    mj_jacSite(&m, &d, nullptr, jac.data(), arm.ee_site());
  } else {
    mj_jacSite(&m, &d, jac.data(), nullptr, arm.ee_site());
  }
  PositionJacobian J;
  for (int r = 0; r < 3; ++r) {
    for (int k = 0; k < kArmJoints; ++k)
      J(r, k) = jac[static_cast<std::size_t>(r) * static_cast<std::size_t>(m.nv) +
                    static_cast<std::size_t>(arm.dof_adr(k))];
  }
  return J;
}

}  // namespace

PositionJacobian ArmState::jacobian(const JointVector& q) {
  set_joints(q);
  return site_jacobian(arm_, *data_, false);
}

PositionJacobian ArmState::rotation_jacobian(const JointVector& q) {
  set_joints(q);
  return site_jacobian(arm_, *data_, true);
}

}  // namespace proprio::robot
