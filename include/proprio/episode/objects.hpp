#pragma once
// objects.json: the objects of an episode, by the id they have in the ground-truth masks.

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "proprio/core/json_io.hpp"

namespace proprio::episode {

inline constexpr const char* kObjectsFormat = "proprio.objects";
inline constexpr int kObjectsFormatVersion = 1;

/// What an object is to the episode: the one the robot acts on, another object on the table,
/// (a part of) the arm, or a distractor (moving background: people, a nudged neighbour...).
enum class ObjectRole { kTarget, kObject, kArm, kDistractor };

[[nodiscard]] std::string to_string(ObjectRole r);  ///< "target", "object", "arm", "distractor"
/// The role named by `s`, or none.
[[nodiscard]] std::optional<ObjectRole> parse_object_role(const std::string& s);

struct ObjectInfo {
  int id = 0;  ///< 1..65535, the value in masks/*.png (0 is the background)
  std::string name;
  ObjectRole role = ObjectRole::kObject;
};

/// objects.json: {"format", "format_version", "objects": [{"id", "name", "role"}, ...]}.
core::Json objects_to_json(const std::vector<ObjectInfo>& objects);

/// Parses objects.json; checks ids (1..65535, unique), names (not empty) and roles (at most one
/// target). Throws Error naming `file` and the first problem.
std::vector<ObjectInfo> objects_from_json(const core::Json& j, const std::filesystem::path& file);

}  // namespace proprio::episode
