#include "proprio/planning/stereo_rig.hpp"

#include <Eigen/Geometry>
#include <cmath>

#include "proprio/core/error.hpp"
#include "proprio/geometry/triangulation.hpp"
#include "proprio/geometry/visual_uncertainty.hpp"

namespace proprio::planning {

geometry::Camera look_at_camera(const Eigen::Vector3d& eye, const Eigen::Vector3d& target,
                                double focal_px, int width, int height) {
  require(eye.allFinite() && target.allFinite(), "camera: eye and target must be finite");
  require(std::isfinite(focal_px) && focal_px > 0, "camera: focal length must be > 0 px");
  require(width > 0 && height > 0, "camera: image size must be positive");
  const Eigen::Vector3d forward = target - eye;
  require(forward.norm() > 1e-9, "camera: eye and target coincide");
  const Eigen::Vector3d z = forward.normalized();
  const Eigen::Vector3d right = z.cross(Eigen::Vector3d::UnitZ());
  require(right.norm() > 1e-6, "camera: a vertical view has no defined image x axis");
  const Eigen::Vector3d x = right.normalized();
  const Eigen::Vector3d y = z.cross(x);  // points down in the image
  geometry::Camera c;
  c.R.row(0) = x.transpose();
  c.R.row(1) = y.transpose();
  c.R.row(2) = z.transpose();
  c.t = -c.R * eye;
  c.K << focal_px, 0, (width - 1) / 2.0, 0, focal_px, (height - 1) / 2.0, 0, 0, 1;
  c.width = width;
  c.height = height;
  return c;
}

StereoRig default_stereo_rig() {
  const Eigen::Vector3d look(0.25, -0.05, 0.05);
  return {look_at_camera({1.3, 0.25, 0.9}, look, 500, 640, 480),
          look_at_camera({1.3, -0.25, 0.9}, look, 500, 640, 480)};
}

namespace {
bool inside(const geometry::Camera& c, const Eigen::Vector3d& X) {
  if (c.depth(X) <= 0) return false;
  const Eigen::Vector2d u = c.project(X);
  return u.x() >= -0.5 && u.y() >= -0.5 && u.x() <= c.width - 0.5 && u.y() <= c.height - 0.5;
}
}  // namespace

bool visible(const StereoRig& rig, const Eigen::Vector3d& X) {
  return inside(rig.left, X) && inside(rig.right, X);
}

Eigen::Matrix3d measurement_covariance(const StereoRig& rig, const Eigen::Vector3d& X,
                                       double sigma_px) {
  require(std::isfinite(sigma_px) && sigma_px >= 0, "pixel noise must be >= 0 px");
  if (sigma_px == 0) return Eigen::Matrix3d::Zero();
  return geometry::triangulation_covariance(rig.left.P(), rig.right.P(), X,
                                            sigma_px * sigma_px * Eigen::Matrix2d::Identity());
}

double position_std_per_pixel(const StereoRig& rig, const Eigen::Vector3d& X) {
  return std::sqrt(measurement_covariance(rig, X, 1.0).trace() / 3);
}

std::optional<StereoMeasurement> measure(const StereoRig& rig, const Eigen::Vector3d& truth,
                                         double sigma_px, core::Rng& rng, double floor) {
  require(std::isfinite(sigma_px) && sigma_px >= 0, "pixel noise must be >= 0 px");
  if (!visible(rig, truth)) return std::nullopt;
  StereoMeasurement m;
  m.pixel_left = rig.left.project(truth);
  m.pixel_right = rig.right.project(truth);
  for (Eigen::Vector2d* u : {&m.pixel_left, &m.pixel_right}) {
    u->x() += rng.normal(0, sigma_px);
    u->y() += rng.normal(0, sigma_px);
  }
  m.position = geometry::triangulate(rig.left.P(), rig.right.P(), m.pixel_left, m.pixel_right).X;
  m.covariance =
      measurement_covariance(rig, m.position, sigma_px) + floor * Eigen::Matrix3d::Identity();
  return m;
}

}  // namespace proprio::planning
