#include "proprio/episode/objects.hpp"

#include <set>

#include "parse.hpp"

namespace proprio::episode {

std::string to_string(ObjectRole r) {
  switch (r) {
    case ObjectRole::kTarget:
      return "target";
    case ObjectRole::kObject:
      return "object";
    case ObjectRole::kArm:
      return "arm";
    case ObjectRole::kDistractor:
      return "distractor";
  }
  return "object";
}

std::optional<ObjectRole> parse_object_role(const std::string& s) {
  for (const ObjectRole r :
       {ObjectRole::kTarget, ObjectRole::kObject, ObjectRole::kArm, ObjectRole::kDistractor}) {
    if (s == to_string(r)) return r;
  }
  return std::nullopt;
}

core::Json objects_to_json(const std::vector<ObjectInfo>& objects) {
  core::Json list = core::Json::array();
  for (const auto& o : objects) {
    list.push_back({{"id", o.id}, {"name", o.name}, {"role", to_string(o.role)}});
  }
  return {{"format", kObjectsFormat}, {"format_version", kObjectsFormatVersion}, {"objects", list}};
}

std::vector<ObjectInfo> objects_from_json(const core::Json& j, const std::filesystem::path& file) {
  detail::ProblemSink sink(true, 1);
  auto objects = detail::parse_objects(j, file, sink);
  // The sink throws on the first problem, so a parse without a result is a bug here.
  ensure(objects.has_value(), file.string() + ": objects.json parsed to nothing without a problem");
  return *objects;
}

namespace detail {

std::optional<std::vector<ObjectInfo>> parse_objects(const core::Json& j,
                                                     const std::filesystem::path& file,
                                                     ProblemSink& sink) {
  if (!j.is_object()) {
    sink.add(file, "expected a JSON object");
    return std::nullopt;
  }
  const auto format = j.find("format");
  if (format == j.end() || !format->is_string() || *format != kObjectsFormat) {
    sink.add(file, std::string("'format' must be '") + kObjectsFormat + "'");
    return std::nullopt;
  }
  const auto version = j.find("format_version");
  if (version == j.end() || !version->is_number_integer() || *version < 1) {
    sink.add(file, "'format_version' must be a positive integer");
    return std::nullopt;
  }
  if (version->get<long long>() > kObjectsFormatVersion) {
    sink.add(file, "format_version " + version->dump() +
                       " is newer than this build of proprio supports (" +
                       std::to_string(kObjectsFormatVersion) + "); update proprio");
    return std::nullopt;
  }
  const auto list = j.find("objects");
  if (list == j.end() || !list->is_array()) {
    sink.add(file, "'objects' must be an array");
    return std::nullopt;
  }
  std::vector<ObjectInfo> out;
  std::set<int> ids;
  std::set<std::string> names;
  bool ok = true;
  int targets = 0;
  for (size_t k = 0; k < list->size(); ++k) {
    const core::Json& o = (*list)[k];
    const std::string where = "objects[" + std::to_string(k) + "]";
    if (!o.is_object()) {
      sink.add(file, where + " is not an object");
      ok = false;
      continue;
    }
    ObjectInfo info;
    const auto id = o.find("id");
    if (id == o.end() || !id->is_number_integer() || *id < 1 || *id > 65535) {
      sink.add(file, where + ": 'id' must be an integer in [1, 65535] (0 is the background), not " +
                         (id == o.end() ? std::string("missing") : id->dump()));
      ok = false;
    } else {
      info.id = id->get<int>();
      if (!ids.insert(info.id).second) {
        sink.add(file, where + ": id " + std::to_string(info.id) + " appears twice");
        ok = false;
      }
    }
    const auto name = o.find("name");
    if (name == o.end() || !name->is_string() || name->get<std::string>().empty()) {
      sink.add(file, where + ": 'name' must be a non-empty string");
      ok = false;
    } else {
      info.name = name->get<std::string>();
      // Objects are told apart by name in results and classifications: a repeated name would
      // merge two objects.
      if (!names.insert(info.name).second) {
        sink.add(file, where + ": name '" + info.name + "' appears twice");
        ok = false;
      }
    }
    const auto role = o.find("role");
    const auto parsed = role != o.end() && role->is_string()
                            ? parse_object_role(role->get<std::string>())
                            : std::nullopt;
    if (!parsed) {
      sink.add(file, where + ": 'role' must be 'target', 'object', 'arm' or 'distractor', not " +
                         (role == o.end() ? std::string("missing") : role->dump()));
      ok = false;
    } else {
      info.role = *parsed;
      if (info.role == ObjectRole::kTarget && ++targets == 2) {
        sink.add(file, "more than one object has the role 'target'");
        ok = false;
      }
    }
    out.push_back(info);
  }
  if (!ok) return std::nullopt;
  return out;
}

}  // namespace detail
}  // namespace proprio::episode
