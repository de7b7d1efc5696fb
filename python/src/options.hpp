#pragma once
// One generic Python class per Options struct, made from its static describe(self, v)
// (proprio/core/fields.hpp): a keyword constructor, a property per described field (docstring:
// help, bounds, default), __repr__, __eq__, to_dict/from_dict, fields() and pickling. A value of
// the wrong type or outside the field's bounds is a ValueError naming "Struct.field".

#include <Python.h>

#include <cmath>
#include <concepts>
#include <filesystem>
#include <limits>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>

#include "common.hpp"
#include "proprio/core/fields.hpp"

namespace proprio::python {

namespace options_detail {

template <class T>
py::object to_py(const T& value) {
  if constexpr (std::is_same_v<T, std::filesystem::path>) {
    return py::str(value.string());
  } else {
    return py::cast(value);
  }
}

inline std::string repr_of(const py::handle& obj) { return py::repr(obj); }

template <class T>
const char* type_name() {
  if constexpr (std::is_same_v<T, bool>) {
    return "bool";
  } else if constexpr (std::is_integral_v<T>) {
    return "int";
  } else if constexpr (std::is_floating_point_v<T>) {
    return "float";
  } else {
    return "str";
  }
}

/// obj as a T for the field `where`: bool only from bool; integers from int-like (not bool, not
/// float), in T's range; floats from real numbers (not bool, not str); strings and paths from str
/// (or os.PathLike). Then the field's bounds.
template <class T>
T from_py(const py::handle& obj, const std::string& where, const core::Bounds& bounds) {
  T value{};
  const bool is_bool =
      PyBool_Check(obj.ptr()) || py::isinstance(obj, py::module_::import("numpy").attr("bool_"));
  if constexpr (std::is_same_v<T, bool>) {
    if (!is_bool) throw py::value_error(where + " must be True or False, got " + repr_of(obj));
    value = obj.cast<bool>();
  } else if constexpr (std::is_integral_v<T>) {
    if (is_bool || PyIndex_Check(obj.ptr()) == 0) {
      throw py::value_error(where + " must be an integer, got " + repr_of(obj));
    }
    const auto index = py::reinterpret_steal<py::object>(PyNumber_Index(obj.ptr()));
    if (!index) throw py::error_already_set();
    int overflow = 0;
    const long long x = PyLong_AsLongLongAndOverflow(index.ptr(), &overflow);
    if constexpr (std::is_unsigned_v<T>) {
      if (overflow < 0 || (overflow == 0 && x < 0)) {
        throw py::value_error(where + " must be >= 0, got " + repr_of(obj));
      }
      if (overflow > 0) {
        const unsigned long long u = PyLong_AsUnsignedLongLong(index.ptr());
        if (PyErr_Occurred() != nullptr) {
          PyErr_Clear();
          throw py::value_error(where + " is too large: " + repr_of(obj));
        }
        value = static_cast<T>(u);
      } else {
        if (static_cast<unsigned long long>(x) > std::numeric_limits<T>::max()) {
          throw py::value_error(where + " is too large: " + repr_of(obj));
        }
        value = static_cast<T>(x);
      }
    } else {
      if (overflow != 0 || x < std::numeric_limits<T>::min() || x > std::numeric_limits<T>::max()) {
        throw py::value_error(where + " is out of range: " + repr_of(obj));
      }
      value = static_cast<T>(x);
    }
  } else if constexpr (std::is_floating_point_v<T>) {
    if (is_bool || PyUnicode_Check(obj.ptr()) || PyBytes_Check(obj.ptr())) {
      throw py::value_error(where + " must be a number, got " + repr_of(obj));
    }
    const double x = PyFloat_AsDouble(obj.ptr());
    if (x == -1.0 && PyErr_Occurred() != nullptr) {
      PyErr_Clear();
      throw py::value_error(where + " must be a number, got " + repr_of(obj));
    }
    value = static_cast<T>(x);
  } else if constexpr (std::is_same_v<T, std::filesystem::path>) {
    value = to_path(obj, where.c_str());
  } else {
    if (!PyUnicode_Check(obj.ptr())) {
      throw py::value_error(where + " must be a str, got " + repr_of(obj));
    }
    value = obj.cast<std::string>();
  }
  if constexpr (core::detail::kNumber<T>) {
    if (!bounds.contains(static_cast<double>(value))) {
      throw py::value_error(where + " must be " + bounds.describe() + ", got " + repr_of(obj));
    }
  }
  return value;
}

// Reads one field by name.
struct Get {
  std::string_view name;
  py::object out;
  template <class T>
  void operator()(const T& value, const core::FieldInfo& info) {
    if (info.name == name) out = to_py(value);
  }
  template <class E, std::size_t N>
  void choice(const E& value, const core::FieldInfo& info, const core::ChoiceNames<E, N>& names) {
    if (info.name == name) out = py::str(std::string(core::choice_name(value, names)));
  }
};

// Sets one field by name; `found` says whether the name is described.
struct Set {
  std::string_view name;
  py::handle value;
  std::string owner;
  bool found = false;
  template <class T>
  void operator()(T& field, const core::FieldInfo& info) {
    if (info.name != name) return;
    found = true;
    field = from_py<T>(value, owner + "." + info.name, info.bounds);
  }
  template <class E, std::size_t N>
  void choice(E& field, const core::FieldInfo& info, const core::ChoiceNames<E, N>& names) {
    if (info.name != name) return;
    found = true;
    const std::string where = owner + "." + info.name;
    if (!PyUnicode_Check(value.ptr())) {
      throw py::value_error(where + " must be one of " + core::choice_list(names) + ", got " +
                            repr_of(value));
    }
    const auto text = value.cast<std::string>();
    for (const auto& [n, v] : names) {
      if (n == text) {
        field = v;
        return;
      }
    }
    throw py::value_error(where + " must be " + core::choice_list(names) + ", got '" + text + "'");
  }
};

// What a description says, for properties and fields(): name, help, type, bounds, default.
struct Field {
  std::string name;
  std::string help;
  std::string type;
  std::string bounds;
  py::object default_value;
};
struct List {
  std::vector<Field> fields;
  template <class T>
  void operator()(const T& value, const core::FieldInfo& info) {
    fields.push_back({info.name, info.help, type_name<T>(), info.bounds.describe(), to_py(value)});
  }
  template <class E, std::size_t N>
  void choice(const E& value, const core::FieldInfo& info, const core::ChoiceNames<E, N>& names) {
    fields.push_back({info.name, info.help, "str", "one of " + core::choice_list(names),
                      py::str(std::string(core::choice_name(value, names)))});
  }
};

template <class S>
std::vector<Field> fields_of(const S& s) {
  List list;
  S::describe(s, list);
  return list.fields;
}

template <class S>
void set_field(S& s, const std::string& key, const py::handle& value, const std::string& owner) {
  Set set{key, value, owner};
  S::describe(s, set);
  if (!set.found) {
    std::string known;
    for (const auto& f : fields_of(s)) known += (known.empty() ? "" : ", ") + f.name;
    throw py::value_error(owner + ": unknown option '" + key + "' (known: " + known + ")");
  }
}

template <class S>
py::dict to_dict(const S& s) {
  py::dict d;
  for (const auto& f : fields_of(s)) {
    Get get{f.name, {}};
    S::describe(s, get);
    d[py::str(f.name)] = get.out;
  }
  return d;
}

template <class S>
void set_from_dict(S& s, const py::dict& d, const std::string& owner) {
  for (const auto& [key, value] : d) set_field(s, py::str(key), value, owner);
}

}  // namespace options_detail

/// Binds S as `name` in `m`: S(**fields), a property per field, repr, ==, to_dict(), from_dict(),
/// fields(), validate() (when S has one) and pickling. Returns the class for more definitions.
template <class S>
py::class_<S> bind_options(py::module_& m, const char* name, const char* doc) {
  namespace d = options_detail;
  const std::string owner = name;
  const auto defaults = d::fields_of(S{});
  std::string full_doc = doc;
  full_doc += "\n\nFields (keyword arguments of the constructor):\n";
  for (const auto& f : defaults) {
    full_doc += "    " + f.name + " (" + f.type + ", default " + d::repr_of(f.default_value) +
                "): " + f.help + (f.bounds.empty() ? "" : "; " + f.bounds) + "\n";
  }
  py::class_<S> cls(m, name, py::is_final());
  cls.attr("__doc__") = full_doc;
  cls.def(py::init([owner](const py::kwargs& kwargs) {
            S s{};
            for (const auto& [key, value] : kwargs) d::set_field(s, py::str(key), value, owner);
            return s;
          }),
          ("Options with the given fields; the others keep their defaults. ValueError for an "
           "unknown name, a wrong type or a value outside the field's bounds."));
  for (const auto& f : defaults) {
    std::string fdoc = f.help + " (" + f.type;
    if (!f.bounds.empty()) fdoc += ", " + f.bounds;
    fdoc += "; default " + d::repr_of(f.default_value) + ")";
    const std::string key = f.name;
    cls.def_property(
        key.c_str(),
        [key](const S& s) {
          d::Get get{key, {}};
          S::describe(s, get);
          return get.out;
        },
        [key, owner](S& s, const py::object& value) { d::set_field(s, key, value, owner); },
        fdoc.c_str());
  }
  cls.def(
      "to_dict", [](const S& s) { return d::to_dict(s); },
      "The fields as a dict (choices by name, paths as str).");
  cls.def_static(
      "from_dict",
      [owner](const py::dict& dict) {
        S s{};
        d::set_from_dict(s, dict, owner);
        return s;
      },
      "Options from a dict of fields (the others keep their defaults).");
  cls.def_static(
      "fields",
      []() {
        py::list out;
        for (const auto& f : d::fields_of(S{})) {
          py::dict e;
          e["name"] = f.name;
          e["help"] = f.help;
          e["type"] = f.type;
          e["bounds"] = f.bounds;
          e["default"] = f.default_value;
          out.append(e);
        }
        return out;
      },
      "The described fields: name, help, type, bounds and default of each, in order.");
  cls.def("__repr__", [owner](const S& s) {
    std::string out = owner + "(";
    bool first = true;
    for (const auto& [key, value] : d::to_dict(s)) {
      if (!first) out += ", ";
      first = false;
      out += std::string(py::str(key)) + "=" + d::repr_of(value);
    }
    return out + ")";
  });
  cls.def("__eq__", [](const S& a, const py::object& b) {
    if (!py::isinstance<S>(b)) return false;
    return d::to_dict(a).equal(d::to_dict(b.cast<const S&>()));
  });
  cls.def("__copy__", [](const S& s) { return S(s); });
  cls.def("__deepcopy__", [](const S& s, const py::dict&) { return S(s); });
  if constexpr (requires(const S& s) { s.validate(); }) {
    cls.def("validate", &S::validate,
            "Raises ValueError naming the first bad option (the library's own check).");
  }
  cls.def(py::pickle([](const S& s) { return d::to_dict(s); },
                     [owner](const py::dict& dict) {
                       S s{};
                       d::set_from_dict(s, dict, owner);
                       return s;
                     }));
  return cls;
}

}  // namespace proprio::python
