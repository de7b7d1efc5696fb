#include "proprio/sim/scene_file.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdint>

#include "proprio/core/error.hpp"
#include "proprio/core/files.hpp"
#include "proprio/core/yaml_depth.hpp"

namespace proprio::sim {
namespace fs = std::filesystem;

namespace {

std::string extension(const fs::path& p) { return p.extension().string(); }

bool is_yaml(const fs::path& p) { return extension(p) == ".yaml" || extension(p) == ".yml"; }

// yaml-cpp keeps an alias as a second reference to its anchor's node, but converting to JSON
// copies it: nested aliases ("billion laughs") turn a kilobyte into gigabytes. The conversion
// counts the values it makes against a budget that grows with the file's size.
struct Budget {
  std::size_t left;
  int depth = 0;
};

core::Json to_json_node(const YAML::Node& node, const fs::path& file, Budget& budget);

core::Json scalar_to_json(const YAML::Node& node, const fs::path& file) {
  const std::string& text = node.Scalar();
  // yaml-cpp can make bytes that are not UTF-8 out of escapes (found by fuzz_scene); JSON holds
  // only UTF-8.
  if (!core::is_utf8(text)) {
    throw Error::at_line(file, node.Mark().line + 1, "a value is not UTF-8 text");
  }
  // yaml-cpp tags quoted scalars "!" and plain ones "?": only plain ones are typed by their text.
  if (node.Tag() == "!") return text;
  if (text.empty() || text == "~" || text == "null" || text == "Null" || text == "NULL") {
    return nullptr;
  }
  bool b = false;
  if (YAML::convert<bool>::decode(node, b)) return b;
  std::int64_t i = 0;
  if (YAML::convert<std::int64_t>::decode(node, i)) return i;
  double d = 0.0;
  if (YAML::convert<double>::decode(node, d)) {
    if (!std::isfinite(d)) {
      throw Error::at_line(file, node.Mark().line + 1, "'" + text + "' is not a finite number");
    }
    return d;
  }
  return text;
}

core::Json to_json(const YAML::Node& node, const fs::path& file, Budget& budget) {
  const long line = node.Mark().line + 1;
  if (budget.left == 0) {
    throw Error::at_line(file, line,
                         "the aliases expand to too many values (at most " +
                             std::to_string(kMaxSceneValuesPerByte) +
                             " per byte of the file); nested aliases?");
  }
  --budget.left;
  if (budget.depth >= core::kMaxYamlDepth) {
    throw Error::at_line(file, line,
                         "nested deeper than " + std::to_string(core::kMaxYamlDepth) + " levels");
  }
  ++budget.depth;
  core::Json out = to_json_node(node, file, budget);
  --budget.depth;
  return out;
}

core::Json to_json_node(const YAML::Node& node, const fs::path& file, Budget& budget) {
  const long line = node.Mark().line + 1;
  switch (node.Type()) {
    case YAML::NodeType::Undefined:
    case YAML::NodeType::Null:
      return nullptr;
    case YAML::NodeType::Scalar:
      return scalar_to_json(node, file);
    case YAML::NodeType::Sequence: {
      core::Json a = core::Json::array();
      for (const YAML::Node& item : node) a.push_back(to_json(item, file, budget));
      return a;
    }
    case YAML::NodeType::Map: {
      core::Json o = core::Json::object();
      for (const auto& kv : node) {
        if (!kv.first.IsScalar()) {
          throw Error::at_line(file, kv.first.Mark().line + 1, "a map key must be a plain value");
        }
        const std::string key = kv.first.Scalar();
        if (!core::is_utf8(key)) {
          throw Error::at_line(file, kv.first.Mark().line + 1, "a key is not UTF-8 text");
        }
        if (o.contains(key)) {
          throw Error::at_line(file, kv.first.Mark().line + 1, "duplicate key '" + key + "'");
        }
        o[key] = to_json(kv.second, file, budget);
      }
      return o;
    }
  }
  throw Error::at_line(file, line, "unknown YAML node");
}

}  // namespace

bool is_scene_file(const std::string& name) {
  const std::string e = extension(name);
  return e == ".json" || e == ".yaml" || e == ".yml";
}

core::Json read_scene_file(const fs::path& file) {
  if (extension(file) == ".json") return core::read_json(file);
  if (!is_yaml(file)) {
    throw Error::in_file(file, "a scene file must end in .json, .yaml or .yml");
  }
  const std::string text = core::read_file(file, kMaxSceneFileBytes);
  // yaml-cpp parses nested values by recursion: bound the nesting before it sees the text.
  core::check_yaml_depth(text, file);
  core::check_utf8(text, file);
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw Error::at_line(file, e.mark.line + 1, e.msg);
  }
  if (!root.IsMap()) throw Error::in_file(file, "a scene file holds a map (objects, target, ...)");
  Budget budget{kMaxSceneValuesPerByte * (text.size() + 1)};
  return to_json(root, file, budget);
}

}  // namespace proprio::sim
