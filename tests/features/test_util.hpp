#pragma once
// Shared by the features tests: temporary files and the expected-error check.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "../support/temp_dir.hpp"
#include "proprio/core/error.hpp"

namespace proprio::features::test {

/// `name` in a per-process temporary directory, removed when the process exits.
inline std::filesystem::path temp_path(const std::string& name) {
  static const proprio::test::TempDir kDir("proprio_", "features_test");
  return kDir.path() / name;
}

inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

inline void spill(const std::filesystem::path& p, const std::string& bytes) {
  std::ofstream(p, std::ios::binary) << bytes;
}

/// Runs f, expects proprio::Error whose message contains `part`.
template <typename F>
void expect_error(F&& f, const std::string& part) {
  try {
    f();
    ADD_FAILURE() << "no Error; expected one mentioning '" << part << "'";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
  }
}

}  // namespace proprio::features::test
