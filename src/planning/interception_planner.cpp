#include "proprio/planning/interception_planner.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>

#include "proprio/core/error.hpp"
#include "text.hpp"

namespace proprio::planning {

using detail::cat;
using detail::num;

const char* to_string(PriorMode mode) {
  switch (mode) {
    case PriorMode::kBoth:
      return "both";
    case PriorMode::kEnergy:
      return "energy";
    case PriorMode::kPrecision:
      return "precision";
  }
  return "?";
}

PriorMode prior_mode_from_string(const std::string& name) {
  if (name == "both") return PriorMode::kBoth;
  if (name == "energy") return PriorMode::kEnergy;
  if (name == "precision") return PriorMode::kPrecision;
  throw Error(cat({"unknown prior '", name, "' (both, energy or precision)"}));
}

void PlannerOptions::validate() const {
  require(std::isfinite(energy_only_std) && energy_only_std > 0,
          "PlannerOptions: energy_only_std must be > 0 m");
  require(std::isfinite(window) && window >= 0 && window <= 60,
          "PlannerOptions: window must be in [0, 60] s");
  require(time_samples >= 1 && time_samples <= 10000,
          "PlannerOptions: time_samples must be in [1, 10000]");
  require(starts >= 1 && starts <= 100, "PlannerOptions: starts must be in [1, 100]");
  require(max_iterations >= 0 && max_iterations <= 10000,
          "PlannerOptions: max_iterations must be in [0, 10000]");
  require(std::isfinite(tolerance) && tolerance >= 0, "PlannerOptions: tolerance must be >= 0");
  require(std::isfinite(reach_tolerance) && reach_tolerance >= 0,
          "PlannerOptions: reach_tolerance must be >= 0 m");
  require(std::isfinite(plane_tolerance) && plane_tolerance >= 0,
          "PlannerOptions: plane_tolerance must be >= 0 m");
  require(std::isfinite(time_quantum) && time_quantum >= 0 && time_quantum <= 1,
          "PlannerOptions: time_quantum must be in [0, 1] s");
}

TargetForecast::TargetForecast(const TargetFilter& filter, double t_end)
    : dt_(filter.options().dt) {
  frames_.push_back(filter.estimate());
  const double span = std::max(0.0, t_end - filter.estimate().t);
  const int steps = static_cast<int>(std::ceil(span / dt_ - 1e-9)) + 2;
  for (auto& e : filter.predict(steps)) frames_.push_back(e);
}

void TargetForecast::at(double t, Eigen::Vector3d* mean, Eigen::Matrix3d* cov) const {
  const int n = static_cast<int>(frames_.size());
  const double s = std::clamp((t - frames_.front().t) / dt_, 0.0, static_cast<double>(n - 1));
  const int i = std::min(static_cast<int>(std::floor(s)), n - 2);
  const double u = s - i;
  auto pos = [&](int k) {
    return frames_[static_cast<std::size_t>(std::clamp(k, 0, n - 1))].position();
  };
  const double u2 = u * u, u3 = u2 * u;
  *mean = 0.5 * ((-u3 + 2 * u2 - u) * pos(i - 1) + (3 * u3 - 5 * u2 + 2) * pos(i) +
                 (-3 * u3 + 4 * u2 + u) * pos(i + 1) + (u3 - u2) * pos(i + 2));
  *cov = (1 - u) * frames_[static_cast<std::size_t>(i)].position_cov() +
         u * frames_[static_cast<std::size_t>(i) + 1].position_cov();
}

namespace {

using Vector4d = Eigen::Vector4d;
using Matrix4d = Eigen::Matrix4d;

struct Eval {
  double J = 0;
  double h = 0;  // J - |w|^2 / 2
  Eigen::Vector2d w = Eigen::Vector2d::Zero();
  bool ok = false;
};

// The negative log posterior over normalised variables u in [0, 1]^4 (theta, l, gamma, t).
class Objective {
 public:
  Objective(const GridCostModel& model, const TargetForecast& forecast, const PlannerOptions& o,
            double t_lo, double t_hi)
      : model_(model), forecast_(forecast), o_(o) {
    const GridSpec& g = model.grid();
    lo_ << g.theta.min, g.length.min, g.gamma.min, t_lo;
    hi_ << g.theta.max, g.length.max, g.gamma.max, t_hi;
    p0_ = g.start.head<2>();
  }

  [[nodiscard]] Vector4d to_z(const Vector4d& u) const { return lo_ + u.cwiseProduct(hi_ - lo_); }
  [[nodiscard]] Vector4d to_u(const Vector4d& z) const {
    Vector4d u;
    for (int i = 0; i < 4; ++i) u[i] = hi_[i] > lo_[i] ? (z[i] - lo_[i]) / (hi_[i] - lo_[i]) : 0;
    return u.cwiseMax(0).cwiseMin(1);
  }
  [[nodiscard]] bool free(int i) const { return hi_[i] > lo_[i]; }
  [[nodiscard]] Eigen::Vector2d end_point(const Vector4d& z) const {
    return p0_ + z[1] * Eigen::Vector2d(std::sin(z[0]), std::cos(z[0]));
  }

  Eval operator()(const Vector4d& u) {
    ++evaluations;
    const Vector4d z = to_z(u);
    const Eigen::Vector3d psi = z.head<3>();
    Eigen::Vector3d mean;
    Eigen::Matrix3d cov;
    forecast_.at(z[3], &mean, &cov);
    const double va = o_.mode == PriorMode::kEnergy ? o_.energy_only_std * o_.energy_only_std
                                                    : model_.arm_variance(psi);
    const Eigen::Matrix2d S = cov.topLeftCorner<2, 2>() + va * Eigen::Matrix2d::Identity();
    const Eigen::LLT<Eigen::Matrix2d> llt(S);
    Eval e;
    if (llt.info() != Eigen::Success) return e;
    const Eigen::Matrix2d L = llt.matrixL();
    e.w = L.triangularView<Eigen::Lower>().solve(end_point(z) - mean.head<2>());
    e.h = std::log(L(0, 0)) + std::log(L(1, 1)) + std::log(2 * std::numbers::pi);
    if (o_.mode != PriorMode::kPrecision) e.h += model_.log_energy(psi);  // eq 3.49
    e.J = 0.5 * e.w.squaredNorm() + e.h;
    e.ok = std::isfinite(e.J);
    return e;
  }

  int evaluations = 0;

 private:
  const GridCostModel& model_;
  const TargetForecast& forecast_;
  const PlannerOptions& o_;
  Vector4d lo_, hi_;
  Eigen::Vector2d p0_;
};

struct Run {
  Vector4d u = Vector4d::Zero();
  Eval e;
  int iterations = 0;
  std::string termination;
};

// Levenberg-Marquardt-damped Gauss-Newton in the box [0, 1]^4 over the variables in `active`.
Run gauss_newton(Objective& f, const Vector4d& u, const std::array<bool, 4>& active,
                 const PlannerOptions& o) {
  Run run;
  run.u = u;
  run.e = f(u);
  run.termination = "iteration limit";
  double lambda = 1e-3;
  constexpr double kStep = 1e-5;
  for (int it = 0; it < o.max_iterations; ++it) {
    run.iterations = it + 1;
    Eigen::Matrix<double, 2, 4> Jw = Eigen::Matrix<double, 2, 4>::Zero();
    Vector4d gh = Vector4d::Zero();
    Matrix4d Hh = Matrix4d::Zero();
    // Central differences, moved inside the box where a bound is near.
    Vector4d base = run.u;
    for (int i = 0; i < 4; ++i) {
      if (active[static_cast<std::size_t>(i)]) base[i] = std::clamp(base[i], kStep, 1 - kStep);
    }
    const Eval e0 = f(base);
    std::array<Eval, 4> ep, em;
    for (int i = 0; i < 4; ++i) {
      if (!active[static_cast<std::size_t>(i)]) continue;
      Vector4d d = Vector4d::Zero();
      d[i] = kStep;
      ep[static_cast<std::size_t>(i)] = f(base + d);
      em[static_cast<std::size_t>(i)] = f(base - d);
      const Eval& a = ep[static_cast<std::size_t>(i)];
      const Eval& b = em[static_cast<std::size_t>(i)];
      Jw.col(i) = (a.w - b.w) / (2 * kStep);
      gh[i] = (a.h - b.h) / (2 * kStep);
      Hh(i, i) = (a.h - 2 * e0.h + b.h) / (kStep * kStep);
    }
    for (int i = 0; i < 4; ++i) {
      for (int j = i + 1; j < 4; ++j) {
        if (!active[static_cast<std::size_t>(i)] || !active[static_cast<std::size_t>(j)]) continue;
        Vector4d di = Vector4d::Zero(), dj = Vector4d::Zero();
        di[i] = kStep;
        dj[j] = kStep;
        Hh(i, j) = Hh(j, i) = (f(base + di + dj).h - f(base + di - dj).h - f(base - di + dj).h +
                               f(base - di - dj).h) /
                              (4 * kStep * kStep);
      }
    }
    const Eigen::SelfAdjointEigenSolver<Matrix4d> eig(Hh);
    const Matrix4d Hh_psd = eig.eigenvectors() * eig.eigenvalues().cwiseMax(0.0).asDiagonal() *
                            eig.eigenvectors().transpose();
    Matrix4d H = Jw.transpose() * Jw + Hh_psd;
    Vector4d g = Jw.transpose() * run.e.w + gh;
    // Variables held by an active bound, or not optimised, take no step.
    std::array<bool, 4> move{};
    for (int i = 0; i < 4; ++i) {
      const bool at_lo = run.u[i] <= 0 && g[i] > 0;
      const bool at_hi = run.u[i] >= 1 && g[i] < 0;
      move[static_cast<std::size_t>(i)] = active[static_cast<std::size_t>(i)] && !at_lo && !at_hi;
      if (!move[static_cast<std::size_t>(i)]) {
        H.row(i).setZero();
        H.col(i).setZero();
        H(i, i) = 1;
        g[i] = 0;
      }
    }
    if (g.norm() < 1e-12) {
      run.termination = "gradient zero";
      break;
    }
    bool accepted = false;
    Vector4d step = Vector4d::Zero();
    Eval next;
    for (int tries = 0; tries < 12 && !accepted; ++tries) {
      Matrix4d A = H;
      A.diagonal() += lambda * (H.diagonal() + Vector4d::Constant(1e-9));
      step = -A.ldlt().solve(g);
      const Vector4d u_new = (run.u + step).cwiseMax(0).cwiseMin(1);
      step = u_new - run.u;
      next = f(u_new);
      if (next.ok && next.J < run.e.J) {
        accepted = true;
        lambda = std::max(lambda / 3, 1e-12);
      } else {
        lambda *= 8;
      }
    }
    if (!accepted) {
      run.termination = "no further decrease";
      break;
    }
    const double decrease = run.e.J - next.J;
    run.u += step;
    run.e = next;
    if (decrease < o.tolerance && step.norm() < 1e-7) {
      run.termination = "converged";
      break;
    }
  }
  return run;
}

}  // namespace

InterceptionPlan plan_interception(const TargetFilter& filter, const GridCostModel& model,
                                   double t_now, const PlannerOptions& options, double t_latest) {
  options.validate();
  const auto clock0 = std::chrono::steady_clock::now();
  ensure(std::isfinite(t_now) && t_now >= filter.estimate().t - 1e-9,
         "plan time must not be before the filter's latest measurement");
  const GridSpec& g = model.grid();
  double t_lo = t_now + g.duration;
  if (options.time_quantum > 0)
    t_lo = std::ceil(t_lo / options.time_quantum - 1e-9) * options.time_quantum;
  ensure(!std::isnan(t_latest), "the latest interception time must not be NaN");
  const double t_hi = std::min(t_lo + options.window, t_latest);
  InterceptionPlan plan;
  if (t_hi < t_lo) {
    plan.why_not = cat({"too late: the earliest interception, ", num(t_lo),
                        " s, is after the latest allowed, ", num(t_latest), " s"});
    return plan;
  }
  const TargetForecast forecast(filter, t_hi);
  Objective f(model, forecast, options, t_lo, t_hi);

  auto finish = [&](InterceptionPlan& p) -> InterceptionPlan& {
    p.summary.evaluations = f.evaluations;
    p.summary.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - clock0).count();
    return p;
  };
  for (const auto& fr : forecast.frames()) {
    if (!fr.mean.allFinite() || !fr.cov.allFinite()) {
      plan.why_not = "the target's prediction diverged (the learned transition is unstable)";
      return finish(plan);
    }
  }

  // Sparse sample: times over the window, each gamma of the grid, theta and l aimed at the
  // predicted target (clamped to the grid).
  struct Sample {
    Vector4d u;
    double J;
  };
  std::vector<Sample> samples;
  const int nt = options.time_samples;
  for (int j = 0; j < nt; ++j) {
    const double t = nt == 1 ? t_lo : t_lo + (t_hi - t_lo) * j / (nt - 1);
    Eigen::Vector3d mean;
    Eigen::Matrix3d cov;
    forecast.at(t, &mean, &cov);
    const Eigen::Vector2d d = mean.head<2>() - g.start.head<2>();
    const double theta = std::atan2(d.x(), d.y());  // p2 = p0 + l (sin theta, cos theta)
    for (int k = 0; k < g.gamma.count; ++k) {
      const Vector4d u = f.to_u(Vector4d(theta, d.norm(), g.gamma.value(k), t));
      const Eval e = f(u);
      if (e.ok) samples.push_back({u, e.J});
    }
  }
  plan.summary.samples = static_cast<int>(samples.size());
  if (samples.empty()) {
    plan.why_not = "the objective is not finite anywhere in the window";
    return finish(plan);
  }
  std::sort(samples.begin(), samples.end(),
            [](const Sample& a, const Sample& b) { return a.J < b.J; });
  plan.summary.initial_objective = samples.front().J;

  // Rounds an interception time to the control period, inside [t_lo, t_hi].
  auto quantise = [&](double t) {
    const double q = options.time_quantum;
    const double top = std::max(t_lo, std::floor(t_hi / q + 1e-9) * q);
    return std::clamp(std::round(t / q) * q, t_lo, top);
  };
  std::array<bool, 4> active{};
  for (int i = 0; i < 4; ++i) active[static_cast<std::size_t>(i)] = f.free(i);
  Run best;
  best.e.J = std::numeric_limits<double>::infinity();
  const int starts = std::min<int>(options.starts, static_cast<int>(samples.size()));
  for (int s = 0; s < starts; ++s) {
    Run r = gauss_newton(f, samples[static_cast<std::size_t>(s)].u, active, options);
    plan.summary.iterations += r.iterations;
    if (r.e.ok && r.e.J < best.e.J) best = r;
  }
  if (options.time_quantum > 0 && f.free(3)) {
    // Round the time to the control period, then re-optimise psi at that time.
    Vector4d z = f.to_z(best.u);
    z[3] = quantise(z[3]);
    std::array<bool, 4> psi_only = active;
    psi_only[3] = false;
    Run r = gauss_newton(f, f.to_u(z), psi_only, options);
    plan.summary.iterations += r.iterations;
    best = r;
  }
  plan.summary.termination = best.termination;

  Vector4d z = f.to_z(best.u);
  if (options.time_quantum > 0 && f.free(3)) z[3] = quantise(z[3]);
  const Eval e = f(f.to_u(z));
  Eigen::Vector3d mean;
  Eigen::Matrix3d cov;
  forecast.at(z[3], &mean, &cov);
  plan.psi = {z[0], z[1], z[2]};
  plan.t_intercept = z[3];
  plan.t_start = z[3] - g.duration;
  plan.end_point = g.end_point(plan.psi);
  plan.predicted_target = mean;
  plan.target_cov = cov.topLeftCorner<2, 2>();
  plan.predicted_sigma = std::sqrt(plan.target_cov.trace() / 2);
  const double va = options.mode == PriorMode::kEnergy
                        ? options.energy_only_std * options.energy_only_std
                        : model.arm_variance(z.head<3>());
  plan.arm_sigma = std::sqrt(va);
  plan.log_energy = model.log_energy(z.head<3>());
  plan.objective = e.J;
  plan.summary.final_objective = e.J;
  const bool finite = z.allFinite() && plan.end_point.allFinite() && mean.allFinite() &&
                      cov.allFinite() && std::isfinite(e.J);
  if (!finite) {
    plan.why_not = "the optimisation produced a non-finite plan";
    return finish(plan);
  }
  const Eigen::Matrix2d S = plan.target_cov + va * Eigen::Matrix2d::Identity();
  const double s_max =
      std::sqrt(Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(S).eigenvalues()(1));
  const double gap = (plan.end_point.head<2>() - mean.head<2>()).norm();
  const double sz = std::sqrt(std::max(cov(2, 2), 0.0));
  if (gap > options.reach_tolerance + 2 * s_max) {
    plan.why_not =
        cat({"the target cannot be reached in time: its predicted path stays ", num(gap),
             " m outside the arm's reach between ", num(t_lo), " and ", num(t_hi), " s"});
  } else if (std::abs(mean.z() - g.start.z()) > options.plane_tolerance + 3 * sz) {
    plan.why_not = cat({"the target is predicted ", num(mean.z() - g.start.z()),
                        " m off the arm's plane of motion at the interception"});
  } else {
    plan.feasible = true;
  }
  return finish(plan);
}

}  // namespace proprio::planning
