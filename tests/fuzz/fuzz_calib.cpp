// Fuzz target: calib.yml (OpenCV FileStorage YAML behind geometry::read_calib).
#include "fuzz_input.hpp"
#include "proprio/geometry/camera.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace proprio;
  const auto file = fuzz::as_file(fuzz::as_text(data, size), ".yml");
  fuzz::expect_error_or_success([&] { (void)geometry::read_calib(file); });
  return 0;
}
