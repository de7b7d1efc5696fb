#pragma once
// Where a test finds the source tree and the built CLI: relative to the test program itself, by
// paths that CMake works out from the build layout (the same in every clone). No absolute path of
// the tree is compiled in, so that a fresh clone in another folder reuses ccache's objects.
// PROPRIO_TEST_SOURCE_FROM_BIN and PROPRIO_TEST_CLI_FROM_BIN are set by proprio_test()
// (cmake/ProprioHelpers.cmake).

#include <unistd.h>

#include <filesystem>
#include <string>

namespace proprio::test {

/// The directory of the running test program.
inline std::filesystem::path program_dir() {
  return std::filesystem::read_symlink("/proc/self/exe").parent_path();
}

/// The source tree's root (where data/, docs/ and tests/ are).
inline std::filesystem::path source_dir() {
  static const std::filesystem::path dir =
      std::filesystem::weakly_canonical(program_dir() / PROPRIO_TEST_SOURCE_FROM_BIN);
  return dir;
}

/// The source tree's data/ directory.
inline std::filesystem::path data_dir() { return source_dir() / "data"; }

/// The built `proprio` CLI.
inline std::string cli_path() {
  static const std::string path =
      std::filesystem::weakly_canonical(program_dir() / PROPRIO_TEST_CLI_FROM_BIN).string();
  return path;
}

}  // namespace proprio::test
