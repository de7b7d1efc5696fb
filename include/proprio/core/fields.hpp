#pragma once
// One description of an Options (or Result) struct's fields. Its JSON, its bounds check, the
// CLI's flags (app/option_binder.hpp) and, next, the Python bindings are all made from it, so that
// a field is named, documented and bounded in one place and means the same in every command.
//
// A Result or Summary describes itself the same way, and its JSON record comes from that
// description (fields_into_json), so that the CLI's --json, the tests and the Python bindings read
// the same names. Output descriptions take three more kinds of field:
//   - a struct with its own describe(): a nested JSON object;
//   - std::vector<T> of any field type: a JSON array;
//   - std::map<std::string, T>: a JSON object keyed by the map's keys;
//   - std::optional<T>: the key is left out when it is empty (or_null(x) writes null instead);
// and core::Json, copied as it is. A derived value may be described as an expression
// (`v(self.documents_per_second(), {...})`): such a description is for output only.
//
// A struct describes itself with a static member template that lists its fields in order:
//
//   struct DenseOptions {
//     int step = 8;
//     FeatureKind kind = FeatureKind::kDense;
//     template <class Self, class Visitor>
//     static void describe(Self& self, Visitor& v) {  // Self: DenseOptions or const DenseOptions
//       v(self.step, {"step", "Dense grid spacing, px", core::at_least(1)});
//       v.choice(self.kind, {"features", "dense or sift"}, kFeatureKindNames);
//     }
//   };
//
// A field may be a member of a nested struct (`self.dense.step`): the description is flat, named
// as the user sees it. Field types: bool, integers, floating point, std::string,
// std::filesystem::path, and enums through choice() with a table of (name, value) pairs.

#include <algorithm>
#include <array>
#include <cmath>
#include <concepts>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "proprio/core/error.hpp"
#include "proprio/core/json_io.hpp"

namespace proprio::core {

/// The values a numeric field accepts: [min, max], or (min, max] when `min_exclusive`. NaN is
/// never inside.
struct Bounds {
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  bool min_exclusive = false;

  [[nodiscard]] bool contains(double x) const {
    if (std::isnan(x)) return false;
    return (min_exclusive ? x > min : x >= min) && x <= max;
  }
  [[nodiscard]] bool bounded() const { return std::isfinite(min) || std::isfinite(max); }
  /// "in [1, 10]", ">= 0", "> 0", "<= 5", "finite, >= 0", or "" when unbounded.
  [[nodiscard]] std::string describe() const;
};

[[nodiscard]] constexpr Bounds at_least(double min) { return {min}; }
[[nodiscard]] constexpr Bounds between(double min, double max) { return {min, max}; }
/// >= min and finite (infinity is outside).
[[nodiscard]] constexpr Bounds finite_at_least(double min) {
  return {min, std::numeric_limits<double>::max()};
}
/// > 0.
[[nodiscard]] constexpr Bounds positive() {
  return {0.0, std::numeric_limits<double>::infinity(), true};
}
/// In (0, max].
[[nodiscard]] constexpr Bounds positive_at_most(double max) { return {0.0, max, true}; }

/// What a description says of one field.
struct FieldInfo {
  const char* name;  ///< the JSON key; the CLI flag is --name with '_' written '-' (or `flag`)
  const char* help;  ///< one line: what it is, its unit
  Bounds bounds = {};
  const char* short_flag = nullptr;  ///< one letter for the CLI (e.g. "k"), or none
  const char* flag = nullptr;        ///< the CLI's long flag when it is not the name
};

/// A choice's (name, value) table: names as users type them and JSON holds them.
template <class E, std::size_t N>
using ChoiceNames = std::array<std::pair<std::string_view, E>, N>;

/// The name of `value` in `names`; InternalError when the table lacks it.
template <class E, std::size_t N>
std::string_view choice_name(E value, const ChoiceNames<E, N>& names) {
  for (const auto& [name, v] : names) {
    if (v == value) return name;
  }
  throw InternalError("a choice's value has no name in its table");
}

/// "a, b or c".
template <class E, std::size_t N>
std::string choice_list(const ChoiceNames<E, N>& names) {
  std::string out;
  for (std::size_t i = 0; i < N; ++i) {
    if (i > 0) out += i + 1 == N ? " or " : ", ";
    out += names[i].first;
  }
  return out;
}

namespace detail {

template <class T>
constexpr bool kNumber = std::is_arithmetic_v<T> && !std::is_same_v<T, bool>;

template <class T>
constexpr bool kVector = false;
template <class T, class A>
constexpr bool kVector<std::vector<T, A>> = true;
template <class T>
constexpr bool kMap = false;
template <class T, class C, class A>
constexpr bool kMap<std::map<std::string, T, C, A>> = true;
template <class T>
constexpr bool kOptional = false;
template <class T>
constexpr bool kOptional<std::optional<T>> = true;

struct ToJson;

/// A struct with a describe() of its own (written as a nested JSON object).
template <class T>
concept Described = requires(const T& t, ToJson& v) {
  T::describe(t, v);
};

template <class T>
Json value_to_json(const T& value);

// Writes each field into a JSON object.
struct ToJson {
  Json* out;
  template <class T>
  void operator()(const T& value, const FieldInfo& info) {
    if constexpr (kOptional<T>) {
      if (value) (*out)[info.name] = value_to_json(*value);
    } else {
      (*out)[info.name] = value_to_json(value);
    }
  }
  template <class E, std::size_t N>
  void choice(const E& value, const FieldInfo& info, const ChoiceNames<E, N>& names) {
    (*out)[info.name] = std::string(choice_name(value, names));
  }
};

// One value as JSON: a path as its string, a described struct as an object, a vector as an array.
template <class T>
Json value_to_json(const T& value) {
  if constexpr (std::is_same_v<T, std::filesystem::path>) {
    return value.string();
  } else if constexpr (Described<T>) {
    Json out = Json::object();
    ToJson v{&out};
    T::describe(value, v);
    return out;
  } else if constexpr (kVector<T>) {
    Json out = Json::array();
    for (const auto& e : value) out.push_back(value_to_json(e));
    return out;
  } else if constexpr (kMap<T>) {
    Json out = Json::object();
    for (const auto& [key, e] : value) out[key] = value_to_json(e);
    return out;
  } else if constexpr (kOptional<T>) {
    return value ? value_to_json(*value) : Json();
  } else {
    return Json(value);
  }
}

// Throws Error naming the first numeric field outside its bounds.
struct CheckBounds {
  std::string_view what;
  template <class T>
  void operator()(const T& value, const FieldInfo& info) const {
    if constexpr (kNumber<T>) {
      if (!info.bounds.contains(static_cast<double>(value))) {
        std::string m(what);
        m += ": ";
        m += info.name;
        m += " must be ";
        m += info.bounds.describe();
        m += " (it is ";
        m += std::isnan(static_cast<double>(value)) ? std::string("NaN") : json_number(value);
        m += ")";
        throw Error(m);
      }
    }
  }
  template <class E, std::size_t N>
  void choice(const E& /*value*/, const FieldInfo& /*info*/, const ChoiceNames<E, N>& /*names*/) {}

  template <class T>
  static std::string json_number(T value) {
    return Json(value).dump();
  }
};

// Reads the fields present in a JSON object; counts what it used so that unknown keys are found.
struct FromJson {
  const Json* in;
  std::string_view where;
  std::size_t used = 0;

  [[nodiscard]] Error bad(const FieldInfo& info, const std::string& problem) const {
    std::string m(where);
    m += ": ";
    m += info.name;
    m += ' ';
    m += problem;
    return Error(m);
  }

  template <class T>
  void operator()(T& value, const FieldInfo& info) {
    const auto it = in->find(info.name);
    if (it == in->end()) return;
    ++used;
    if constexpr (std::is_same_v<T, bool>) {
      if (!it->is_boolean()) throw bad(info, "must be true or false");
      value = it->template get<bool>();
    } else if constexpr (std::is_integral_v<T>) {
      if (!it->is_number_integer()) throw bad(info, "must be an integer");
      if constexpr (std::is_unsigned_v<T>) {
        if (it->is_number_unsigned()) {
          value = it->template get<T>();
        } else {
          const auto x = it->template get<std::int64_t>();
          if (x < 0) throw bad(info, "must be >= 0");
          value = static_cast<T>(x);
        }
      } else {
        if (it->is_number_unsigned() &&
            it->template get<std::uint64_t>() >
                static_cast<std::uint64_t>(std::numeric_limits<T>::max()))
          throw bad(info, "is too large");
        const auto x = it->template get<std::int64_t>();
        if (x < std::numeric_limits<T>::min() || x > std::numeric_limits<T>::max())
          throw bad(info, "is out of range");
        value = static_cast<T>(x);
      }
    } else if constexpr (std::is_floating_point_v<T>) {
      if (!it->is_number()) throw bad(info, "must be a number");
      value = it->template get<T>();
    } else if constexpr (std::is_same_v<T, std::filesystem::path>) {
      if (!it->is_string()) throw bad(info, "must be a string (a path)");
      value = it->template get<std::string>();
    } else {
      if (!it->is_string()) throw bad(info, "must be a string");
      value = it->template get<std::string>();
    }
  }
  template <class E, std::size_t N>
  void choice(E& value, const FieldInfo& info, const ChoiceNames<E, N>& names) {
    const auto it = in->find(info.name);
    if (it == in->end()) return;
    ++used;
    if (!it->is_string()) throw bad(info, "must be a string: " + choice_list(names));
    const auto text = it->template get<std::string>();
    for (const auto& [name, v] : names) {
      if (name == text) {
        value = v;
        return;
      }
    }
    throw bad(info, "must be " + choice_list(names) + " (it is '" + text + "')");
  }
};

// Collects the names, to list them when a key is unknown.
struct Names {
  std::vector<std::string_view> names;
  template <class T>
  void operator()(const T& /*value*/, const FieldInfo& info) {
    names.emplace_back(info.name);
  }
  template <class E, std::size_t N>
  void choice(const E& /*value*/, const FieldInfo& info, const ChoiceNames<E, N>& /*names*/) {
    names.emplace_back(info.name);
  }
  [[nodiscard]] bool has(std::string_view key) const {
    return std::find(names.begin(), names.end(), key) != names.end();
  }
  [[nodiscard]] std::string list() const {
    std::string out;
    for (const auto n : names) {
      if (!out.empty()) out += ", ";
      out += n;
    }
    return out;
  }
};

}  // namespace detail

/// An optional field whose key a record always holds: its value, or null when it is empty (a
/// plain std::optional field leaves the key out).
template <class T>
Json or_null(const std::optional<T>& x) {
  return x ? detail::value_to_json(*x) : Json();
}

/// A matrix (anything with rows(), cols() and (r, c), e.g. Eigen's) as its rows, for a
/// description to list as a derived field.
template <class M>
std::vector<std::vector<double>> matrix_rows(const M& m) {
  std::vector<std::vector<double>> rows;
  rows.reserve(static_cast<std::size_t>(m.rows()));
  for (decltype(m.rows()) r = 0; r < m.rows(); ++r) {
    std::vector<double> row;
    row.reserve(static_cast<std::size_t>(m.cols()));
    for (decltype(m.cols()) c = 0; c < m.cols(); ++c) row.push_back(static_cast<double>(m(r, c)));
    rows.push_back(std::move(row));
  }
  return rows;
}

/// A vector (anything with size() and data(), e.g. an Eigen vector) as a std::vector<double>.
template <class V>
std::vector<double> vector_values(const V& v) {
  return std::vector<double>(v.data(), v.data() + v.size());
}

/// The fields of `s` as a JSON object (keys sorted, as in every proprio JSON; enums by name,
/// paths as strings).
template <class S>
Json fields_to_json(const S& s) {
  Json out = Json::object();
  detail::ToJson v{&out};
  S::describe(s, v);
  return out;
}

/// Adds the fields of `s` to the object `out` (a record that already holds its "format" and
/// provenance): the one way a Result or Summary becomes JSON.
template <class S>
void fields_into_json(const S& s, Json& out) {
  detail::ToJson v{&out};
  S::describe(s, v);
}

/// Throws Error "WHAT: NAME must be BOUNDS (it is X)" for the first numeric field outside its
/// documented bounds (NaN is outside every bound). The usual first line of a validate().
template <class S>
void check_field_bounds(const S& s, std::string_view what) {
  detail::CheckBounds v{what};
  S::describe(s, v);
}

/// The names of the fields of S, in the description's order.
template <class S>
std::vector<std::string_view> field_names() {
  S s{};
  detail::Names names;
  S::describe(std::as_const(s), names);
  return names.names;
}

/// Sets the fields of `s` that `json` (an object) names; the others keep their values. Throws
/// Error naming `where` and the key for a key the description lacks, a value of the wrong type,
/// or a name outside a choice's table. Bounds are not checked here (validate() does).
template <class S>
void fields_from_json(const Json& json, S& s, std::string_view where) {
  if (!json.is_object()) throw Error(std::string(where) + ": must be a JSON object");
  detail::FromJson v{&json, where};
  S::describe(s, v);
  if (v.used != json.size()) {
    detail::Names names;
    S::describe(std::as_const(s), names);
    for (const auto& [key, value] : json.items()) {
      if (!names.has(key)) {
        throw Error(std::string(where) + ": unknown option '" + key + "' (known: " + names.list() +
                    ")");
      }
    }
  }
}

/// The Summary convention of every Result and Summary: a one-line `message` (what happened, or
/// why it stopped) and `brief()`, the few lines a person reads (the CLI prints it). A message is
/// for people and logs; a record's JSON comes from the description.
template <class S>
concept Summary = requires(const S& s) {
  { s.message } -> std::convertible_to<std::string>;
  { s.brief() } -> std::convertible_to<std::string>;
};

/// The first line of `text` (all of it when it has one): the headline of a brief(), which a
/// Summary whose brief() opens with what happened keeps as its message.
inline std::string first_line(std::string_view text) {
  return std::string(text.substr(0, text.find('\n')));
}

}  // namespace proprio::core
