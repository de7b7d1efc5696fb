// Fuzz target: image files as proprio reads them (geometry::read_image): the header checks of
// core/image_header, then OpenCV's codecs (libpng, libjpeg) on what passes them. A crash inside a
// codec that no check before it can avoid is a finding to report, not to hide.
#include "fuzz_input.hpp"
#include "proprio/core/image_header.hpp"
#include "proprio/geometry/image_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace proprio;
  const std::string_view bytes = fuzz::as_text(data, size);
  fuzz::expect_error_or_success([&] {
    const core::ImageHeader h = core::parse_image_header(bytes, "fuzz.img");
    // Decode only small images: a valid 100-megapixel header costs the codec 300 MB per input,
    // which is the header check's job to allow, not the fuzzer's to repeat.
    if (h.pixels() > 1'000'000) return;
    const auto path = fuzz::as_file(bytes, ".img");
    (void)geometry::read_image(path, cv::IMREAD_UNCHANGED);
  });
  return 0;
}
