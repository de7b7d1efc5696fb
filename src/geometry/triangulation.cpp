#include "proprio/geometry/triangulation.hpp"

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <unsupported/Eigen/NonLinearOptimization>

#include "proprio/core/error.hpp"

namespace proprio::geometry {
namespace {

double rms_of(const Matrix34d& P1, const Matrix34d& P2, const Eigen::Vector2d& x1,
              const Eigen::Vector2d& x2, const Eigen::Vector3d& X) {
  const double e1 = (project(P1, X) - x1).squaredNorm();
  const double e2 = (project(P2, X) - x2).squaredNorm();
  return std::sqrt((e1 + e2) / 2.0);
}

// The four reprojection residuals in the form Eigen's Levenberg-Marquardt expects.
struct ReprojectionResiduals {
  const Matrix34d& P1;
  const Matrix34d& P2;
  const Eigen::Vector2d& x1;
  const Eigen::Vector2d& x2;

  [[nodiscard]] int inputs() const { return 3; }
  [[nodiscard]] int values() const { return 4; }
  int operator()(const Eigen::VectorXd& X, Eigen::VectorXd& f) const {
    f.resize(4);
    f.head<2>() = project(P1, X) - x1;
    f.tail<2>() = project(P2, X) - x2;
    return 0;
  }
  int df(const Eigen::VectorXd& X, Eigen::MatrixXd& J) const {
    J.resize(4, 3);
    J.topRows<2>() = projection_jacobian(P1, X);
    J.bottomRows<2>() = projection_jacobian(P2, X);
    return 0;
  }
};

// The centre of a finite camera P = [M | p4]: -M^-1 p4.
Eigen::Vector3d centre_of(const Matrix34d& P) {
  return -P.leftCols<3>().fullPivLu().solve(P.col(3));
}

}  // namespace

void TriangulationOptions::validate() const {
  require(max_evaluations >= 1, "triangulation option max_evaluations must be at least 1");
  require(tolerance > 0.0 && tolerance < 1.0, "triangulation option tolerance must lie in (0, 1)");
  require(infinity_tolerance > 0.0 && infinity_tolerance < 1.0,
          "triangulation option infinity_tolerance must lie in (0, 1)");
  require(degeneracy_tolerance > 0.0 && degeneracy_tolerance < 1.0,
          "triangulation option degeneracy_tolerance must lie in (0, 1)");
}

const char* to_string(TriangulationTermination t) {
  switch (t) {
    case TriangulationTermination::kLinearOnly:
      return "linear only";
    case TriangulationTermination::kConverged:
      return "converged";
    case TriangulationTermination::kMaxEvaluations:
      return "max evaluations";
  }
  return "?";
}

Triangulation triangulate(const Matrix34d& P1, const Matrix34d& P2, const Eigen::Vector2d& x1,
                          const Eigen::Vector2d& x2, const TriangulationOptions& options) {
  options.validate();
  require_distinct_centres(P1, P2);
  if (!x1.allFinite() || !x2.allFinite()) throw Error("triangulation: pixel is not finite");
  Eigen::Matrix4d A;
  A.row(0) = x1.x() * P1.row(2) - P1.row(0);
  A.row(1) = x1.y() * P1.row(2) - P1.row(1);
  A.row(2) = x2.x() * P2.row(2) - P2.row(0);
  A.row(3) = x2.y() * P2.row(2) - P2.row(1);
  const Eigen::JacobiSVD<Eigen::Matrix4d> svd(A, Eigen::ComputeFullV);
  const Eigen::Vector4d& sv = svd.singularValues();
  if (!(sv(2) >= options.degeneracy_tolerance * sv(0))) {
    throw Error("triangulation: the two rays coincide (the point is undetermined along them)");
  }
  const Eigen::Vector4d Xh = svd.matrixV().col(3);
  if (std::abs(Xh(3)) < options.infinity_tolerance) {
    throw Error("triangulation: the rays are parallel (point at infinity)");
  }
  Triangulation result;
  result.X = Xh.hnormalized();
  result.summary.linear_rms_px = rms_of(P1, P2, x1, x2, result.X);
  if (options.refine) {
    ReprojectionResiduals residuals{P1, P2, x1, x2};
    Eigen::LevenbergMarquardt<ReprojectionResiduals> lm(residuals);
    lm.parameters.maxfev = options.max_evaluations;
    lm.parameters.ftol = options.tolerance;
    lm.parameters.xtol = options.tolerance;
    Eigen::VectorXd X = result.X;
    const auto status = lm.minimize(X);
    result.summary.iterations = static_cast<int>(lm.iter);
    result.summary.termination = status == Eigen::LevenbergMarquardtSpace::TooManyFunctionEvaluation
                                     ? TriangulationTermination::kMaxEvaluations
                                     : TriangulationTermination::kConverged;
    // LM never accepts a step that raises the cost, but guard against a non-finite excursion.
    if (X.allFinite() && rms_of(P1, P2, x1, x2, X) <= result.summary.linear_rms_px) {
      result.X = X;
    }
  }
  result.rms_px = rms_of(P1, P2, x1, x2, result.X);
  result.summary.final_rms_px = result.rms_px;
  return result;
}

std::string BatchTriangulationSummary::brief() const {
  char buf[256];
  std::snprintf(buf, sizeof buf,
                "triangulated %d points%s: reprojection RMS %.4g px (linear %.4g px), worst %.4g "
                "px, %ld iterations, %d not converged",
                num_points, refined ? " with refinement" : "", final_rms_px, linear_rms_px,
                max_rms_px, total_iterations, not_converged);
  return buf;
}

BatchTriangulation triangulate(const Matrix34d& P1, const Matrix34d& P2,
                               const std::vector<Eigen::Vector2d>& x1,
                               const std::vector<Eigen::Vector2d>& x2,
                               const TriangulationOptions& options) {
  options.validate();
  require_distinct_centres(P1, P2);
  if (x1.size() != x2.size()) {
    throw Error("triangulation: " + std::to_string(x1.size()) + " pixels in view 1 but " +
                std::to_string(x2.size()) + " in view 2");
  }
  BatchTriangulation out;
  out.points.reserve(x1.size());
  out.rms_px.reserve(x1.size());
  auto& s = out.summary;
  s.num_points = static_cast<int>(x1.size());
  s.refined = options.refine;
  double linear_sq = 0.0;
  double final_sq = 0.0;
  for (size_t i = 0; i < x1.size(); ++i) {
    Triangulation t;
    try {
      t = triangulate(P1, P2, x1[i], x2[i], options);
    } catch (const Error& e) {
      throw Error("point " + std::to_string(i + 1) + ": " + e.what());
    }
    out.points.push_back(t.X);
    out.rms_px.push_back(t.rms_px);
    s.total_iterations += t.summary.iterations;
    if (t.summary.termination == TriangulationTermination::kMaxEvaluations) ++s.not_converged;
    linear_sq += t.summary.linear_rms_px * t.summary.linear_rms_px;
    final_sq += t.rms_px * t.rms_px;
    s.max_rms_px = std::max(s.max_rms_px, t.rms_px);
  }
  if (!x1.empty()) {
    s.linear_rms_px = std::sqrt(linear_sq / static_cast<double>(x1.size()));
    s.final_rms_px = std::sqrt(final_sq / static_cast<double>(x1.size()));
  }
  out.summary.message = core::first_line(out.summary.brief());
  return out;
}

// Two views from one centre see no depth: every pair of rays meets at that centre, so each point
// would "triangulate" to it (issue 16: the same calibration given as both cameras).
void require_distinct_centres(const Matrix34d& P1, const Matrix34d& P2) {
  const Eigen::Vector3d c1 = centre_of(P1);
  const Eigen::Vector3d c2 = centre_of(P2);
  const double scale = std::max({1.0, c1.norm(), c2.norm()});
  if (!((c1 - c2).norm() > 1e-9 * scale)) {
    throw Error(
        "triangulation: the two cameras have the same centre (the same calibration given twice?); "
        "they see no depth");
  }
}

}  // namespace proprio::geometry
