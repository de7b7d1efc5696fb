#pragma once
// Errors caused by input from outside the program (files, command lines, user data).
// Programming errors are asserts, not proprio::Error.

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

}  // namespace proprio
