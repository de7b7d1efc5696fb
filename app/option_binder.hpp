#pragma once
// Registers the fields of a described Options struct (core/fields.hpp) as a command's flags: the
// name, help, default and bounds come from the struct's one description, so an option means the
// same in every command that takes it.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdlib>
#include <initializer_list>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "proprio/core/fields.hpp"

namespace proprio::app {

/// Which of a description's fields a command takes: all but `skip`, or only `only` when given.
struct FieldFilter {
  std::vector<std::string_view> only;
  std::vector<std::string_view> skip;

  [[nodiscard]] bool takes(std::string_view name) const {
    if (std::find(skip.begin(), skip.end(), name) != skip.end()) return false;
    return only.empty() || std::find(only.begin(), only.end(), name) != only.end();
  }
};

namespace detail {

inline std::string flag_of(const core::FieldInfo& info) {
  std::string name = info.flag != nullptr ? info.flag : info.name;
  std::replace(name.begin(), name.end(), '_', '-');
  std::string flags;
  if (info.short_flag != nullptr) {
    flags += '-';
    flags += info.short_flag;
    flags += ',';
  }
  return flags + "--" + name;
}

// A check of the bounds on the option's text, so that the message names the flag and its bounds
// (NaN and infinities are outside every finite bound).
inline CLI::Validator bounds_check(const core::Bounds& bounds) {
  return CLI::Validator(
      [bounds](std::string& text) -> std::string {
        char* end = nullptr;
        const double x = std::strtod(text.c_str(), &end);
        if (end == text.c_str()) return {};  // not a number: the conversion reports it
        if (bounds.contains(x)) return {};
        return "must be " + bounds.describe() + " (it is " + text + ")";
      },
      bounds.describe());
}

template <class E, std::size_t N>
std::string list_of(const core::ChoiceNames<E, N>& names) {
  std::string out;
  for (const auto& [name, v] : names) {
    out += out.empty() ? "" : "|";
    out += name;
  }
  return out;
}

struct Binder {
  CLI::App* cmd;
  const FieldFilter* filter;

  template <class T>
  void operator()(T& value, const core::FieldInfo& info) {
    if (!filter->takes(info.name)) return;
    if constexpr (std::is_same_v<T, bool>) {
      std::string name = info.flag != nullptr ? info.flag : info.name;
      std::replace(name.begin(), name.end(), '_', '-');
      cmd->add_flag("--" + name + ",!--no-" + name, value, info.help)
          ->default_str(value ? "true" : "false");
    } else {
      CLI::Option* o = cmd->add_option(flag_of(info), value, info.help)->capture_default_str();
      if constexpr (std::is_arithmetic_v<T>) {
        if (info.bounds.bounded()) o->check(bounds_check(info.bounds));
      }
    }
  }

  template <class E, std::size_t N>
  void choice(E& value, const core::FieldInfo& info, const core::ChoiceNames<E, N>& names) {
    if (!filter->takes(info.name)) return;
    // Names only (not the enum's numbers), and a message that lists them.
    std::map<std::string, E, std::less<>> table;
    for (const auto& [name, v] : names) table.emplace(std::string(name), v);
    const std::string list = core::choice_list(names);
    const CLI::Validator known(
        [table, list](std::string& text) -> std::string {
          if (table.find(text) != table.end()) return {};
          return "must be " + list + " (it is " + text + ")";
        },
        "");
    cmd->add_option_function<std::string>(
           flag_of(info), [&value, table](const std::string& text) { value = table.at(text); },
           info.help)
        ->check(known)
        ->type_name(list_of(names))
        ->default_str(std::string(core::choice_name(value, names)));
  }
};

}  // namespace detail

/// Adds a flag to `cmd` for each field of `options` that `filter` takes: --name (or the field's
/// own flag), its help, the current value as the default shown, a check of its bounds; a bool
/// field is a pair --name / --no-name; a choice takes its names. `options` must outlive parsing.
template <class S>
void bind_options(CLI::App* cmd, S& options, const FieldFilter& filter = {}) {
  detail::Binder b{cmd, &filter};
  S::describe(options, b);
}

/// One choice flag (an enum with its names table) not part of a described struct.
template <class E, std::size_t N>
void bind_choice(CLI::App* cmd, E& value, const core::FieldInfo& info,
                 const core::ChoiceNames<E, N>& names) {
  const FieldFilter all;
  detail::Binder{cmd, &all}.choice(value, info, names);
}

}  // namespace proprio::app
