#pragma once
// A record that takes over the keys of a JSON object made elsewhere (a confusion matrix's
// to_json(), an evaluation's record) lists them in its describe() with describe_json_members.

#include "proprio/core/fields.hpp"
#include "proprio/core/json_io.hpp"

namespace proprio::core {

/// Lists each member of the JSON object `object` as a field of an output description (the key as
/// its name), in the object's order; nothing when it is not an object.
template <class Visitor>
void describe_json_members(const Json& object, Visitor& v) {
  if (!object.is_object()) return;
  for (const auto& [key, value] : object.items()) {
    v(value, FieldInfo{key.c_str(), "a member of a record made elsewhere"});
  }
}

}  // namespace proprio::core
