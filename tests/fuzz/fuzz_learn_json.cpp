// Fuzz target: learn.json of a learn run, read as `proprio report` reads it (every member typed
// and bounded, every path inside the run directory): loop::learn_report_inputs.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "fuzz_input.hpp"
#include "proprio/loop/learn_report.hpp"

// NOLINTNEXTLINE(readability-identifier-naming): the name libFuzzer calls
extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace proprio;
  namespace fs = std::filesystem;
  static const fs::path kDir = [] {
    std::error_code ec;
    const fs::path base =
        fs::is_directory("/dev/shm", ec) ? fs::path("/dev/shm") : fs::temp_directory_path();
    fs::path d = base / ("proprio_fuzz_run_" + std::to_string(::getpid()));
    fs::create_directories(d, ec);
    return d;
  }();
  {
    std::ofstream out(kDir / "learn.json", std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  fuzz::expect_error_or_success([&] { (void)loop::learn_report_inputs(kDir); });
  return 0;
}
