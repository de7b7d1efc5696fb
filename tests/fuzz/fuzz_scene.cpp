// Fuzz target: YAML scene files (yaml-cpp behind sim::read_scene_file).
#include "fuzz_input.hpp"
#include "proprio/sim/scene_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace proprio;
  const auto file = fuzz::as_file(fuzz::as_text(data, size), ".yaml");
  fuzz::expect_error_or_success([&] {
    const core::Json j = sim::read_scene_file(file);
    (void)j.dump();
  });
  return 0;
}
