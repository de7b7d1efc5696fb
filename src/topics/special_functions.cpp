#include "special_functions.hpp"

#include <cassert>
#include <cmath>

namespace proprio::topics::detail {

namespace {
constexpr double kShift = 10.0;                        // below this, the recurrence shifts x up
constexpr double kEulerGamma = 0.5772156649015328606;  // -psi(1)
}  // namespace

double digamma(double x) {
  assert(x > 0.0);
  double r = 0.0;
  while (x < kShift) {
    r -= 1.0 / x;
    x += 1.0;
  }
  const double f = 1.0 / (x * x);
  return r + std::log(x) - 0.5 / x -
         f * (1.0 / 12 -
              f * (1.0 / 120 -
                   f * (1.0 / 252 - f * (1.0 / 240 - f * (1.0 / 132 - f * 691.0 / 32760)))));
}

double trigamma(double x) {
  assert(x > 0.0);
  double r = 0.0;
  while (x < kShift) {
    r += 1.0 / (x * x);
    x += 1.0;
  }
  // 1/x + 1/(2x^2) + sum_k B_2k / x^(2k+1), Bernoulli numbers B_2 .. B_14.
  const double f = 1.0 / (x * x);
  return r + 1.0 / x + 0.5 * f +
         f / x *
             (1.0 / 6 - f * (1.0 / 30 -
                             f * (1.0 / 42 - f * (1.0 / 30 - f * (5.0 / 66 - f * (691.0 / 2730 -
                                                                                  f * 7.0 / 6))))));
}

double inverse_digamma(double y) {
  double x = y >= -2.22 ? std::exp(y) + 0.5 : -1.0 / (y + kEulerGamma);
  for (int i = 0; i < 8; ++i) {
    const double step = (digamma(x) - y) / trigamma(x);
    double next = x - step;
    // Newton on the concave, increasing psi never overshoots from the left; from the right it
    // can, so it is held inside (0, x).
    if (next <= 0.0) next = 0.5 * x;
    const bool done = std::abs(next - x) <= 1e-15 * x;
    x = next;
    if (done) break;
  }
  return x;
}

}  // namespace proprio::topics::detail
