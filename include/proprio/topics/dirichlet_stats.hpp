#pragma once
// The sufficient statistics of a Dirichlet sample (Minka eq 5): the count N and, per component,
// the mean of log p. They are all a Dirichlet fit needs, so they can be accumulated one sample at
// a time, merged exactly across batches or machines, and discounted (forgetting) for online
// updates (thesis 8.1.2's online Mixture of Topics).

#include <Eigen/Core>
#include <cstdint>

namespace proprio::topics {

/// Zeros in proportions. A proportion below `floor` (exact zeros included: a variational E-step's
/// theta can underflow) is raised to `floor` before its log is taken, and counted as clamped.
/// The default 1e-300 keeps log p finite (>= -690.8) and, for alpha_k >= 0.05, moves the mean of
/// log p by less than 1e-13 (a floored component contributes ~floor^alpha / alpha); for alpha_k
/// near 1e-3 no floor is harmless, and such data should be given as log-proportions (where only
/// exact zeros, -inf, are floored). Data whose
/// zeros are single-precision underflow should set the floor near that limit (1e-38, FLT_MIN):
/// a floor far below the data's own underflow level drags the small alpha_k down.
inline constexpr double kDirichletFloor = 1e-300;
/// How far a row of proportions may sum from 1 (absolute), and a row of log-proportions'
/// logsumexp from 0. 1e-5 admits proportions computed in single precision (as the LDA engine's).
inline constexpr double kProportionSumTolerance = 1e-5;

struct ProportionOptions {
  double floor = kDirichletFloor;                  ///< in [1e-300, 1e-2]
  double sum_tolerance = kProportionSumTolerance;  ///< in [0, 0.5)

  /// Throws Error naming the option when floor is outside [1e-300, 1e-2] or sum_tolerance outside
  /// [0, 0.5) (NaN included).
  void validate() const;
};

class DirichletStats {
 public:
  /// No samples of no dimension; add() or merge() fixes the dimension.
  DirichletStats() = default;
  /// No samples of dimension T (>= 1; throws Error otherwise).
  explicit DirichletStats(int dim);

  /// The statistics of n samples, one per row (n x T), of proportions: every entry in [0, 1] and
  /// not NaN, every row summing to 1 within options.sum_tolerance, or Error naming the row (from
  /// 0) and the problem. Entries below options.floor are raised to it and counted (clamped()).
  static DirichletStats of_proportions(const Eigen::Ref<const Eigen::MatrixXd>& proportions,
                                       const ProportionOptions& options = {});
  /// The same from log-proportions (n x T): every entry <= sum_tolerance and not NaN or +inf, -inf
  /// standing for an exact zero; every row's logsumexp within sum_tolerance of 0, or Error naming
  /// the row. Only exact zeros (-inf) are raised to log(options.floor) and counted: finite
  /// log-proportions are kept however small (alpha far below 1 needs them).
  static DirichletStats of_log_proportions(const Eigen::Ref<const Eigen::MatrixXd>& log_proportions,
                                           const ProportionOptions& options = {});

  /// Adds one sample given as log-proportions (size T, every entry finite, taken as given: no
  /// floor, no sum check), with weight w > 0 (a sample counted w times). Error when the size or a
  /// value is wrong. The first sample of a default-constructed value sets T.
  void add_log(const Eigen::Ref<const Eigen::VectorXd>& log_p, double weight = 1.0);
  /// Adds other's samples: the result equals accumulating both sets at once (up to rounding).
  /// Error when both have samples and their dimensions differ.
  void merge(const DirichletStats& other);
  /// Multiplies the count by factor in (0, 1] (and leaves the means): forgetting, so that old
  /// samples weigh less against new ones merged afterwards. Error outside (0, 1].
  void scale(double factor);

  /// T (0 for a default-constructed value with no sample yet).
  [[nodiscard]] int dim() const { return static_cast<int>(mean_log_.size()); }
  /// N, the total weight of the samples (the number of samples unless weighted or scaled).
  [[nodiscard]] double count() const { return count_; }
  /// log p-bar_k = (1/N) sum_i log p_ik (Minka eq 5), per component, in nats.
  [[nodiscard]] const Eigen::VectorXd& mean_log() const { return mean_log_; }
  /// How many proportions were raised to the floor (summed over merges).
  [[nodiscard]] std::int64_t clamped() const { return clamped_; }

 private:
  double count_ = 0.0;
  Eigen::VectorXd mean_log_;
  std::int64_t clamped_ = 0;
};

}  // namespace proprio::topics
