#pragma once
// Seeded randomness. Every random algorithm takes an Rng (or a seed); the same seed gives the
// same sequence on every run and machine (std::mt19937_64 is specified exactly by the standard;
// the distributions here are written out so that they are too).

#include <cstdint>
#include <random>

namespace proprio::core {

/// SplitMix64's output function (Steele, Lea & Flood 2014) applied to x: a bijection of 64-bit
/// words in which every input bit changes about half the output bits.
constexpr std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30U)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27U)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31U);
}

/// The seed of the sub-stream named by `keys` (a stream constant, a trial, a document, an update,
/// a restart...) of `seed`: h = seed, then h = splitmix64(h) ^ key for each key, then
/// splitmix64(h). This is the one way proprio derives child streams: neighbouring seeds, keys and
/// indices give unrelated generators, and a stream depends only on its keys, never on how many
/// draws another stream made or on the thread that draws it.
template <class... Keys>
constexpr std::uint64_t stream_seed(std::uint64_t seed, Keys... keys) {
  std::uint64_t h = seed;
  ((h = splitmix64(h) ^ static_cast<std::uint64_t>(keys)), ...);
  return splitmix64(h);
}

class Rng {
 public:
  explicit Rng(std::uint64_t seed) : engine_(seed) {}

  /// The generator of sub-stream `keys` of `seed` (see stream_seed).
  template <class... Keys>
  static Rng stream(std::uint64_t seed, Keys... keys) {
    return Rng(stream_seed(seed, keys...));
  }

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
