#pragma once
// Seeded randomness. Every random algorithm takes an Rng (or a seed); the same seed gives the
// same sequence on every run and machine (std::mt19937_64 is specified exactly by the standard;
// the distributions here are written out so that they are too).

#include <cstdint>
#include <random>

namespace proprio::core {

class Rng {
 public:
  explicit Rng(std::uint64_t seed) : engine_(seed) {}

  /// Uniform in [0, 1).
  double uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  /// Uniform in [lo, hi).
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  /// Uniform integer in [0, n), n > 0.
  std::uint64_t index(std::uint64_t n);
  /// Standard normal by the Box-Muller transform (reproducible across standard libraries, unlike
  /// std::normal_distribution).
  double normal();
  double normal(double mean, double stddev) { return mean + stddev * normal(); }
  /// A new seed drawn from this stream, for child generators.
  std::uint64_t next_seed() { return engine_(); }

  std::mt19937_64& engine() { return engine_; }

 private:
  std::mt19937_64 engine_;
  double spare_ = 0.0;
  bool has_spare_ = false;
};

}  // namespace proprio::core
