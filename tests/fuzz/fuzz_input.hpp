#pragma once
// Shared by the fuzz targets: the input as text, and as a file for the readers that take a path
// (their checks of size, type and extension are part of what is fuzzed).

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

#include "proprio/core/error.hpp"

namespace proprio::fuzz {

inline std::string_view as_text(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

/// Writes the input to a file of this process (in /dev/shm when there is one: no disk traffic),
/// named with `extension`, and returns its path. The same file is reused for every input.
inline std::filesystem::path as_file(std::string_view bytes, const std::string& extension) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path dir =
      fs::is_directory("/dev/shm", ec) ? fs::path("/dev/shm") : fs::temp_directory_path();
  const fs::path p = dir / ("proprio_fuzz_" + std::to_string(::getpid()) + extension);
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  return p;
}

/// Runs `f`; bad input must end in proprio::Error, anything else escapes and is a finding.
template <typename F>
void expect_error_or_success(F&& f) {
  try {
    f();
  } catch (const proprio::Error&) {
    // the documented answer to bad input
  }
}

}  // namespace proprio::fuzz
