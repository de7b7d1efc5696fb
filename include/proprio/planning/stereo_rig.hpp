#pragma once
// The stereo pair that watches the target (thesis 3.4.1-3.4.2): two pinhole cameras, a simulated
// measurement of a 3D point through them (project, pixel noise, triangulate), and the linearised
// covariance of that measurement, p(x | C) as a 3D Gaussian (eqs 3.20-3.21; SPEC section 2).
//
// Frames: world = robot base frame (metres, z up); camera frames follow OpenCV (x right, y down,
// z forward), P = K [R | t] (geometry/camera.hpp).

#include <Eigen/Core>
#include <optional>

#include "proprio/core/random.hpp"
#include "proprio/geometry/camera.hpp"

namespace proprio::planning {

struct StereoRig {
  geometry::Camera left;
  geometry::Camera right;
};

/// An ideal camera at `eye` looking at `target` with the world's z axis up in the image (no
/// roll): square pixels of focal length `focal_px`, the principal point at the image centre
/// ((width - 1) / 2, (height - 1) / 2), no distortion. Throws Error when eye and target coincide,
/// the view is vertical, or a size is not positive.
geometry::Camera look_at_camera(const Eigen::Vector3d& eye, const Eigen::Vector3d& target,
                                double focal_px, int width, int height);

/// The default pair: 640 x 480 cameras (focal length 500 px) 0.5 m apart at (1.3, +-0.25, 0.9) m,
/// facing the arm from the front and looking down at (0.25, -0.05, 0.05) m, the middle of the
/// interception workspace. They see the table from x = -0.5 to 1 m and y = -0.8 to 0.7 m.
StereoRig default_stereo_rig();

/// True when X is in front of both cameras and projects inside both images (which needs the
/// image sizes).
bool visible(const StereoRig& rig, const Eigen::Vector3d& X);

/// Linearised covariance (m^2) of the point triangulated at X when both cameras' pixels carry
/// independent noise of std `sigma_px` per axis: (J1^T J1 + J2^T J2)^-1 sigma_px^2
/// (geometry::triangulation_covariance). Throws Error for X behind a camera or on the baseline.
Eigen::Matrix3d measurement_covariance(const StereoRig& rig, const Eigen::Vector3d& X,
                                       double sigma_px);

/// The per-axis standard deviation of a triangulated point at X per pixel of image noise,
/// sqrt(trace(Cov) / 3) for sigma_px = 1 (m/px).
double position_std_per_pixel(const StereoRig& rig, const Eigen::Vector3d& X);

struct StereoMeasurement {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();    ///< triangulated, world frame, m
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();  ///< linearised, at `position`, m^2
  Eigen::Vector2d pixel_left = Eigen::Vector2d::Zero();  ///< the noisy pixels
  Eigen::Vector2d pixel_right = Eigen::Vector2d::Zero();
};

/// Measures the world point `truth`: projects it into both cameras, adds Gaussian noise of std
/// `sigma_px` to each pixel coordinate, and triangulates (linear method, geometry::triangulate).
/// The covariance is measurement_covariance at the triangulated point, plus `floor` m^2 on the
/// diagonal (so that a noise-free measurement still has a positive definite covariance).
/// Returns nothing when the point is not visible in both images. Throws Error for a negative
/// sigma_px.
std::optional<StereoMeasurement> measure(const StereoRig& rig, const Eigen::Vector3d& truth,
                                         double sigma_px, core::Rng& rng, double floor = 1e-12);

}  // namespace proprio::planning
