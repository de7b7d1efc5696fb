#pragma once
// Message building (core/text.hpp) and seed streams for the planning module.

#include <cstdint>

#include "proprio/core/text.hpp"

namespace proprio::planning::detail {

using core::cat;
using core::num;

/// splitmix64: a well-mixed seed for stream `x` (independent streams from one seed).
inline std::uint64_t mix_seed(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

}  // namespace proprio::planning::detail
