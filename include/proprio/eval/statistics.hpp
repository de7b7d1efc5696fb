#pragma once
// Statistics for comparing segmentation methods over a dataset: the two-sample
// Kolmogorov-Smirnov test (thesis 5.1.1; it tests whether two distributions differ, not, as the
// thesis reads it, the chance that one method wins) and bootstrap intervals of a mean.
//
// Written here because Debian's Boost (1.74) has no Kolmogorov distribution (it arrived in 1.75)
// and no other packaged C++ library offers the two-sample test.

#include <cstdint>
#include <vector>

namespace proprio::eval {

struct KsResult {
  double statistic = 0.0;  ///< D = sup |F1 - F2|
  double p_value = 1.0;    ///< two-sided
  bool exact = false;      ///< exact (lattice paths) or asymptotic (Kolmogorov distribution)
  int n1 = 0, n2 = 0;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.statistic, {"statistic", "D = sup |F1 - F2|"});
    v(self.p_value, {"p_value", "Two-sided"});
    v(self.exact, {"exact", "Exact or asymptotic p-value"});
    v(self.n1, {"n1", "First sample's size"});
    v(self.n2, {"n2", "Second sample's size"});
  }
};

/// Two-sided two-sample KS test, as scipy.stats.ks_2samp(method="auto"): the exact p-value by
/// counting lattice paths when n1 * n2 <= exact_limit, else the asymptotic Kolmogorov
/// distribution at sqrt(n1 n2 / (n1 + n2)) D. Empty samples give statistic 0, p-value 1.
/// Values must be finite (assert).
KsResult ks_two_sample(std::vector<double> a, std::vector<double> b,
                       std::int64_t exact_limit = 1000000);

/// Survival function of the Kolmogorov distribution, P(K > x) = 2 sum_k (-1)^(k-1) e^(-2 k^2 x^2).
double kolmogorov_sf(double x);

struct Interval {
  double lower = 0.0, upper = 0.0;
  /// [lower, upper], as records write an interval.
  [[nodiscard]] std::vector<double> bounds() const { return {lower, upper}; }
};

/// Percentile bootstrap interval of the mean of `values` at `level` (e.g. 0.95), from
/// `resamples` resamples drawn with `seed`. One value gives [v, v]; none gives [0, 0].
Interval bootstrap_mean_interval(const std::vector<double>& values, double level, int resamples,
                                 std::uint64_t seed);

double mean(const std::vector<double>& v);    ///< 0 for none
double stddev(const std::vector<double>& v);  ///< population std, 0 for fewer than 2

}  // namespace proprio::eval
