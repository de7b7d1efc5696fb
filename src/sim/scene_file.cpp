#include "proprio/sim/scene_file.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdint>
#include <fstream>
#include <sstream>

#include "proprio/core/error.hpp"

namespace proprio::sim {
namespace fs = std::filesystem;

namespace {

std::string extension(const fs::path& p) { return p.extension().string(); }

bool is_yaml(const fs::path& p) { return extension(p) == ".yaml" || extension(p) == ".yml"; }

core::Json scalar_to_json(const YAML::Node& node, const fs::path& file) {
  const std::string& text = node.Scalar();
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

core::Json to_json(const YAML::Node& node, const fs::path& file) {
  const long line = node.Mark().line + 1;
  switch (node.Type()) {
    case YAML::NodeType::Undefined:
    case YAML::NodeType::Null:
      return nullptr;
    case YAML::NodeType::Scalar:
      return scalar_to_json(node, file);
    case YAML::NodeType::Sequence: {
      core::Json a = core::Json::array();
      for (const YAML::Node& item : node) a.push_back(to_json(item, file));
      return a;
    }
    case YAML::NodeType::Map: {
      core::Json o = core::Json::object();
      for (const auto& kv : node) {
        if (!kv.first.IsScalar()) {
          throw Error::at_line(file, kv.first.Mark().line + 1, "a map key must be a plain value");
        }
        const std::string key = kv.first.Scalar();
        if (o.contains(key)) {
          throw Error::at_line(file, kv.first.Mark().line + 1, "duplicate key '" + key + "'");
        }
        o[key] = to_json(kv.second, file);
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
  std::ifstream in(file, std::ios::binary);
  if (!in) throw Error::in_file(file, "cannot read the scene file");
  std::ostringstream text;
  text << in.rdbuf();
  YAML::Node root;
  try {
    root = YAML::Load(text.str());
  } catch (const YAML::Exception& e) {
    throw Error::at_line(file, e.mark.line + 1, e.msg);
  }
  if (!root.IsMap()) throw Error::in_file(file, "a scene file holds a map (objects, target, ...)");
  return to_json(root, file);
}

}  // namespace proprio::sim
