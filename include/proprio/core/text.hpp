#pragma once
// Building messages and reports.

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

/// `text` for HTML or XML text and attribute values: & < > " ' as entities (' as &#39;, which
/// HTML and XML both read), bytes that are not UTF-8 as U+FFFD, control characters other than
/// newline and tab dropped (XML 1.0 admits none of them).
std::string markup_escape(std::string_view text);

/// printf-style formatting into a string (the reports commands print keep printf's formats, so
/// that their text stays byte for byte what it was).
template <class... Args>
std::string printf_string(const char* format, Args... args) {
  // NOLINTNEXTLINE(cppcoreguidelines-pro-type-vararg)
  const int n = std::snprintf(nullptr, 0, format, args...);
  if (n <= 0) return {};
  std::string out(static_cast<std::size_t>(n), '\0');
  // NOLINTNEXTLINE(cppcoreguidelines-pro-type-vararg)
  std::snprintf(out.data(), out.size() + 1, format, args...);
  return out;
}

}  // namespace proprio::core
