#pragma once
// Errors caused by input from outside the program (files, command lines, user data), and the
// internal errors that are not: a broken invariant of proprio's own is InternalError (or an
// assert), never proprio::Error, so that the CLI reports a bug as a bug (exit 1), not as bad
// input (exit 2).

#include <filesystem>
#include <stdexcept>
#include <string>

namespace proprio {

/// Bad input from outside. The message names the file (and line) and the problem, in the form
/// "FILE:LINE: problem" or "FILE: problem", so that the CLI can print it as one line.
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}

  /// "FILE: problem".
  static Error in_file(const std::filesystem::path& file, const std::string& problem);
  /// "FILE:LINE: problem" (line counts from 1).
  static Error at_line(const std::filesystem::path& file, long line, const std::string& problem);
};

/// Throws Error(message) unless condition holds. For checks of outside input only.
inline void require(bool condition, const std::string& message) {
  if (!condition) throw Error(message);
}

/// A broken internal invariant: a bug in proprio, whatever the input. The CLI prints it as an
/// internal error and exits 1. Used where a check must stay in release builds (an assert would
/// vanish) and the caller may recover (a library user can catch it).
class InternalError : public std::logic_error {
 public:
  explicit InternalError(const std::string& message) : std::logic_error(message) {}
};

/// Throws InternalError(message) unless condition holds. For proprio's own invariants only.
inline void ensure(bool condition, const std::string& message) {
  if (!condition) throw InternalError(message);
}

}  // namespace proprio
