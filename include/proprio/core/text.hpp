#pragma once
// Building error messages.

#include <cstdio>
#include <initializer_list>
#include <string>
#include <string_view>

namespace proprio::core {

/// Concatenation in steps (GCC 12's -Wrestrict misfires on "literal" + std::string + ...).
inline std::string cat(std::initializer_list<std::string_view> parts) {
  std::string out;
  for (std::string_view p : parts) out += p;
  return out;
}

/// A number with 4 significant digits, for messages.
inline std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

}  // namespace proprio::core
