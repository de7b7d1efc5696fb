// The vector kernels against double-precision references, on every instruction set this
// processor runs.
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <set>

#include "engine.hpp"
#include "kernels.hpp"
#include "proprio/core/random.hpp"
#include "proprio/core/thread_pool.hpp"

namespace proprio::topics::detail {
namespace {

// psi by the recurrence and a long asymptotic series, in long double.
double reference_digamma(double x) {
  long double r = 0, z = x;
  while (z < 20) {
    r -= 1 / z;
    z += 1;
  }
  const long double f = 1 / (z * z);
  return static_cast<double>(
      r + std::log(z) - 0.5L / z -
      f * (1.0L / 12 - f * (1.0L / 120 - f * (1.0L / 252 - f * (1.0L / 240 - f / 132)))));
}

TEST(Kernels, DigammaMatchesTheReference) {
  for (const auto& name : supported_kernels()) {
    const Kernels& k = kernels_named(name);
    for (double x : {1e-3, 0.01, 0.1, 0.5, 1.0, 1.4616321, 2.0, 5.5, 10.0, 100.0, 1e4, 1e6}) {
      const double ref = reference_digamma(x);
      EXPECT_NEAR(k.digamma(static_cast<float>(x)), ref, 2e-6 * std::max(1.0, std::abs(ref)))
          << name << " x=" << x;
      EXPECT_NEAR(digamma(x), ref, 1e-12 * std::max(1.0, std::abs(ref))) << "double x=" << x;
    }
    EXPECT_NEAR(k.digamma(1.0f), -0.5772156649, 1e-6) << name;  // -Euler's constant
  }
}

TEST(Kernels, ExpDigammaMinusMatchesTheReferenceAndFloors) {
  for (const auto& name : supported_kernels()) {
    const Kernels& k = kernels_named(name);
    const int n = 4 * k.lanes;
    FloatBuffer x(static_cast<std::size_t>(n)), sub(static_cast<std::size_t>(n)),
        out(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
      x[static_cast<std::size_t>(i)] = 0.05f + 3.7f * static_cast<float>(i);
      sub[static_cast<std::size_t>(i)] = static_cast<float>(i % 5);
    }
    x[0] = 1e-3f;  // psi(0.001) = -1000.4: floored
    k.exp_digamma_minus(x.data(), sub.data(), out.data(), n);
    EXPECT_FLOAT_EQ(out[0], std::exp(kLogFloor)) << name;
    for (int i = 1; i < n; ++i) {
      const auto u = static_cast<std::size_t>(i);
      const double ref = std::exp(std::max<double>(reference_digamma(x[u]) - sub[u], kLogFloor));
      EXPECT_NEAR(out[u], ref, 3e-6 * ref) << name << " i=" << i;
    }
  }
}

// One document's E-step in double precision, straight from eq B.16-B.18.
std::vector<double> reference_estep(const std::vector<std::vector<double>>& beta,
                                    const std::vector<int>& ids, const std::vector<double>& counts,
                                    double alpha, int iterations) {
  const std::size_t K = beta[0].size();
  std::vector<double> gamma(K, 1.0), eth(K);
  auto expect = [&] {
    const double s = std::accumulate(gamma.begin(), gamma.end(), 0.0);
    for (std::size_t k = 0; k < K; ++k)
      eth[k] = std::exp(reference_digamma(gamma[k]) - reference_digamma(s));
  };
  expect();
  for (int it = 0; it < iterations; ++it) {
    std::vector<double> acc(K, 0.0);
    for (std::size_t j = 0; j < ids.size(); ++j) {
      const auto& b = beta[static_cast<std::size_t>(ids[j])];
      double norm = 0;
      for (std::size_t k = 0; k < K; ++k) norm += eth[k] * b[k];
      for (std::size_t k = 0; k < K; ++k) acc[k] += counts[j] / norm * b[k];
    }
    for (std::size_t k = 0; k < K; ++k) gamma[k] = alpha + eth[k] * acc[k];
    expect();
  }
  return gamma;
}

TEST(Kernels, DocumentEStepMatchesTheDoublePrecisionReference) {
  for (const int K : {3, 10, 37, 100, 130}) {
    core::Rng rng(static_cast<std::uint64_t>(K));
    const int rows = 60;
    std::vector<std::vector<double>> beta(rows, std::vector<double>(static_cast<std::size_t>(K)));
    for (auto& r : beta) {
      for (auto& v : r) v = std::exp(-8.0 * rng.uniform());
    }
    std::vector<int> ids;
    std::vector<double> counts;
    for (int j = 0; j < 40; ++j) {
      ids.push_back(static_cast<int>(rng.index(rows)));
      counts.push_back(1.0 + static_cast<double>(rng.index(5)));
    }
    const double alpha = 0.05;
    const int iterations = 12;
    const auto ref = reference_estep(beta, ids, counts, alpha, iterations);
    for (const auto& name : supported_kernels()) {
      const Kernels& k = kernels_named(name);
      const int stride = padded(K, k.lanes);
      FloatBuffer fb(static_cast<std::size_t>(rows * stride), 0.0f);
      for (int r = 0; r < rows; ++r) {
        for (int t = 0; t < K; ++t)
          fb[static_cast<std::size_t>(r * stride + t)] =
              static_cast<float>(beta[static_cast<std::size_t>(r)][static_cast<std::size_t>(t)]);
      }
      std::vector<std::int32_t> fid(ids.begin(), ids.end());
      FloatBuffer fc(counts.begin(), counts.end());
      FloatBuffer gamma(static_cast<std::size_t>(stride), 1.0f),
          eth(static_cast<std::size_t>(stride)), w(fid.size()),
          scratch(static_cast<std::size_t>(stride));
      DocEStepArgs a;
      a.ids = fid.data();
      a.counts = fc.data();
      a.n = static_cast<int>(fid.size());
      a.beta = fb.data();
      a.num_topics = K;
      a.stride = stride;
      a.alpha = static_cast<float>(alpha);
      a.max_iterations = iterations;
      a.tolerance = 0.0f;
      a.gamma = gamma.data();
      a.exp_elog_theta = eth.data();
      a.weights = w.data();
      a.scratch = scratch.data();
      const DocEStepOut out = k.estep_doc(a);
      EXPECT_EQ(out.iterations, iterations);
      double total = 0;
      for (int t = 0; t < K; ++t) {
        EXPECT_NEAR(gamma[static_cast<std::size_t>(t)], ref[static_cast<std::size_t>(t)],
                    2e-3 * (1.0 + ref[static_cast<std::size_t>(t)]))
            << name << " K=" << K << " topic " << t;
        total += gamma[static_cast<std::size_t>(t)];
      }
      // gamma sums to K alpha + the tokens (eq B.17).
      EXPECT_NEAR(total, K * alpha + std::accumulate(counts.begin(), counts.end(), 0.0), 1e-2)
          << name;
      for (int t = K; t < stride; ++t) EXPECT_EQ(eth[static_cast<std::size_t>(t)], 0.0f) << name;
    }
  }
}

TEST(RandomGamma, HasMeanOneAndSpreadOneTenth) {
  std::vector<float> g(20000);
  random_gamma(42, static_cast<int>(g.size()), g.data());
  double mean = 0, var = 0;
  for (float v : g) mean += v;
  mean /= static_cast<double>(g.size());
  for (float v : g) var += (v - mean) * (v - mean);
  var /= static_cast<double>(g.size());
  EXPECT_NEAR(mean, 1.0, 0.005);
  EXPECT_NEAR(std::sqrt(var), 0.1, 0.005);
  std::vector<float> h(20000);
  random_gamma(42, static_cast<int>(h.size()), h.data());
  EXPECT_EQ(g, h);
}

}  // namespace
}  // namespace proprio::topics::detail
