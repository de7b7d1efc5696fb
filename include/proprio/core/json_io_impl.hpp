#pragma once
// Template definitions for json_io.hpp.

#include "proprio/core/error.hpp"

namespace proprio::core {

template <typename T>
T json_get(const Json& j, const std::string& key, const std::filesystem::path& file) {
  if (!j.is_object()) throw Error::in_file(file, "expected a JSON object");
  const auto it = j.find(key);
  if (it == j.end()) throw Error::in_file(file, "missing key '" + key + "'");
  try {
    return it->template get<T>();
  } catch (const nlohmann::json::exception&) {
    throw Error::in_file(file, "key '" + key + "' has the wrong type (" + it->type_name() + ")");
  }
}

}  // namespace proprio::core
