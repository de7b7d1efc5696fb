#pragma once
// Camera resection by the Direct Linear Transform (thesis 3.2.3, eqs 3.7-3.11; SPEC §1): the
// projection matrix P from >= 6 known world points and their pixels, e.g. the arm's marker
// positions (robot frame, metres) and where the camera saw them.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "proprio/geometry/camera.hpp"

namespace proprio::geometry {

struct DltOptions {
  /// Fewest 3D-2D pairs accepted. P has 11 degrees of freedom and each pair gives two equations,
  /// so 6 is the least that determines it.
  int min_points = 6;
  /// Hartley normalisation of both point sets before the SVD (centroid at the origin, mean
  /// distance sqrt(2) in the image and sqrt(3) in space). The thesis omits it; without it the
  /// solution depends on the units and is badly conditioned.
  bool normalize = true;
  /// The world points count as coplanar (collinear) when the smallest (middle) standard deviation
  /// of their principal axes is below this fraction of the largest.
  double degeneracy_tolerance = 1e-6;
  /// The DLT matrix counts as rank < 11 when its 11th singular value is below this fraction of
  /// its largest.
  double rank_tolerance = 1e-9;

  /// Throws Error when an option is out of range.
  void validate() const;
};

struct DltSummary {
  int num_points = 0;
  bool normalized = true;
  /// Singular values of the (normalised) DLT matrix: the 11th and 12th relative to the 1st. The
  /// 12th is the algebraic residual (0 for exact data); a small 11th means a near-degenerate set.
  double sigma11_ratio = 0.0;
  double sigma12_ratio = 0.0;
  /// World points that the estimated camera sees behind itself (should be 0; more means
  /// outliers or mismatched pairs).
  int points_behind = 0;
  double max_residual_px = 0.0;
  std::string message;                      ///< one line: what happened (brief()'s first line)
  [[nodiscard]] std::string brief() const;  ///< one line for logs
};

struct DltResult {
  /// The projection matrix, scaled to unit Frobenius norm with det(P(:, 0:2)) > 0, so that the
  /// third row gives a positive depth to points in front of the camera.
  Matrix34d P = Matrix34d::Zero();
  Camera camera;  ///< P decomposed into K [R | t] (decompose_projection)
  /// Reprojection RMS, sqrt(mean over points of |x_i - pi(P X_i)|^2), pixels.
  double rms_px = 0.0;
  std::vector<double> residuals_px;  ///< |x_i - pi(P X_i)| per point, pixels
  DltSummary summary;

  /// How well conditioned the fit was (the record's "summary").
  struct Conditioning {
    const DltSummary* s;
    template <class Self, class Visitor>
    static void describe(Self& self, Visitor& v) {
      v(self.s->normalized, {"normalized", "Hartley normalisation used"});
      v(self.s->sigma11_ratio, {"sigma11_ratio", "11th singular value / the 1st"});
      v(self.s->sigma12_ratio, {"sigma12_ratio", "12th singular value / the 1st"});
      v(self.s->points_behind, {"points_behind", "World points behind the camera"});
    }
  };

  /// Output only: rms_px, points, max_residual_px, residuals_px, P, camera, summary.
  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.rms_px, {"rms_px", "Reprojection RMS, px"});
    v(self.summary.num_points, {"points", "Correspondences"});
    v(self.summary.max_residual_px, {"max_residual_px", "Largest residual, px"});
    v(self.residuals_px, {"residuals_px", "Residual per point, px"});
    v(core::matrix_rows(self.P), {"P", "The projection matrix"});
    v(self.camera, {"camera", "P decomposed into K [R | t]"});
    v(Conditioning{&self.summary}, {"summary", "The fit's conditioning"});
  }
};

/// Estimates P from world points X_i (any consistent unit) and their ideal (undistorted) pixels
/// x_i: two rows per pair, [X^T, 0^T, -u X^T] and [0^T, X^T, -v X^T] acting on (P1; P2; P3) (the
/// corrected eq 3.10), solved as the right singular vector of the smallest singular value
/// (eq 3.11). Throws Error for fewer than min_points pairs, non-finite values, coplanar or
/// collinear world points, or any other set that leaves the DLT matrix with rank < 11.
DltResult calibrate_dlt(const std::vector<Eigen::Vector3d>& world,
                        const std::vector<Eigen::Vector2d>& pixels, const DltOptions& options = {});

}  // namespace proprio::geometry
