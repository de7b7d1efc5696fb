#include "proprio/core/yaml_depth.hpp"

#include <algorithm>
#include <string>
#include <vector>

#include "proprio/core/error.hpp"

namespace proprio::core {

void check_yaml_depth(std::string_view text, const std::filesystem::path& source, int max_depth) {
  std::vector<std::size_t> indents;  // the indentation of the open block levels
  int flow = 0;                      // open '[' and '{' (flow collections span lines)
  long line = 0;
  std::size_t pos = 0;
  auto too_deep = [&] {
    return Error::at_line(source, line,
                          "nested deeper than " + std::to_string(max_depth) + " levels");
  };
  while (pos < text.size()) {
    ++line;
    const std::size_t end = std::min(text.find('\n', pos), text.size());
    const std::string_view l = text.substr(pos, end - pos);
    pos = end + 1;
    std::size_t i = 0;
    while (i < l.size() && l[i] == ' ') ++i;
    if (i == l.size() || l[i] == '#') continue;  // blank or comment: no level
    if (flow == 0) {
      while (!indents.empty() && indents.back() > i) indents.pop_back();
      if (indents.empty() || indents.back() < i) indents.push_back(i);
    }
    // "- - - x": each dash opens a sequence inside the one before.
    int dashes = 0;
    while (i + 1 < l.size() && l[i] == '-' && (l[i + 1] == ' ' || l[i + 1] == '\t')) {
      ++dashes;
      i += 2;
      while (i < l.size() && l[i] == ' ') ++i;
    }
    char quote = 0;
    int deepest_flow = flow;
    for (; i < l.size(); ++i) {
      const char c = l[i];
      if (quote != 0) {
        if (c == quote) quote = 0;
        continue;
      }
      if (c == '"' || c == '\'') {
        quote = c;
      } else if (c == '#' && (i == 0 || l[i - 1] == ' ')) {
        break;
      } else if (c == '[' || c == '{') {
        deepest_flow = std::max(deepest_flow, ++flow);
      } else if ((c == ']' || c == '}') && flow > 0) {
        --flow;
      }
    }
    if (static_cast<long>(indents.size()) + dashes + deepest_flow > max_depth) throw too_deep();
  }
}

namespace {

// The offset of the first byte that is not part of well-formed UTF-8 and why, or npos.
std::size_t first_non_utf8(std::string_view text, std::string& why) {
  for (std::size_t i = 0; i < text.size();) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c < 0x80) {
      ++i;
      continue;
    }
    std::size_t n = 0;
    unsigned min = 0;
    if ((c & 0xE0) == 0xC0) {
      n = 1;
      min = 0x80;
    } else if ((c & 0xF0) == 0xE0) {
      n = 2;
      min = 0x800;
    } else if ((c & 0xF8) == 0xF0) {
      n = 3;
      min = 0x10000;
    } else {
      why = "byte " + std::to_string(c);
      return i;
    }
    unsigned code = c & (0x3Fu >> n);
    for (std::size_t k = 1; k <= n; ++k) {
      const auto b = i + k < text.size() ? static_cast<unsigned char>(text[i + k]) : 0;
      if ((b & 0xC0) != 0x80) {
        why = "a truncated sequence";
        return i;
      }
      code = (code << 6) | (b & 0x3Fu);
    }
    // Overlong forms, UTF-16 surrogates and code points past U+10FFFF are not UTF-8 either.
    if (code < min || (code >= 0xD800 && code <= 0xDFFF) || code > 0x10FFFF) {
      why = "an invalid sequence";
      return i;
    }
    i += n + 1;
  }
  return std::string_view::npos;
}

}  // namespace

void check_utf8(std::string_view text, const std::filesystem::path& source) {
  std::string why;
  const std::size_t at = first_non_utf8(text, why);
  if (at == std::string_view::npos) return;
  const long line =
      1 + static_cast<long>(std::count(text.begin(), text.begin() + static_cast<long>(at), '\n'));
  throw Error::at_line(source, line, "not UTF-8 text (" + why + ")");
}

bool is_utf8(std::string_view text) {
  std::string why;
  return first_non_utf8(text, why) == std::string_view::npos;
}

}  // namespace proprio::core
