#pragma once
// Choosing the interception (thesis 3.6, eqs 3.44-3.49; SPEC section 2): the trajectory psi and
// the time t at which the arm meets the target, as the maximum of
//   p(psi, t | alpha, beta) ~ integral N(x | arm(psi, t), Sigma_psi) p(x | beta, t) dx  p(psi),
// where arm(psi, t) is the trajectory's end point p2 (the arm starts at rest at the grid's start
// at t - duration and arrives at rest at t), p(x | beta, t) = N(mu_t, M_t) the filter's
// prediction of the target's position (eqs 3.27-3.29), Sigma_psi the arm's end-point covariance
// (eq 3.43) and p(psi) ~ 1 / sum_k E_k(psi) (eq 3.49). The integral of the two Gaussians is
// N(p2 | mu_t, Sigma_psi + M_t) (eq 3.48), so the negative log posterior is
//   J = 1/2 r^T S^-1 r + 1/2 log det(2 pi S) + log E(psi),  r = p2 - mu_t, S = Sigma_psi + M_t.
// The psi family is planar (3.5.1), so r and S are taken in the horizontal plane of the move; the
// log det term is what makes a noisier target worth meeting earlier (Fig 3-11).
//
// J is minimised over (theta, l, gamma, t) by Gauss-Newton (the Gauss-Newton Hessian of the
// residual term plus the finite-difference Hessian of the rest, Levenberg-Marquardt damped,
// within the grid's box) from the best points of a sparse sample of the domain.

#include <Eigen/Core>
#include <limits>
#include <string>
#include <vector>

#include "proprio/planning/target_filter.hpp"
#include "proprio/planning/trajectory_grid.hpp"

namespace proprio::planning {

/// The priors of 3.7: energy and precision; energy only (the arm's std fixed); precision only
/// (uniform p(psi)).
enum class PriorMode { kBoth, kEnergy, kPrecision };
const char* to_string(PriorMode mode);
/// "both", "energy" or "precision"; throws Error otherwise.
PriorMode prior_mode_from_string(const std::string& name);

struct PlannerOptions {
  PriorMode mode = PriorMode::kBoth;
  /// The arm's end-point std per axis in energy-only mode, m (the thesis's 0.01).
  double energy_only_std = 0.01;
  /// Interception times considered: [t_now + duration, t_now + duration + window], s.
  double window = 1.5;
  /// Interception times in the sparse sample (each with every gamma of the grid, theta and l
  /// aimed at the predicted target).
  int time_samples = 24;
  /// Gauss-Newton runs from this many of the best samples; the best result wins.
  int starts = 3;
  int max_iterations = 50;
  /// Stop when the objective falls by less than this (absolute; it is a log-probability).
  double tolerance = 1e-9;
  /// The plan is infeasible when its end point stays farther than this plus two standard
  /// deviations of S from the predicted target, m: the target does not come within reach.
  double reach_tolerance = 0.005;
  /// And when the predicted target is farther than this plus three of its standard deviations
  /// from the arm's horizontal plane, m.
  double plane_tolerance = 0.03;
  /// The interception time is rounded to a multiple of this (the control period), s; 0 = none.
  double time_quantum = 0;
  /// Throws Error when an option is out of range.
  void validate() const;
};

struct PlanSummary {
  int samples = 0;               ///< sparse-sample evaluations
  int iterations = 0;            ///< Gauss-Newton iterations, summed over the starts
  int evaluations = 0;           ///< objective evaluations in all
  double initial_objective = 0;  ///< best sample's J
  double final_objective = 0;    ///< J at the plan
  std::string termination;       ///< why the last Gauss-Newton run stopped
  double seconds = 0;            ///< wall time of plan_interception
};

struct InterceptionPlan {
  bool feasible = false;
  std::string why_not;  ///< when !feasible: a sentence for the user
  robot::TrajectoryParams psi;
  double t_intercept = 0;  ///< s, same clock as the measurements
  double t_start = 0;      ///< t_intercept - duration: when the arm leaves the start point, s
  Eigen::Vector3d end_point = Eigen::Vector3d::Zero();         ///< p2, world, m
  Eigen::Vector3d predicted_target = Eigen::Vector3d::Zero();  ///< mu at t_intercept, m
  Eigen::Matrix2d target_cov = Eigen::Matrix2d::Zero();        ///< M's horizontal block there, m^2
  /// The filter's predicted position std at the interception, per horizontal axis:
  /// sqrt(trace(target_cov) / 2), m.
  double predicted_sigma = 0;
  double arm_sigma = 0;   ///< sqrt of Sigma_psi per axis, m
  double log_energy = 0;  ///< log of the trajectory's energy (eq 3.41), log(N m s)
  double objective = 0;   ///< J at the plan
  PlanSummary summary;
};

/// The filter's predictions as a function of time, for the planner: means by Catmull-Rom and
/// covariances linearly between frames, from the filter's latest estimate to `t_end`.
class TargetForecast {
 public:
  TargetForecast(const TargetFilter& filter, double t_end);
  [[nodiscard]] double t_begin() const { return frames_.front().t; }
  [[nodiscard]] double t_end() const { return frames_.back().t; }
  /// Mean position (m) and its covariance (m^2) at t, clamped to [t_begin, t_end].
  void at(double t, Eigen::Vector3d* mean, Eigen::Matrix3d* cov) const;
  [[nodiscard]] const std::vector<TargetEstimate>& frames() const { return frames_; }

 private:
  std::vector<TargetEstimate> frames_;
  double dt_;
};

/// Plans the interception at time t_now (the arm at rest at the grid's start; t_now at or after
/// the filter's latest measurement), meeting the target between t_now + duration and the end of
/// the window, and not after t_latest (s). Never returns a non-finite plan: when the predicted
/// target does not come within reach in that time, or leaves the arm's plane, or t_latest is too
/// early, the plan is infeasible and says why. Throws Error for invalid options or a t_now before
/// the filter's time.
InterceptionPlan plan_interception(const TargetFilter& filter, const GridCostModel& model,
                                   double t_now, const PlannerOptions& options = {},
                                   double t_latest = std::numeric_limits<double>::infinity());

}  // namespace proprio::planning
