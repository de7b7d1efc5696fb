#pragma once
// Validates JSON files against docs/formats/schemas with Debian's python3-jsonschema, which
// scripts/install-deps installs. It runs /usr/bin/python3, not the first python3 on PATH (which
// may be another interpreter without the module); a missing module fails the check, so a schema
// test can never pass by being skipped.

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "paths.hpp"

namespace proprio::test {

/// Exit code of tests/schemas/check_schema.py for `file` against docs/formats/schemas/`schema`:
/// 0 when valid.
inline int check_schema(const std::string& schema, const std::filesystem::path& file) {
  const std::string source = source_dir().string();
  std::string cmd = "/usr/bin/python3 -W ignore " + source + "/tests/schemas/check_schema.py ";
  cmd += source + "/docs/formats/schemas " + schema + " " + file.string();
  const int status = std::system(cmd.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

inline void expect_schema_valid(const std::string& schema, const std::filesystem::path& file) {
  EXPECT_EQ(check_schema(schema, file), 0) << schema << " on " << file;
}

}  // namespace proprio::test
