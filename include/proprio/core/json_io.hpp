#pragma once
// JSON files: read with errors that name the file and line, written atomically.

#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>

namespace proprio::core {

using Json = nlohmann::json;

/// The deepest nesting of arrays and objects a JSON input may have. proprio's own files nest a few
/// levels; a bound keeps hostile input (100,000 '[') from exhausting the stack of code that walks
/// the parsed value recursively.
inline constexpr int kMaxJsonDepth = 256;

/// Parses JSON text read from `source`. Throws Error "FILE:LINE: problem" on a syntax error, on
/// nesting deeper than kMaxJsonDepth, and on a number out of a double's range (1e400).
Json parse_json(std::string_view text, const std::filesystem::path& source);

/// Parses a JSON file (core::read_file, then parse_json).
Json read_json(const std::filesystem::path& path);

/// The JSON pointer (RFC 6901, "/a/0/b"; keys not escaped) of the first NaN or Inf in `value`, or
/// none when every number is finite.
std::optional<std::string> first_non_finite(const Json& value);

/// Writes `value` pretty-printed (2-space indent) atomically. Bytes of strings that are not
/// UTF-8 (a file name, a problem quoting outside input) are written as U+FFFD. Throws
/// InternalError, writing nothing, when a number is NaN or Inf (first_non_finite): nlohmann
/// would write null, and proprio never writes a non-finite figure.
void write_json_atomic(const std::filesystem::path& path, const Json& value);

/// Reads `key` from object `j` as T; throws Error naming `file` and the key when it is missing or
/// of the wrong type.
template <typename T>
T json_get(const Json& j, const std::string& key, const std::filesystem::path& file);

}  // namespace proprio::core

#include "proprio/core/json_io_impl.hpp"
