#include "proprio/core/yaml_depth.hpp"

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

}  // namespace proprio::core
