#include "proprio/core/json_io.hpp"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "proprio/core/error.hpp"
#include "proprio/core/files.hpp"

namespace proprio::core {
namespace {

long line_of(std::string_view text, std::size_t byte) {
  byte = std::min(byte, text.size());
  return 1 +
         static_cast<long>(std::count(text.begin(), text.begin() + static_cast<long>(byte), '\n'));
}

// Throws unless the nesting of arrays and objects stays within kMaxJsonDepth. A scan of the
// text, outside strings, before the parser sees it.
void check_depth(std::string_view text, const std::filesystem::path& source) {
  int depth = 0;
  bool in_string = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\') {
        ++i;
      } else if (c == '"') {
        in_string = false;
      }
      continue;
    }
    if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > kMaxJsonDepth) {
        throw Error::at_line(
            source, line_of(text, i),
            "invalid JSON: nested deeper than " + std::to_string(kMaxJsonDepth) + " levels");
      }
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
}

// nlohmann's message without its "[json.exception.parse_error.101] " prefix.
std::string plain_message(const nlohmann::json::exception& e) {
  std::string what = e.what();
  const auto bracket = what.find("] ");
  if (what.rfind("[json.exception.", 0) == 0 && bracket != std::string::npos) {
    what = what.substr(bracket + 2);
  }
  return what;
}

}  // namespace

std::optional<std::string> first_non_finite(const Json& value) {
  // An explicit stack, not recursion: a parsed value may nest kMaxJsonDepth levels.
  std::vector<std::pair<const Json*, std::string>> todo{{&value, ""}};
  while (!todo.empty()) {
    auto [v, where] = std::move(todo.back());
    todo.pop_back();
    if (v->is_number_float()) {
      if (!std::isfinite(v->get<double>())) return where.empty() ? std::string("/") : where;
    } else if (v->is_object()) {
      for (auto it = v->begin(); it != v->end(); ++it) {
        todo.emplace_back(&it.value(), where + "/" + it.key());
      }
    } else if (v->is_array()) {
      for (std::size_t i = 0; i < v->size(); ++i) {
        todo.emplace_back(&(*v)[i], where + "/" + std::to_string(i));
      }
    }
  }
  return std::nullopt;
}

Json parse_json(std::string_view text, const std::filesystem::path& source) {
  check_depth(text, source);
  try {
    return Json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    std::string what = e.what();
    // nlohmann's message starts "[json.exception.parse_error.101] parse error at line ...".
    const auto colon = what.find(": ");
    if (colon != std::string::npos) what = what.substr(colon + 2);
    throw Error::at_line(source, line_of(text, e.byte), "invalid JSON: " + what);
  } catch (const nlohmann::json::exception& e) {
    // out_of_range 406: a number beyond a double ("1e400"); nlohmann gives no position.
    throw Error::in_file(source, "invalid JSON: " + plain_message(e));
  }
}

Json read_json(const std::filesystem::path& path) { return parse_json(read_file(path), path); }

void write_json_atomic(const std::filesystem::path& path, const Json& value) {
  // nlohmann would write NaN and Inf as null: a figure silently lost. proprio never writes them;
  // one here is a bug upstream (inputs and options are checked where they come in).
  if (const auto where = first_non_finite(value)) {
    throw InternalError(path.string() + ": refusing to write a non-finite number at " + *where);
  }
  write_file_atomic(path, value.dump(2, ' ', false, Json::error_handler_t::replace) + "\n");
}

}  // namespace proprio::core
