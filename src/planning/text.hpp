#pragma once
// Message building for the planning module's errors.

#include <cstdio>
#include <initializer_list>
#include <string>
#include <string_view>

namespace proprio::planning::detail {

/// Concatenation in steps (GCC 12's -Wrestrict misfires on "literal" + std::string + ...).
inline std::string cat(std::initializer_list<std::string_view> parts) {
  std::string out;
  for (std::string_view p : parts) out += p;
  return out;
}

/// A number with 4 significant digits.
inline std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

}  // namespace proprio::planning::detail

#include <cstdint>

namespace proprio::planning::detail {

/// splitmix64: a well-mixed seed for stream `x` (independent streams from one seed).
inline std::uint64_t mix_seed(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

}  // namespace proprio::planning::detail
