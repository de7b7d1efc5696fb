#include "proprio/topics/dirichlet.hpp"

#include <cmath>
#include <sstream>
#include <utility>

#include "gamma_variate.hpp"
#include "proprio/core/error.hpp"
#include "proprio/topics/dirichlet_stats.hpp"
#include "special_functions.hpp"

namespace proprio::topics {

namespace {

// log G, G ~ Gamma(shape, 1). Marsaglia & Tsang (2000) for shape >= 1, returned as log(d v) so
// that nothing is exponentiated; for shape < 1 the boost G(a) = G(a + 1) U^(1/a), in logs.
double log_gamma_variate(core::Rng& rng, double shape) {
  if (shape < 1.0) {
    const double u = 1.0 - rng.uniform();  // (0, 1]: log(u) is finite
    return log_gamma_variate(rng, shape + 1.0) + std::log(u) / shape;
  }
  const detail::GammaFactors g = detail::marsaglia_tsang(rng, shape);
  return std::log(g.d) + std::log(g.v);
}

}  // namespace

Dirichlet::Dirichlet(Eigen::VectorXd alpha) : alpha_(std::move(alpha)) {
  if (!(alpha_.size() >= 2))
    throw Error("Dirichlet: alpha needs at least 2 entries, got " + std::to_string(alpha_.size()));
  for (Eigen::Index k = 0; k < alpha_.size(); ++k) {
    if (!(std::isfinite(alpha_(k)) && alpha_(k) > 0.0)) {
      std::ostringstream m;
      m << "Dirichlet: alpha[" << k << "] = " << alpha_(k) << " is not positive and finite";
      throw Error(m.str());
    }
  }
  precision_ = alpha_.sum();
  log_normalizer_ = std::lgamma(precision_);
  for (const double a : alpha_) log_normalizer_ -= std::lgamma(a);
}

Eigen::VectorXd Dirichlet::mean() const { return alpha_ / precision_; }

Eigen::VectorXd Dirichlet::mean_log() const {
  const double ps = detail::digamma(precision_);
  Eigen::VectorXd m(alpha_.size());
  for (Eigen::Index k = 0; k < alpha_.size(); ++k) m(k) = detail::digamma(alpha_(k)) - ps;
  return m;
}

double Dirichlet::log_density(const Eigen::Ref<const Eigen::VectorXd>& p) const {
  if (!(p.size() == alpha_.size()))
    throw Error("Dirichlet::log_density: a point of size " + std::to_string(p.size()) +
                " for a Dirichlet of size " + std::to_string(alpha_.size()));
  double r = log_normalizer_;
  for (Eigen::Index k = 0; k < alpha_.size(); ++k) {
    if (alpha_(k) != 1.0) r += (alpha_(k) - 1.0) * std::log(p(k));
  }
  return r;
}

double Dirichlet::log_density_of_log(const Eigen::Ref<const Eigen::VectorXd>& log_p) const {
  if (!(log_p.size() == alpha_.size()))
    throw Error("Dirichlet::log_density_of_log: a point of size " + std::to_string(log_p.size()) +
                " for a Dirichlet of size " + std::to_string(alpha_.size()));
  return log_normalizer_ + (alpha_.array() - 1.0).matrix().dot(log_p);
}

double Dirichlet::log_likelihood(const DirichletStats& stats) const {
  if (stats.count() == 0.0) return 0.0;
  if (!(stats.dim() == dim()))
    throw Error("Dirichlet::log_likelihood: statistics of dimension " +
                std::to_string(stats.dim()) + " for a Dirichlet of size " + std::to_string(dim()));
  return stats.count() * (log_normalizer_ + (alpha_.array() - 1.0).matrix().dot(stats.mean_log()));
}

Eigen::VectorXd Dirichlet::sample_log(core::Rng& rng) const {
  Eigen::VectorXd g(alpha_.size());
  for (Eigen::Index k = 0; k < alpha_.size(); ++k) g(k) = log_gamma_variate(rng, alpha_(k));
  const double m = g.maxCoeff();
  const double lse = m + std::log((g.array() - m).exp().sum());
  return g.array() - lse;
}

Eigen::MatrixXd Dirichlet::sample_log(core::Rng& rng, int n) const {
  require(n >= 0, "Dirichlet::sample_log: a negative number of samples");
  Eigen::MatrixXd out(n, alpha_.size());
  for (int i = 0; i < n; ++i) out.row(i) = sample_log(rng).transpose();
  return out;
}

Eigen::VectorXd Dirichlet::sample(core::Rng& rng) const { return sample_log(rng).array().exp(); }

}  // namespace proprio::topics
