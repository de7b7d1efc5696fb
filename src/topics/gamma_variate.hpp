#pragma once
// Gamma(shape, 1) variates by Marsaglia & Tsang (2000), shared by the Dirichlet sampler (which
// works in logs, dirichlet.cpp) and the synthetic corpora (synthetic.cpp). Written by hand: the
// standard library's std::gamma_distribution is not specified exactly, so its draws differ between
// standard libraries, and a seed must give the same corpus and samples everywhere.
#include <cmath>

#include "proprio/core/random.hpp"

namespace proprio::topics::detail {

/// A Gamma(shape, 1) variate G = d v for shape >= 1, kept as its two factors so that a caller
/// working in logs takes log d + log v without forming G.
struct GammaFactors {
  double d = 0;
  double v = 0;
};

/// Marsaglia & Tsang's squeeze-and-reject loop, shape >= 1.
inline GammaFactors marsaglia_tsang(core::Rng& rng, double shape) {
  const double d = shape - 1.0 / 3.0;
  const double c = 1.0 / std::sqrt(9.0 * d);
  for (;;) {
    const double x = rng.normal();
    double v = 1.0 + c * x;
    if (v <= 0.0) continue;
    v = v * v * v;
    const double u = rng.uniform();
    if (u < 1.0 - 0.0331 * x * x * x * x ||
        std::log(u) < 0.5 * x * x + d * (1.0 - v + std::log(v))) {
      return {d, v};
    }
  }
}

}  // namespace proprio::topics::detail
