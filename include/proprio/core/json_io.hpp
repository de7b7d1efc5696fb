#pragma once
// JSON files: read with errors that name the file and line, written atomically.

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

namespace proprio::core {

using Json = nlohmann::json;

/// Parses a JSON file. Throws Error "FILE:LINE: problem" on a syntax error.
Json read_json(const std::filesystem::path& path);

/// Writes `value` pretty-printed (2-space indent) atomically.
void write_json_atomic(const std::filesystem::path& path, const Json& value);

/// Reads `key` from object `j` as T; throws Error naming `file` and the key when it is missing or
/// of the wrong type.
template <typename T>
T json_get(const Json& j, const std::string& key, const std::filesystem::path& file);

}  // namespace proprio::core

#include "proprio/core/json_io_impl.hpp"
