#pragma once
// Mixtures of Dirichlets, and Dirichlets that share one precision: the two refinements of the
// Mixture of Topics object model (thesis 7.1) measured in docs/results/mot.md. With
// object-specific topics the theta of one object's views sit in the corners of its several
// topics; one Dirichlet over such a multi-modal set has every alpha_k < 1 and is high at every
// corner of the simplex, also at other objects' topics. A mixture of Dirichlets puts one
// component at each of the object's corners; a shared precision stops the broadest object from
// being much broader than the others.
//
// Mixture: sum_j w_j Dir(p | alpha_j), fitted by EM on log-proportions: the E-step gives each
// sample its responsibilities r_ij = w_j Dir(p_i | alpha_j) / sum_l w_l Dir(p_i | alpha_l); the
// M-step is the maximum-likelihood fit of proprio/topics/dirichlet_fit.hpp (Minka 2003) on each
// component's responsibility-weighted sufficient statistics (DirichletStats::add_log with weight
// r_ij), and w_j = sum_i r_ij / n. Each start is seeded by k-means++ over the proportions
// (hard responsibilities from Lloyd's iterations); the start with the highest log-likelihood wins.
// The number of components is chosen by BIC (Schwarz 1978) in [1, max_components].

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "proprio/topics/dirichlet.hpp"
#include "proprio/topics/dirichlet_fit.hpp"
#include "proprio/topics/dirichlet_stats.hpp"

namespace proprio::topics {

struct DirichletMixtureOptions {
  /// Components tried: 1 .. max_components (further bounded by n / min_component_count).
  int max_components = 10;
  /// EM starts per number of components (k-means++ seeds, each from its own sub-stream).
  int restarts = 3;
  /// EM iterations per start at most (one iteration: M-step then E-step).
  int max_iterations = 100;
  /// A start has converged when an iteration raises the log-likelihood by less than tolerance
  /// nats per sample.
  double tolerance = 1e-6;
  /// A component whose responsibilities sum to less than this (effective samples) makes its start
  /// degenerate (discarded): a Dirichlet on a handful of near-equal samples has a precision
  /// without bound, and with it an unbounded likelihood. >= 2.
  double min_component_count = 5;
  std::uint64_t seed = 1;   ///< the k-means++ starts
  DirichletFitOptions fit;  ///< each M-step fit

  /// Throws Error naming the first bad option.
  void validate() const;
};

/// One component: its weight w_j, the responsibility-weighted statistics it was fitted on, alpha_j.
struct DirichletComponent {
  double weight = 0;
  DirichletStats stats;
  Dirichlet dirichlet;
};

/// sum_j w_j Dir(p | alpha_j).
struct DirichletMixture {
  std::vector<DirichletComponent> components;

  [[nodiscard]] int num_components() const { return static_cast<int>(components.size()); }
  /// log sum_j w_j Dir(p | alpha_j) from log p (finite entries), nats.
  [[nodiscard]] double log_density_of_log(const Eigen::Ref<const Eigen::VectorXd>& log_p) const;
  /// Throws Error unless there is a component, all of one dimension, weights positive and finite
  /// summing to 1 within 1e-6.
  void validate() const;
};

/// Why the chosen start stopped.
enum class MixtureStop {
  kOneComponent,   ///< one component: the plain fit, no EM
  kConverged,      ///< the log-likelihood rose by less than tolerance per sample
  kMaxIterations,  ///< max_iterations reached first
};

/// "one-component", "converged", "max-iterations".
[[nodiscard]] const char* to_string(MixtureStop stop);

struct DirichletMixtureSummary {
  int samples = 0;
  int components = 0;  ///< chosen
  int iterations = 0;  ///< EM iterations of the chosen start
  MixtureStop stop = MixtureStop::kOneComponent;
  int starts = 0;             ///< EM starts run, over every number of components tried
  int degenerate = 0;         ///< of those, discarded (a component below min_component_count)
  double log_likelihood = 0;  ///< of the chosen mixture, nats, summed over the samples
  /// BIC = -2 L + p ln n, p = K T + K - 1, of each K tried (index K - 1; +inf when every start
  /// with K components was degenerate). One entry when the number was fixed.
  std::vector<double> bic;
  std::string message;  ///< one line: what happened (brief()'s first line)
  /// "4 components (BIC among 1..10), EM converged after 23 iterations; 30 starts, 3 degenerate;
  /// log-likelihood ...".
  [[nodiscard]] std::string brief() const;
};

struct DirichletMixtureFit {
  DirichletMixture mixture;
  DirichletMixtureSummary summary;
};

/// BIC of a mixture of k Dirichlets over T proportions with log-likelihood L from n samples.
[[nodiscard]] double dirichlet_mixture_bic(double log_likelihood, int k, int dim, int n);

/// EM with exactly k components on n x T log-proportions (finite entries; each row's logsumexp
/// 0, as from check_theta). k = 1 is the plain maximum-likelihood fit (fit_dirichlet on the
/// rows' statistics, identical to it). Throws Error when options are invalid, n < 2, k < 1, or
/// every start was degenerate (naming k).
[[nodiscard]] DirichletMixtureFit fit_dirichlet_mixture_k(
    const Eigen::Ref<const Eigen::MatrixXd>& log_p, int k,
    const DirichletMixtureOptions& options = {});

/// The same with the number of components chosen by the smallest BIC in
/// [1, min(max_components, n / min_component_count)]; each k's starts draw from the sub-stream
/// (seed, k), so a k's result does not depend on which others were tried.
[[nodiscard]] DirichletMixtureFit fit_dirichlet_mixture(
    const Eigen::Ref<const Eigen::MatrixXd>& log_p, const DirichletMixtureOptions& options = {});

struct SharedPrecisionSummary {
  int iterations = 0;  ///< outer rounds (means given s, then s given the means)
  bool converged = false;
  double precision = 0;       ///< the shared s
  double log_likelihood = 0;  ///< summed over every class's samples, nats
  std::string message;        ///< one line: what happened (brief()'s first line)
  [[nodiscard]] std::string brief() const;
};

struct SharedPrecisionFit {
  std::vector<Dirichlet> dirichlets;  ///< one per class, each of precision s
  SharedPrecisionSummary summary;
};

/// Maximum likelihood of C Dirichlets alpha_c = s m_c with one precision s and a mean m_c per
/// class, from each class's sufficient statistics. Alternates Minka's (2003, section 3.1)
/// fixed-point for each mean at fixed s and Newton steps on 1/s for s at fixed means (his section
/// 3.2, summed over the classes), starting from the independent fits and the count-weighted
/// geometric mean of their precisions; stops when s and every mean change by less than
/// fit.tolerance (relative), or after fit.max_iterations rounds. s is kept in [1e-6,
/// fit.max_precision]. Throws Error on no classes, a class without samples or of another
/// dimension.
[[nodiscard]] SharedPrecisionFit fit_dirichlets_shared_precision(
    const std::vector<DirichletStats>& classes, const DirichletFitOptions& fit = {});

}  // namespace proprio::topics
