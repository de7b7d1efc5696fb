#pragma once
// The Dirichlet distribution over proportions (points of the simplex): the model of an object's
// topic proportions theta in the thesis's Mixture of Topics (Ch 7.1, Dir(theta | omega_c)).
// Equation numbers are those of Minka, "Estimating a Dirichlet distribution" (2000, revised
// 2003-2012). Its maximum-likelihood fit is proprio/topics/dirichlet_fit.hpp; its sufficient
// statistics are proprio/topics/dirichlet_stats.hpp.

#include <Eigen/Core>

#include "proprio/core/random.hpp"

namespace proprio::topics {

class DirichletStats;

/// Dir(alpha) over T >= 2 proportions: density Gamma(sum_k alpha_k) / prod_k Gamma(alpha_k) *
/// prod_k p_k^(alpha_k - 1) on the simplex (Minka eq 1). A constant value; every alpha_k is
/// positive and finite. Log densities are in nats.
class Dirichlet {
 public:
  /// Throws Error unless alpha has at least 2 entries, each positive and finite (the message names
  /// the first bad entry).
  explicit Dirichlet(Eigen::VectorXd alpha);

  [[nodiscard]] const Eigen::VectorXd& alpha() const { return alpha_; }
  /// T, the number of proportions.
  [[nodiscard]] int dim() const { return static_cast<int>(alpha_.size()); }
  /// The precision s = sum_k alpha_k (Minka section 3): how tightly samples gather at the mean.
  [[nodiscard]] double precision() const { return precision_; }
  /// The mean E[p] = alpha / s (sums to 1).
  [[nodiscard]] Eigen::VectorXd mean() const;
  /// E[log p_k] = psi(alpha_k) - psi(s) (Minka eq 8): the expected sufficient statistics.
  [[nodiscard]] Eigen::VectorXd mean_log() const;

  /// log Gamma(s) - sum_k log Gamma(alpha_k), the log of the density's normalising constant.
  [[nodiscard]] double log_normalizer() const { return log_normalizer_; }

  /// log Dir(p | alpha) (Minka eq 1; the thesis's Dir(theta | omega), eq 7.2) for p of size T. No
  /// check that p is on the simplex (the caller's data was checked where it entered, see
  /// DirichletStats); a zero p_k gives the limit: -inf if alpha_k > 1, +inf if alpha_k < 1, and no
  /// term if alpha_k == 1.
  [[nodiscard]] double log_density(const Eigen::Ref<const Eigen::VectorXd>& p) const;
  /// The same from log p (finite entries): for points whose proportions underflow a double.
  [[nodiscard]] double log_density_of_log(const Eigen::Ref<const Eigen::VectorXd>& log_p) const;

  /// The log-likelihood of the samples summarised by `stats` (Minka eq 4, in nats, summed over the
  /// samples, each weighted as in the stats): count * (log_normalizer + sum_k (alpha_k - 1)
  /// mean_log_k). Throws Error when stats has another dimension.
  [[nodiscard]] double log_likelihood(const DirichletStats& stats) const;

  /// One sample as log-proportions log p (T values, logsumexp 0), drawn as log-Gamma variates
  /// normalised in log space, so that alpha far below 1 does not underflow: for alpha_k < 1,
  /// log G(alpha_k) = log G(alpha_k + 1) + log(U) / alpha_k, U uniform in (0, 1]; G(a >= 1) by
  /// Marsaglia & Tsang (2000). Deterministic for the Rng's seed.
  [[nodiscard]] Eigen::VectorXd sample_log(core::Rng& rng) const;
  /// n samples as log-proportions, one per row (n x T).
  [[nodiscard]] Eigen::MatrixXd sample_log(core::Rng& rng, int n) const;
  /// One sample as proportions: exp of sample_log (entries below ~1e-308 underflow to 0).
  [[nodiscard]] Eigen::VectorXd sample(core::Rng& rng) const;

 private:
  Eigen::VectorXd alpha_;
  double precision_ = 0.0;
  double log_normalizer_ = 0.0;
};

}  // namespace proprio::topics
