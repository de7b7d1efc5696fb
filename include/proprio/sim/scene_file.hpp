#pragma once
// Scene files (docs/formats/scenario.md) in JSON or YAML. A YAML file is converted to the same
// JSON tree a JSON file parses to, so that one reader checks both.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>

#include "proprio/core/json_io.hpp"

namespace proprio::sim {

/// The largest scene file read (16 MiB; the shipped ones are a few kilobytes).
inline constexpr std::uintmax_t kMaxSceneFileBytes = std::uintmax_t{16} << 20;
/// What a YAML scene may expand to through aliases: this many values per byte of the file.
inline constexpr std::size_t kMaxSceneValuesPerByte = 4;

/// True when `name` ends in .json, .yaml or .yml (a scene file rather than a scenario name).
[[nodiscard]] bool is_scene_file(const std::string& name);

/// Reads a scene file into JSON: .json with nlohmann::json, .yaml / .yml with yaml-cpp. YAML
/// scalars become JSON scalars by their text (null, ~ and empty: null; true/false: booleans;
/// integers; decimal numbers; anything else, and every quoted scalar: strings). Throws Error
/// "FILE:LINE: problem" for a syntax error, a duplicate or non-scalar key, or a number that is
/// not finite, nesting deeper than core::kMaxYamlDepth, or aliases that expand to more than
/// kMaxSceneValuesPerByte values per byte of the file; Error naming the file when it cannot be
/// read, is bigger than kMaxSceneFileBytes, or its extension is neither.
core::Json read_scene_file(const std::filesystem::path& file);

}  // namespace proprio::sim
