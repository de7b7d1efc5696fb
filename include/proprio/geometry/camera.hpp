#pragma once
// The pinhole camera of thesis 3.2.2 and its calibration file.
//
// Conventions (docs/formats/episode.md): the world frame is the robot base frame (metres, z up);
// the camera frame follows OpenCV (x right, y down, z forward); pixel centres sit at integer
// coordinates; extrinsics map world to camera, x_cam = R x_world + t; P = K [R | t].

#include <Eigen/Core>
#include <filesystem>
#include <optional>
#include <vector>

#include "proprio/core/fields.hpp"
#include "proprio/core/provenance.hpp"

namespace proprio::geometry {

using Matrix34d = Eigen::Matrix<double, 3, 4>;

/// Camera intrinsics and extrinsics. Constant data: algorithms take it by const reference.
struct Camera {
  Eigen::Matrix3d K = Eigen::Matrix3d::Identity();  ///< intrinsics, pixels
  /// Lens distortion in OpenCV's order (k1, k2, p1, p2[, k3[, k4, k5, k6]]); empty = none.
  std::vector<double> dist;
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();  ///< world -> camera rotation
  Eigen::Vector3d t = Eigen::Vector3d::Zero();      ///< world -> camera translation, metres
  int width = 0;                                    ///< image width in pixels, 0 when unknown
  int height = 0;                                   ///< image height in pixels, 0 when unknown

  /// P = K [R | t] (eq 3.7).
  [[nodiscard]] Matrix34d P() const;
  /// Optical centre in world coordinates, -R^T t.
  [[nodiscard]] Eigen::Vector3d center() const;
  /// Ideal (undistorted) pixel of world point X; X must lie in front of the camera.
  [[nodiscard]] Eigen::Vector2d project(const Eigen::Vector3d& X) const;
  /// Depth of world point X along the optical axis (metres; negative behind the camera).
  [[nodiscard]] double depth(const Eigen::Vector3d& X) const;
  [[nodiscard]] bool has_distortion() const;

  /// Output only: K, dist, R, t, P, centre and the image size (matrices as arrays of rows;
  /// docs/formats/schemas/calib_*.schema.json).
  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(core::matrix_rows(self.K), {"K", "Intrinsics, pixels"});
    v(self.dist, {"dist", "Lens distortion, OpenCV's order"});
    v(core::matrix_rows(self.R), {"R", "Rotation, world to camera"});
    v(core::vector_values(self.t), {"t", "Translation, world to camera"});
    v(core::matrix_rows(self.P()), {"P", "K [R | t] (eq 3.7)"});
    v(core::vector_values(self.center()), {"centre", "Camera centre, world frame"});
    v(self.width, {"image_width", "Image width, px (0: unknown)"});
    v(self.height, {"image_height", "Image height, px (0: unknown)"});
  }
};

/// Pixel of homogeneous projection P X (pi_3 of eq 3.21).
Eigen::Vector2d project(const Matrix34d& P, const Eigen::Vector3d& X);

/// Jacobian d pi(P X) / dX of project() (pixels per world unit, 2x3), analytic: with
/// (a, b, w) = P (X, 1), it is (1 / w) [P_1 - u P_3; P_2 - v P_3] restricted to the first three
/// columns, where u = a / w and v = b / w. Used to linearise triangulation (eqs 3.20-3.21).
Eigen::Matrix<double, 2, 3> projection_jacobian(const Matrix34d& P, const Eigen::Vector3d& X);

/// Removes lens distortion from measured pixels (cv::undistortPoints with P = K): the result is
/// the ideal pixels that P = K [R | t] predicts. Without distortion the pixels are returned as is.
/// OpenCV's model has no skew: K(0, 1) is ignored here (DLT's skew is a fraction of a pixel).
std::vector<Eigen::Vector2d> undistort_pixels(const Camera& camera,
                                              const std::vector<Eigen::Vector2d>& pixels);

/// Splits P into K [R | t] by RQ decomposition: K upper triangular with positive diagonal and
/// K(2,2) = 1, R a proper rotation. P is only defined up to scale (and sign); the result is the
/// camera whose projection equals P up to a positive or negative factor. Throws Error when the
/// left 3x3 block of P is singular (not a finite camera).
Camera decompose_projection(const Matrix34d& P);

/// Reads calib.yml (OpenCV FileStorage YAML: camera_matrix, dist_coeffs, R, t, P, and optionally
/// image_width and image_height). A file with only P is decomposed. Checks that every matrix has
/// its size, is finite, that R is a rotation, that P agrees with K [R | t], that the format
/// version is not newer than kCalibFormatVersion, that image_width and image_height are integers,
/// and that the sizes are within the caps below; throws Error naming the file and the problem.
/// The nesting of the YAML is bounded (core::check_yaml_depth) and its layout held to what OpenCV
/// writes (directives, one "---" line, one block map with its keys at column 0, nothing after
/// "...") before OpenCV parses it: OpenCV 4.6's parser loops for ever on some other layouts.
Camera read_calib(const std::filesystem::path& path);

/// Caps of read_calib: a camera translated by more than 10^6 units (1000 km in metres), a K with
/// an entry above 10^7 pixels, or an image side above 10^6 pixels is garbage, not a camera.
inline constexpr double kMaxCalibTranslation = 1e6;
inline constexpr double kMaxCalibPixels = 1e7;
inline constexpr int kMaxCalibImageSide = 1000000;

/// Format version of the calib.yml that write_calib writes (its `format_version` key). Files
/// without the key (written by other tools) are read as version 1.
inline constexpr int kCalibFormatVersion = 1;

/// Writes calib.yml atomically, with P = K [R | t], `format: proprio.calib`, `format_version`,
/// and, when given, the provenance of the run that produced it (a map of strings).
void write_calib(const std::filesystem::path& path, const Camera& camera,
                 const std::optional<core::Provenance>& provenance = std::nullopt);

}  // namespace proprio::geometry
