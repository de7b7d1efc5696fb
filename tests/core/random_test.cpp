#include "proprio/core/random.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace proprio::core {
namespace {

TEST(Rng, SameSeedSameSequence) {
  Rng a(42), b(42), c(43);
  bool differs = false;
  for (int i = 0; i < 100; ++i) {
    const double x = a.normal();
    EXPECT_EQ(x, b.normal());
    differs |= (x != c.normal());
  }
  EXPECT_TRUE(differs);
}

TEST(Rng, NormalMomentsAndUniformRange) {
  Rng r(1);
  constexpr int kN = 200000;
  double s = 0, s2 = 0;
  for (int i = 0; i < kN; ++i) {
    const double x = r.normal(2.0, 3.0);
    s += x;
    s2 += x * x;
  }
  const double mean = s / kN;
  const double var = s2 / kN - mean * mean;
  EXPECT_NEAR(mean, 2.0, 0.03);
  EXPECT_NEAR(std::sqrt(var), 3.0, 0.03);
  for (int i = 0; i < 1000; ++i) {
    const double u = r.uniform(-1.0, 1.0);
    EXPECT_GE(u, -1.0);
    EXPECT_LT(u, 1.0);
    EXPECT_LT(r.index(7), 7u);
  }
}

}  // namespace
}  // namespace proprio::core
