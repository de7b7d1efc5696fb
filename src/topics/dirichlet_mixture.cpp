#include "proprio/topics/dirichlet_mixture.hpp"

#include "proprio/core/fields.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>
#include <utility>

#include "kmeans_seeding.hpp"
#include "proprio/core/error.hpp"
#include "proprio/core/random.hpp"
#include "special_functions.hpp"

namespace proprio::topics {
namespace {

double log_sum_exp(const Eigen::Ref<const Eigen::VectorXd>& x) {
  const double m = x.maxCoeff();
  if (!std::isfinite(m)) return m;
  return m + std::log((x.array() - m).exp().sum());
}

/// Lloyd iterations after the k-means++ seeding of an EM start.
constexpr int kLloydIterations = 20;

/// Hard responsibilities (n x k) of one k-means++ start over the rows of x.
Eigen::MatrixXd kmeans_start(const Eigen::MatrixXd& x, int k, core::Rng& rng) {
  const Eigen::Index n = x.rows();
  Eigen::MatrixXd centres = detail::kmeans_pp_seeds(x, k, rng);
  std::vector<int> a(static_cast<std::size_t>(n), -1);
  for (int it = 0; it < kLloydIterations; ++it) {
    bool moved = false;
    for (Eigen::Index i = 0; i < n; ++i) {
      Eigen::Index best = 0;
      (centres.rowwise() - x.row(i)).rowwise().squaredNorm().minCoeff(&best);
      if (a[static_cast<std::size_t>(i)] != static_cast<int>(best)) {
        a[static_cast<std::size_t>(i)] = static_cast<int>(best);
        moved = true;
      }
    }
    if (!moved) break;
    Eigen::MatrixXd sum = Eigen::MatrixXd::Zero(k, x.cols());
    Eigen::VectorXd count = Eigen::VectorXd::Zero(k);
    for (Eigen::Index i = 0; i < n; ++i) {
      sum.row(a[static_cast<std::size_t>(i)]) += x.row(i);
      count(a[static_cast<std::size_t>(i)]) += 1;
    }
    for (int j = 0; j < k; ++j) {
      if (count(j) > 0) centres.row(j) = sum.row(j) / count(j);
    }
  }
  Eigen::MatrixXd r = Eigen::MatrixXd::Zero(n, k);
  for (Eigen::Index i = 0; i < n; ++i) r(i, a[static_cast<std::size_t>(i)]) = 1.0;
  return r;
}

/// The M-step: each component fitted to its responsibility-weighted statistics. nullopt when a
/// component's effective count is below the minimum.
std::optional<DirichletMixture> m_step(const Eigen::MatrixXd& log_p, const Eigen::MatrixXd& r,
                                       const DirichletMixtureOptions& o) {
  DirichletMixture m;
  const auto n = static_cast<double>(log_p.rows());
  for (Eigen::Index j = 0; j < r.cols(); ++j) {
    DirichletStats s(static_cast<int>(log_p.cols()));
    for (Eigen::Index i = 0; i < log_p.rows(); ++i) {
      if (r(i, j) > 0.0) s.add_log(log_p.row(i).transpose(), r(i, j));
    }
    if (!(s.count() >= o.min_component_count)) return std::nullopt;
    DirichletFit f = fit_dirichlet(s, o.fit);
    const double w = s.count() / n;
    m.components.push_back({w, std::move(s), std::move(f.dirichlet)});
  }
  return m;
}

/// The E-step: responsibilities into r, returns the log-likelihood.
double e_step(const DirichletMixture& m, const Eigen::MatrixXd& log_p, Eigen::MatrixXd& r) {
  const Eigen::Index k = m.num_components();
  r.resize(log_p.rows(), k);
  Eigen::VectorXd l(k);
  double total = 0;
  for (Eigen::Index i = 0; i < log_p.rows(); ++i) {
    for (Eigen::Index j = 0; j < k; ++j) {
      const auto& c = m.components[static_cast<std::size_t>(j)];
      l(j) = std::log(c.weight) + c.dirichlet.log_density_of_log(log_p.row(i).transpose());
    }
    const double z = log_sum_exp(l);
    total += z;
    r.row(i) = (l.array() - z).exp().transpose();
  }
  return total;
}

std::string number(double v) {
  std::ostringstream s;
  s.precision(10);
  s << v;
  return s.str();
}

}  // namespace

void DirichletMixtureOptions::validate() const {
  require(max_components >= 1 && max_components <= 1000,
          "Dirichlet mixture: max_components must be in [1, 1000]");
  require(restarts >= 1 && restarts <= 1000, "Dirichlet mixture: restarts must be in [1, 1000]");
  require(max_iterations >= 1 && max_iterations <= 100000,
          "Dirichlet mixture: max_iterations must be in [1, 100000]");
  require(std::isfinite(tolerance) && tolerance > 0,
          "Dirichlet mixture: tolerance must be positive and finite");
  require(std::isfinite(min_component_count) && min_component_count >= 2,
          "Dirichlet mixture: min_component_count must be >= 2");
  fit.validate();
}

const char* to_string(MixtureStop stop) {
  switch (stop) {
    case MixtureStop::kOneComponent:
      return "one-component";
    case MixtureStop::kConverged:
      return "converged";
    case MixtureStop::kMaxIterations:
      return "max-iterations";
  }
  return "?";
}

double DirichletMixture::log_density_of_log(const Eigen::Ref<const Eigen::VectorXd>& log_p) const {
  if (components.size() == 1) return components[0].dirichlet.log_density_of_log(log_p);
  Eigen::VectorXd l(num_components());
  for (int j = 0; j < num_components(); ++j) {
    const auto& c = components[static_cast<std::size_t>(j)];
    l(j) = std::log(c.weight) + c.dirichlet.log_density_of_log(log_p);
  }
  return log_sum_exp(l);
}

void DirichletMixture::validate() const {
  require(!components.empty(), "Dirichlet mixture: no components");
  double sum = 0;
  for (const auto& c : components) {
    require(c.dirichlet.dim() == components[0].dirichlet.dim(),
            "Dirichlet mixture: components of different dimensions");
    require(std::isfinite(c.weight) && c.weight > 0,
            "Dirichlet mixture: a weight is not positive and finite: " + number(c.weight));
    sum += c.weight;
  }
  require(std::abs(sum - 1.0) <= 1e-6, "Dirichlet mixture: weights sum to " + number(sum));
}

std::string DirichletMixtureSummary::brief() const {
  std::ostringstream s;
  s << components << (components == 1 ? " component" : " components");
  if (bic.size() > 1) s << " (BIC among 1.." << bic.size() << ")";
  if (stop == MixtureStop::kOneComponent) {
    s << ", one Dirichlet (no EM)";
  } else {
    s << ", EM " << to_string(stop) << " after " << iterations << " iterations";
  }
  s << "; " << starts << " starts, " << degenerate << " degenerate";
  s.precision(8);
  s << "; log-likelihood " << log_likelihood;
  return s.str();
}

double dirichlet_mixture_bic(double log_likelihood, int k, int dim, int n) {
  const double p = static_cast<double>(k) * dim + k - 1.0;
  return -2.0 * log_likelihood + p * std::log(static_cast<double>(n));
}

DirichletMixtureFit fit_dirichlet_mixture_k(const Eigen::Ref<const Eigen::MatrixXd>& log_p, int k,
                                            const DirichletMixtureOptions& options) {
  options.validate();
  const auto n = static_cast<int>(log_p.rows());
  const auto t = static_cast<int>(log_p.cols());
  require(n >= 2, "Dirichlet mixture: at least 2 samples are needed, not " + std::to_string(n));
  require(k >= 1, "Dirichlet mixture: at least one component");
  const Eigen::MatrixXd lp = log_p;
  DirichletMixtureFit out;
  out.summary.samples = n;
  if (k == 1) {
    // The plain fit, the statistics accumulated as MoT's stats_of does (identical results).
    DirichletStats s(t);
    for (Eigen::Index i = 0; i < lp.rows(); ++i) s.add_log(lp.row(i).transpose());
    DirichletFit f = fit_dirichlet(s, options.fit);
    out.summary.log_likelihood = f.summary.log_likelihood;
    out.mixture.components.push_back({1.0, std::move(s), std::move(f.dirichlet)});
    out.summary.components = 1;
    out.summary.stop = MixtureStop::kOneComponent;
    out.summary.bic = {dirichlet_mixture_bic(out.summary.log_likelihood, 1, t, n)};
    out.summary.message = core::first_line(out.summary.brief());
    return out;
  }
  const Eigen::MatrixXd p = lp.array().exp().matrix();
  auto rng = core::Rng::stream(options.seed, static_cast<std::uint64_t>(k));
  double best = -std::numeric_limits<double>::infinity();
  for (int start = 0; start < options.restarts; ++start) {
    ++out.summary.starts;
    Eigen::MatrixXd r = kmeans_start(p, k, rng);
    std::optional<DirichletMixture> m;
    double ll = -std::numeric_limits<double>::infinity();
    int it = 0;
    MixtureStop stop = MixtureStop::kMaxIterations;
    for (it = 1; it <= options.max_iterations; ++it) {
      m = m_step(lp, r, options);
      if (!m) break;
      const double next = e_step(*m, lp, r);
      const bool done = it > 1 && next - ll < options.tolerance * n;
      ll = next;
      if (done) {
        stop = MixtureStop::kConverged;
        break;
      }
    }
    if (!m) {
      ++out.summary.degenerate;
      continue;
    }
    if (ll > best) {
      best = ll;
      out.mixture = std::move(*m);
      out.summary.iterations = std::min(it, options.max_iterations);
      out.summary.stop = stop;
      out.summary.log_likelihood = ll;
    }
  }
  if (out.mixture.components.empty()) {
    throw Error("Dirichlet mixture: every start with " + std::to_string(k) + " components over " +
                std::to_string(n) + " samples left a component with fewer than " +
                number(options.min_component_count) + " effective samples");
  }
  out.summary.components = k;
  out.summary.bic = {dirichlet_mixture_bic(out.summary.log_likelihood, k, t, n)};
  out.summary.message = core::first_line(out.summary.brief());
  return out;
}

DirichletMixtureFit fit_dirichlet_mixture(const Eigen::Ref<const Eigen::MatrixXd>& log_p,
                                          const DirichletMixtureOptions& options) {
  options.validate();
  const auto n = static_cast<int>(log_p.rows());
  const int largest =
      std::max(1, std::min(options.max_components,
                           static_cast<int>(std::floor(n / options.min_component_count))));
  DirichletMixtureFit best;
  std::vector<double> bic;
  int starts = 0;
  int degenerate = 0;
  double best_bic = std::numeric_limits<double>::infinity();
  for (int k = 1; k <= largest; ++k) {
    DirichletMixtureFit f;
    try {
      f = fit_dirichlet_mixture_k(log_p, k, options);
    } catch (const Error&) {
      if (k == 1) throw;
      starts += options.restarts;
      degenerate += options.restarts;
      bic.push_back(std::numeric_limits<double>::infinity());
      continue;
    }
    starts += f.summary.starts;
    degenerate += f.summary.degenerate;
    const double b = f.summary.bic.front();
    bic.push_back(b);
    if (b < best_bic) {
      best_bic = b;
      best = std::move(f);
    }
  }
  best.summary.bic = std::move(bic);
  best.summary.starts = starts;
  best.summary.degenerate = degenerate;
  best.summary.message = core::first_line(best.summary.brief());
  return best;
}

std::string SharedPrecisionSummary::brief() const {
  std::ostringstream s;
  s.precision(6);
  s << "shared precision " << precision << (converged ? ", converged after " : ", stopped after ")
    << iterations << " rounds";
  s.precision(8);
  s << "; log-likelihood " << log_likelihood;
  return s.str();
}

SharedPrecisionFit fit_dirichlets_shared_precision(const std::vector<DirichletStats>& classes,
                                                   const DirichletFitOptions& fit) {
  fit.validate();
  require(!classes.empty(), "shared-precision Dirichlets: no classes");
  const int t = classes[0].dim();
  double total = 0;
  double log_s = 0;
  std::vector<Eigen::VectorXd> mean;
  for (const auto& c : classes) {
    require(c.count() > 0 && c.dim() == t && t >= 2,
            "shared-precision Dirichlets: a class without samples or of another dimension");
    const Dirichlet d = fit_dirichlet(c, fit).dirichlet;
    log_s += c.count() * std::log(d.precision());
    total += c.count();
    mean.push_back(d.mean());
  }
  constexpr double kMinPrecision = 1e-6;
  double s = std::clamp(std::exp(log_s / total), kMinPrecision, fit.max_precision);
  SharedPrecisionFit out;
  for (int round = 1; round <= fit.max_iterations; ++round) {
    out.summary.iterations = round;
    double change = 0;
    // Each mean at fixed s (Minka 2003, 3.1): alpha_k = psi^-1(log p-bar_k - sum_j m_j
    // (log p-bar_j - psi(s m_j))), m = alpha / sum alpha; a few steps a round.
    for (std::size_t c = 0; c < classes.size(); ++c) {
      Eigen::VectorXd& m = mean[c];
      const Eigen::VectorXd& lbar = classes[c].mean_log();
      for (int step = 0; step < 5; ++step) {
        double dot = 0;
        for (int k = 0; k < t; ++k) dot += m(k) * (lbar(k) - detail::digamma(s * m(k)));
        Eigen::VectorXd a(t);
        for (int k = 0; k < t; ++k) a(k) = detail::inverse_digamma(lbar(k) - dot);
        a /= a.sum();
        change = std::max(change, ((a - m).array().abs() / m.array()).maxCoeff());
        m = a;
      }
    }
    // s at fixed means: Newton on 1/s (Minka 3.2), the derivatives summed over the classes.
    double g = 0;
    double h = 0;
    for (std::size_t c = 0; c < classes.size(); ++c) {
      const Eigen::VectorXd& m = mean[c];
      const Eigen::VectorXd& lbar = classes[c].mean_log();
      double gc = detail::digamma(s);
      double hc = detail::trigamma(s);
      for (int k = 0; k < t; ++k) {
        gc += m(k) * (lbar(k) - detail::digamma(s * m(k)));
        hc -= m(k) * m(k) * detail::trigamma(s * m(k));
      }
      g += classes[c].count() * gc;
      h += classes[c].count() * hc;
    }
    double next = s;
    if (h < 0) {
      const double inv = 1.0 / s + g / (s * s * h);
      next = inv > 0 ? 1.0 / inv : s * 2.0;  // a step past 1/s = 0: double s instead
    } else {
      next = g > 0 ? s * 2.0 : s / 2.0;  // not concave here: move s the gradient's way
    }
    next = std::clamp(next, kMinPrecision, fit.max_precision);
    change = std::max(change, std::abs(next - s) / s);
    s = next;
    if (change <= fit.tolerance) {
      out.summary.converged = true;
      break;
    }
  }
  out.summary.precision = s;
  for (std::size_t c = 0; c < classes.size(); ++c) {
    Dirichlet d(s * mean[c]);
    out.summary.log_likelihood += d.log_likelihood(classes[c]);
    out.dirichlets.push_back(std::move(d));
  }
  out.summary.message = core::first_line(out.summary.brief());
  return out;
}

}  // namespace proprio::topics
