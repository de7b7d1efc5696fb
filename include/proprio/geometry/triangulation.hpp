#pragma once
// Two-view triangulation (thesis 3.4.1, eq 3.12; SPEC §1): the world point X seen at pixel x1 by
// camera P1 and at x2 by camera P2. Linear (SVD) solution, optionally refined by
// Levenberg-Marquardt on the two reprojection errors.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "proprio/geometry/camera.hpp"

namespace proprio::geometry {

struct TriangulationOptions {
  /// Refine the linear solution by minimising |x1 - pi(P1 X)|^2 + |x2 - pi(P2 X)|^2 over X
  /// (Eigen's Levenberg-Marquardt with the analytic Jacobian). The linear method minimises an
  /// algebraic error; the refined point is the maximum-likelihood one under Gaussian pixel noise.
  bool refine = false;
  /// Most residual evaluations of the refinement.
  int max_evaluations = 100;
  /// Relative tolerance on the step and on the cost reduction that ends the refinement.
  double tolerance = 1e-12;
  /// The linear solution counts as a point at infinity (parallel rays) when its homogeneous
  /// coordinate w, with |(X, w)| = 1 and X in the units of the cameras, is below this.
  double infinity_tolerance = 1e-12;
  /// The two rays count as the same line (the point slides along it undetermined: identical
  /// cameras, or a point on the baseline) when the third singular value of the 4x4 system is below
  /// this fraction of the first.
  double degeneracy_tolerance = 1e-10;

  /// Throws Error when an option is out of range.
  void validate() const;
};

/// How the refinement ended.
enum class TriangulationTermination {
  kLinearOnly,     ///< no refinement asked for
  kConverged,      ///< step or cost reduction below the tolerance
  kMaxEvaluations  ///< stopped by max_evaluations; the point is still the best found
};

const char* to_string(TriangulationTermination t);

struct TriangulationSummary {
  TriangulationTermination termination = TriangulationTermination::kLinearOnly;
  int iterations = 0;          ///< Levenberg-Marquardt iterations (0 without refinement)
  double linear_rms_px = 0.0;  ///< reprojection RMS of the linear solution, pixels
  double final_rms_px = 0.0;   ///< reprojection RMS of the returned point, pixels
};

struct Triangulation {
  Eigen::Vector3d X = Eigen::Vector3d::Zero();  ///< world point, in the cameras' units
  /// sqrt((|x1 - pi(P1 X)|^2 + |x2 - pi(P2 X)|^2) / 2), pixels.
  double rms_px = 0.0;
  TriangulationSummary summary;
};

/// Throws Error unless the centres of the two cameras differ (by more than 1e-9 of their distance
/// from the origin, at least 1e-9): two views from one centre see no depth.
void require_distinct_centres(const Matrix34d& P1, const Matrix34d& P2);

/// Triangulates one point from ideal (undistorted) pixels. The linear method is the one of
/// Hartley & Zisserman 12.2 (and cv::triangulatePoints): the rows u P3 - P1, v P3 - P2 of both
/// cameras, the right singular vector of the smallest singular value. Throws Error when the pixels
/// are not finite, the rays are parallel (the point is at infinity) or coincide, or the cameras
/// share one centre.
Triangulation triangulate(const Matrix34d& P1, const Matrix34d& P2, const Eigen::Vector2d& x1,
                          const Eigen::Vector2d& x2, const TriangulationOptions& options = {});

struct BatchTriangulationSummary {
  int num_points = 0;
  bool refined = false;
  long total_iterations = 0;   ///< summed over points
  int not_converged = 0;       ///< points whose refinement hit max_evaluations
  double linear_rms_px = 0.0;  ///< RMS over all points and both views, linear solutions
  double final_rms_px = 0.0;   ///< the same for the returned points
  double max_rms_px = 0.0;     ///< worst point's rms_px
  std::string message;         ///< one line: what happened (brief()'s first line)
  [[nodiscard]] std::string brief() const;  ///< one line for logs

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.num_points, {"points", "Points triangulated"});
    v(self.refined, {"refined", "Refined by Levenberg-Marquardt"});
    v(self.total_iterations, {"iterations", "Refinement iterations, summed"});
    v(self.not_converged, {"not_converged", "Points whose refinement did not converge"});
    v(self.linear_rms_px, {"linear_rms_px", "RMS of the linear solutions, px"});
    v(self.final_rms_px, {"rms_px", "RMS of the points returned, px"});
    v(self.max_rms_px, {"max_rms_px", "Worst point's RMS, px"});
  }
};

struct BatchTriangulation {
  std::vector<Eigen::Vector3d> points;
  std::vector<double> rms_px;  ///< per point, as Triangulation::rms_px
  BatchTriangulationSummary summary;
};

/// Triangulates corresponding pixel lists (same length) point by point. Throws Error naming the
/// point (1-based) on the first failure, and when the two cameras share one centre (no baseline).
BatchTriangulation triangulate(const Matrix34d& P1, const Matrix34d& P2,
                               const std::vector<Eigen::Vector2d>& x1,
                               const std::vector<Eigen::Vector2d>& x2,
                               const TriangulationOptions& options = {});

}  // namespace proprio::geometry
