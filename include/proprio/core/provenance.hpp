#pragma once
// Provenance carried by every result file: which program, which build, which command, which seed.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "proprio/core/json_io.hpp"

namespace proprio::core {

struct Provenance {
  std::string proprio_version;
  std::string git_commit;
  std::string command_line;  ///< the argv joined by spaces, as the user typed it
  std::optional<std::uint64_t> seed;
  /// The linked OpenCV's and MuJoCo's versions. Empty from current(): core links neither, so the
  /// program fills them from the modules that do (geometry::opencv_version(),
  /// robot::mujoco_version()); they stay empty in a program that links neither.
  std::string opencv_version;
  std::string mujoco_version;
  std::string created_utc;  ///< ISO 8601, e.g. 2026-11-21T23:46:32Z

  /// This build's provenance for a run with the given command line and seed (library versions
  /// left empty, see above).
  static Provenance current(const std::vector<std::string>& argv,
                            std::optional<std::uint64_t> seed = std::nullopt);
  /// The same, from main()'s arguments.
  static Provenance current(int argc, const char* const* argv,
                            std::optional<std::uint64_t> seed = std::nullopt);
};

Json to_json(const Provenance& p);
/// Reads provenance written by to_json; `file` names the source in errors.
Provenance provenance_from_json(const Json& j, const std::string& file);

/// A JSON result document: {"format": name, "format_version": v, "provenance": {...}} to which the
/// caller adds its figures.
Json result_document(const std::string& format, int format_version, const Provenance& p);

}  // namespace proprio::core
