#pragma once
// Maximum-likelihood fit of a Dirichlet to proportions, after Minka (2003), "Estimating a
// Dirichlet distribution" (equation numbers of its 2012 revision): the thesis's omega_c of each
// object in the Mixture of Topics (Ch 7.1). The fit works on the sufficient statistics alone
// (proprio/topics/dirichlet_stats.hpp), so after the one pass over the data it costs O(T) per
// iteration.
//
// The method: (1) the initial precision s0 = (T - 1) / (2 (-log sum_k exp(log p-bar_k))) (Minka
// section 3's approximation, with the mean taken as the normalised geometric means), (2) fixed-
// point steps psi(alpha_k) = psi(sum_j alpha_j) + log p-bar_k (Minka's fixed-point iteration of
// section 2; psi^-1 by Newton, his Appendix C), the first from s0, (3) Newton steps on the
// log-likelihood (eq 4) with gradient eq 6 and the Hessian diag(q) + z 1 1^T, inverted in O(T) by
// the matrix inversion lemma (Minka section 2, Newton iteration). A Newton step that would make an
// alpha_k non-positive, or lower the log-likelihood, is halved (up to 30 times) and, failing that,
// replaced by a fixed-point step (which always stays positive and never lowers it); both are
// counted in the summary.
//
// The maximum exists when the samples are not all equal; as they approach equality it moves to
// infinite precision. When the data put it beyond max_precision (one sample, duplicate rows only,
// a degenerate sample), the fit stops at precision max_precision with the mean of the data and
// says so (DirichletStop::kPrecisionBound); alpha stays finite.

#include <Eigen/Core>
#include <cstdint>
#include <string>

#include "proprio/topics/dirichlet.hpp"
#include "proprio/topics/dirichlet_stats.hpp"

namespace proprio::topics {

struct DirichletFitOptions {
  /// Converged when max_k |g_k| <= tolerance * N, g the gradient of eq 6 (i.e. every
  /// psi(sum alpha) - psi(alpha_k) + log p-bar_k within tolerance of 0, in nats).
  double tolerance = 1e-9;
  /// At most this many iterations, fixed-point and Newton together.
  int max_iterations = 100;
  /// Fixed-point steps before Newton (the first starts from the initial precision), >= 1.
  int fixed_point_steps = 2;
  /// The largest precision sum_k alpha_k the fit will return (see the file comment).
  double max_precision = 1e8;
  /// How proportions are checked and floored (fit_dirichlet from proportions only).
  ProportionOptions proportions;

  /// Throws Error naming the option: tolerance not positive and finite, max_iterations < 1,
  /// fixed_point_steps < 1 or > max_iterations, max_precision not finite or < 1, or
  /// proportions.validate() failing.
  void validate() const;
};

/// Why a fit stopped.
enum class DirichletStop {
  kConverged,       ///< the gradient's max-norm fell to tolerance * N
  kMaxIterations,   ///< max_iterations reached first
  kPrecisionBound,  ///< the maximum lies at precision > max_precision (samples (nearly) all equal)
  kNoProgress,      ///< neither Newton nor a fixed-point step raised the likelihood (rounding)
};

/// A fit's account of itself.
struct DirichletFitSummary {
  int fixed_point_iterations = 0;
  int newton_iterations = 0;
  int step_halvings = 0;     ///< Newton steps halved to keep alpha positive or L rising
  int newton_fallbacks = 0;  ///< Newton steps replaced by a fixed-point step
  bool converged = false;    ///< stop == kConverged
  DirichletStop stop = DirichletStop::kMaxIterations;
  std::string message;             ///< why it stopped, in words
  double log_likelihood = 0.0;     ///< eq 4 at the returned alpha, nats, summed over the samples
  double gradient_max_norm = 0.0;  ///< max_k |g_k| (eq 6) at the returned alpha
  double count = 0.0;              ///< N, the samples' total weight
  std::int64_t clamped = 0;        ///< proportions raised to the floor (DirichletStats::clamped)

  [[nodiscard]] int iterations() const { return fixed_point_iterations + newton_iterations; }
  /// One line: "converged after 2 fixed-point + 4 Newton iterations (...), log-likelihood ...,
  /// ... proportions clamped to the floor", and the message unless converged.
  [[nodiscard]] std::string brief() const;
};

struct DirichletFit {
  Dirichlet dirichlet;
  DirichletFitSummary summary;
};

/// The maximum-likelihood Dirichlet of the summarised samples: the thesis's omega of eq 7.2 for
/// one object's theta_1..theta_N. Throws Error when options are invalid, stats has no samples
/// (count 0) or dimension < 2, or a mean log-proportion is not finite or below -1e100 (an alpha
/// below ~1e-100, where psi' overflows).
[[nodiscard]] DirichletFit fit_dirichlet(const DirichletStats& stats,
                                         const DirichletFitOptions& options = {});
/// The same from n x T proportions, one sample per row (DirichletStats::of_proportions with
/// options.proportions: errors name the row).
[[nodiscard]] DirichletFit fit_dirichlet(const Eigen::Ref<const Eigen::MatrixXd>& proportions,
                                         const DirichletFitOptions& options = {});
/// The same from n x T log-proportions (DirichletStats::of_log_proportions).
[[nodiscard]] DirichletFit fit_dirichlet_log(
    const Eigen::Ref<const Eigen::MatrixXd>& log_proportions,
    const DirichletFitOptions& options = {});

/// "converged", "max-iterations", "precision-bound", "no-progress".
[[nodiscard]] const char* to_string(DirichletStop stop);

}  // namespace proprio::topics
