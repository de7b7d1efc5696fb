#include "proprio/eval/statistics.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdlib>

#include "proprio/core/random.hpp"

namespace proprio::eval {

double mean(const std::vector<double>& v) {
  if (v.empty()) return 0.0;
  double s = 0;
  for (double x : v) s += x;
  return s / static_cast<double>(v.size());
}

double stddev(const std::vector<double>& v) {
  if (v.size() < 2) return 0.0;
  const double m = mean(v);
  double s = 0;
  for (double x : v) s += (x - m) * (x - m);
  return std::sqrt(s / static_cast<double>(v.size()));
}

double kolmogorov_sf(double x) {
  if (x <= 0) return 1.0;
  if (x < 0.2) return 1.0;  // the series converges slowly here; the value is 1 to 1e-20
  double sum = 0;
  for (int k = 1; k <= 100; ++k) {
    const double term = std::exp(-2.0 * k * k * x * x);
    sum += (k % 2 == 1 ? term : -term);
    if (term < 1e-17) break;
  }
  return std::clamp(2.0 * sum, 0.0, 1.0);
}

namespace {

// P(D >= d) under the null by counting monotone lattice paths from (0, 0) to (n1, n2) that stay
// strictly inside |i / n1 - j / n2| < d (Hodges 1958). f(i, j) is the fraction of all paths to
// (i, j) that stayed inside, so nothing overflows: f(i, j) = f(i-1, j) i / (i+j) + f(i, j-1) j /
// (i+j). In integers: |i n2 - j n1| < h with h = D n1 n2 (rounded).
double exact_p(int n1, int n2, double d) {
  const std::int64_t h = std::llround(d * n1 * n2);
  auto inside = [&](std::int64_t i, std::int64_t j) { return std::llabs(i * n2 - j * n1) < h; };
  std::vector<double> f(static_cast<std::size_t>(n2) + 1, 0.0);
  for (int i = 0; i <= n1; ++i) {
    for (int j = 0; j <= n2; ++j) {
      double v;
      if (i == 0 && j == 0) {
        v = 1.0;
      } else {
        const double up = i > 0 ? f[static_cast<std::size_t>(j)] * i / (i + j) : 0.0;
        const double left = j > 0 ? f[static_cast<std::size_t>(j) - 1] * j / (i + j) : 0.0;
        v = up + left;
      }
      f[static_cast<std::size_t>(j)] = inside(i, j) || (i == 0 && j == 0) ? v : 0.0;
    }
  }
  return std::clamp(1.0 - f[static_cast<std::size_t>(n2)], 0.0, 1.0);
}

}  // namespace

KsResult ks_two_sample(std::vector<double> a, std::vector<double> b, std::int64_t exact_limit) {
  KsResult r;
  r.n1 = static_cast<int>(a.size());
  r.n2 = static_cast<int>(b.size());
  if (a.empty() || b.empty()) return r;
  std::sort(a.begin(), a.end());
  std::sort(b.begin(), b.end());
  // Sweep both sorted samples; ties advance together so D is measured between distinct values.
  std::size_t i = 0, j = 0;
  double d = 0;
  while (i < a.size() && j < b.size()) {
    assert(std::isfinite(a[i]) && std::isfinite(b[j]));
    const double x = std::min(a[i], b[j]);
    while (i < a.size() && a[i] == x) ++i;
    while (j < b.size() && b[j] == x) ++j;
    d = std::max(d, std::abs(static_cast<double>(i) / r.n1 - static_cast<double>(j) / r.n2));
  }
  r.statistic = d;
  if (static_cast<std::int64_t>(r.n1) * r.n2 <= exact_limit) {
    r.exact = true;
    r.p_value = exact_p(r.n1, r.n2, d);
  } else {
    const double en = static_cast<double>(r.n1) * r.n2 / (r.n1 + r.n2);
    r.p_value = kolmogorov_sf(std::sqrt(en) * d);
  }
  return r;
}

Interval bootstrap_mean_interval(const std::vector<double>& values, double level, int resamples,
                                 std::uint64_t seed) {
  assert(level > 0 && level < 1 && resamples >= 1);
  if (values.empty()) return {};
  if (values.size() == 1) return {values[0], values[0]};
  core::Rng rng(seed);
  std::vector<double> means(static_cast<std::size_t>(resamples));
  for (double& m : means) {
    double s = 0;
    for (std::size_t k = 0; k < values.size(); ++k) s += values[rng.index(values.size())];
    m = s / static_cast<double>(values.size());
  }
  std::sort(means.begin(), means.end());
  auto quantile = [&](double q) {
    const double pos = q * (means.size() - 1);
    const std::size_t lo = static_cast<std::size_t>(std::floor(pos));
    const std::size_t hi = std::min(lo + 1, means.size() - 1);
    return means[lo] + (pos - lo) * (means[hi] - means[lo]);
  };
  return {quantile((1 - level) / 2), quantile(1 - (1 - level) / 2)};
}

}  // namespace proprio::eval
