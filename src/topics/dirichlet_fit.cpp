#include "proprio/topics/dirichlet_fit.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <utility>

#include "proprio/core/error.hpp"
#include "special_functions.hpp"

namespace proprio::topics {

namespace {

// Halvings of one Newton step before a fixed-point step replaces it.
constexpr int kMaxHalvings = 30;
// The smallest mean log p accepted: alpha_k stays above ~1e-100, where psi'(alpha_k) is finite.
constexpr double kMinMeanLog = -1e100;

// The log-likelihood per sample (eq 4 divided by N) and the size of its terms, which bounds its
// rounding error.
struct Likelihood {
  double value = 0.0;
  double scale = 0.0;
};

Likelihood likelihood(const Eigen::VectorXd& alpha, const Eigen::VectorXd& mean_log) {
  Likelihood l;
  const double a = std::lgamma(alpha.sum());
  l.value = a;
  l.scale = std::abs(a);
  for (Eigen::Index k = 0; k < alpha.size(); ++k) {
    const double g = std::lgamma(alpha(k));
    const double t = (alpha(k) - 1.0) * mean_log(k);
    l.value += t - g;
    l.scale += std::abs(g) + std::abs(t);
  }
  return l;
}

// g / N (eq 6): psi(sum alpha) - psi(alpha_k) + log p-bar_k.
void gradient(const Eigen::VectorXd& alpha, const Eigen::VectorXd& mean_log, Eigen::VectorXd& g) {
  const double ps = detail::digamma(alpha.sum());
  for (Eigen::Index k = 0; k < alpha.size(); ++k) {
    g(k) = ps - detail::digamma(alpha(k)) + mean_log(k);
  }
}

// One fixed-point step: psi(alpha_k) = psi(s) + log p-bar_k, s the precision before the step.
void fixed_point_from(double precision, const Eigen::VectorXd& mean_log, Eigen::VectorXd& alpha) {
  const double ps = detail::digamma(precision);
  for (Eigen::Index k = 0; k < alpha.size(); ++k) {
    alpha(k) = detail::inverse_digamma(ps + mean_log(k));
  }
}

bool positive_finite(const Eigen::VectorXd& v) {
  // Above the smallest normal double, so that 1/alpha and psi(alpha) stay finite.
  return (v.array() >= 1e-300).all() && v.allFinite();
}

std::string number(double v) {
  std::ostringstream s;
  s.precision(6);
  s << v;
  return s.str();
}

}  // namespace

void DirichletFitOptions::validate() const {
  if (!(std::isfinite(tolerance) && tolerance > 0.0)) {
    throw Error("Dirichlet fit: tolerance must be positive and finite, not " + number(tolerance));
  }
  if (max_iterations < 1) {
    throw Error("Dirichlet fit: max_iterations must be at least 1, not " +
                std::to_string(max_iterations));
  }
  if (fixed_point_steps < 1 || fixed_point_steps > max_iterations) {
    throw Error("Dirichlet fit: fixed_point_steps must be in [1, max_iterations], not " +
                std::to_string(fixed_point_steps));
  }
  if (!(std::isfinite(max_precision) && max_precision >= 1.0)) {
    throw Error("Dirichlet fit: max_precision must be finite and at least 1, not " +
                number(max_precision));
  }
  proportions.validate();
}

const char* to_string(DirichletStop stop) {
  switch (stop) {
    case DirichletStop::kConverged:
      return "converged";
    case DirichletStop::kMaxIterations:
      return "max-iterations";
    case DirichletStop::kPrecisionBound:
      return "precision-bound";
    case DirichletStop::kNoProgress:
      return "no-progress";
  }
  return "?";
}

std::string DirichletFitSummary::brief() const {
  std::ostringstream s;
  s << to_string(stop) << " after " << fixed_point_iterations << " fixed-point + "
    << newton_iterations << " Newton iterations (" << step_halvings << " halvings, "
    << newton_fallbacks << " fallbacks), log-likelihood " << log_likelihood << " over " << count
    << " samples, gradient max-norm " << gradient_max_norm << ", " << clamped
    << " proportions clamped to the floor";
  if (!converged) s << ": " << message;
  return s.str();
}

DirichletFit fit_dirichlet(const DirichletStats& stats, const DirichletFitOptions& options) {
  options.validate();
  require(stats.count() > 0.0, "Dirichlet fit: no samples");
  // Messages built only on failure: fits run in EM's inner loop (dirichlet_mixture).
  if (stats.dim() < 2) {
    throw Error("Dirichlet fit: at least 2 proportions per sample are needed, not " +
                std::to_string(stats.dim()));
  }
  const Eigen::VectorXd& m = stats.mean_log();
  for (Eigen::Index k = 0; k < m.size(); ++k) {
    if (!(std::isfinite(m(k)) && m(k) >= kMinMeanLog)) {
      throw Error("Dirichlet fit: the mean log-proportion " + std::to_string(k) + " is " +
                  number(m(k)) + ", not finite or below -1e100");
    }
  }
  const Eigen::Index T = m.size();
  const double n = stats.count();

  DirichletFitSummary sum;
  sum.count = n;
  sum.clamped = stats.clamped();
  Eigen::VectorXd alpha(T);

  // The maximum's distance from infinite precision: -log sum_k exp(log p-bar_k) >= 0, zero only
  // when every sample is the same point (Jensen). s0 = (T - 1) / (2 gap) is Minka's approximate
  // precision (section 3) with the normalised geometric means as the mean.
  const double top = m.maxCoeff();
  const double gap = -(top + std::log((m.array() - top).exp().sum()));
  const auto at_bound = [&] {
    alpha = options.max_precision * (m.array() - top).exp() / (m.array() - top).exp().sum();
    sum.stop = DirichletStop::kPrecisionBound;
    sum.message = "the likelihood rises without bound towards precision max_precision = " +
                  number(options.max_precision) +
                  " (samples (nearly) all the same point: one sample, or duplicates?); alpha is "
                  "the samples' normalised geometric mean times max_precision";
  };

  Eigen::VectorXd g(T);
  if (!(gap > 0.0)) {
    at_bound();
  } else {
    const double s0 = std::min(static_cast<double>(T - 1) / (2.0 * gap), options.max_precision);
    fixed_point_from(s0, m, alpha);
    sum.fixed_point_iterations = 1;
    Eigen::VectorXd step(T);
    Eigen::VectorXd candidate(T);
    for (;;) {
      if (!positive_finite(alpha)) {
        throw InternalError("Dirichlet fit: alpha left the positive reals");
      }
      if (alpha.sum() > options.max_precision) {
        at_bound();
        break;
      }
      gradient(alpha, m, g);
      const double gmax = g.cwiseAbs().maxCoeff();
      if (gmax <= options.tolerance) {
        sum.stop = DirichletStop::kConverged;
        sum.message = "the gradient's max-norm is within tolerance x N";
        break;
      }
      if (sum.iterations() >= options.max_iterations) {
        sum.stop = DirichletStop::kMaxIterations;
        sum.message = "max_iterations = " + std::to_string(options.max_iterations) +
                      " reached with the gradient's max-norm at " + number(gmax * n) + " > " +
                      number(options.tolerance * n) + " (tolerance x N)";
        break;
      }
      if (sum.fixed_point_iterations < options.fixed_point_steps) {
        fixed_point_from(alpha.sum(), m, alpha);
        ++sum.fixed_point_iterations;
        continue;
      }
      // Newton: H = diag(q) + z 1 1^T (per sample), q_k = -psi'(alpha_k), z = psi'(s);
      // H^-1 g by the matrix inversion lemma: (g_k - b) / q_k, b = sum_j g_j/q_j /
      // (1/z + sum_j 1/q_j).
      const double z = detail::trigamma(alpha.sum());
      double num = 0.0;
      double den = 1.0 / z;
      for (Eigen::Index k = 0; k < T; ++k) {
        const double q = -detail::trigamma(alpha(k));
        step(k) = q;
        num += g(k) / q;
        den += 1.0 / q;
      }
      const double b = num / den;
      for (Eigen::Index k = 0; k < T; ++k) step(k) = (g(k) - b) / step(k);
      const Likelihood now = likelihood(alpha, m);
      const double slack = 1e-13 * now.scale;
      double t = 1.0;
      bool accepted = false;
      for (int h = 0; h <= kMaxHalvings; ++h) {
        candidate = alpha - t * step;
        if (positive_finite(candidate) && likelihood(candidate, m).value >= now.value - slack) {
          accepted = true;
          break;
        }
        ++sum.step_halvings;
        t *= 0.5;
      }
      ++sum.newton_iterations;
      if (accepted) {
        alpha.swap(candidate);
        continue;
      }
      // Newton found no better point: a fixed-point step instead (it never lowers L).
      ++sum.newton_fallbacks;
      candidate = alpha;
      fixed_point_from(alpha.sum(), m, candidate);
      if (((candidate - alpha).array().abs() <= 1e-15 * alpha.array()).all()) {
        sum.stop = DirichletStop::kNoProgress;
        sum.message =
            "neither a Newton nor a fixed-point step moves alpha any more, with the "
            "gradient's max-norm at " +
            number(gmax * n) + " > " + number(options.tolerance * n) + " (tolerance x N): rounding";
        break;
      }
      alpha.swap(candidate);
    }
  }
  sum.converged = sum.stop == DirichletStop::kConverged;
  gradient(alpha, m, g);
  sum.gradient_max_norm = g.cwiseAbs().maxCoeff() * n;
  sum.log_likelihood = likelihood(alpha, m).value * n;
  ensure(std::isfinite(sum.log_likelihood) && std::isfinite(sum.gradient_max_norm),
         "Dirichlet fit: a non-finite log-likelihood or gradient");
  return DirichletFit{Dirichlet(std::move(alpha)), std::move(sum)};
}

DirichletFit fit_dirichlet(const Eigen::Ref<const Eigen::MatrixXd>& proportions,
                           const DirichletFitOptions& options) {
  options.validate();
  return fit_dirichlet(DirichletStats::of_proportions(proportions, options.proportions), options);
}

DirichletFit fit_dirichlet_log(const Eigen::Ref<const Eigen::MatrixXd>& log_proportions,
                               const DirichletFitOptions& options) {
  options.validate();
  return fit_dirichlet(DirichletStats::of_log_proportions(log_proportions, options.proportions),
                       options);
}

}  // namespace proprio::topics
