// Fuzz target: feature files (keypoints and SIFT descriptors). An odd first byte frames the rest
// with a valid header and checksum, so that mutations reach the payload's checks.
#include "fuzz_input.hpp"
#include "proprio/core/binary_file.hpp"
#include "proprio/features/features.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace proprio;
  if (size == 0) return 0;
  const std::string_view rest = fuzz::as_text(data + 1, size - 1);
  const core::BinaryFormat format{"PRFEATS1", features::kFeaturesFormatVersion, "features"};
  const std::string bytes =
      (data[0] & 1) != 0 ? core::frame_binary(format, rest) : std::string(rest);
  const auto path = fuzz::as_file(bytes, ".feat");
  fuzz::expect_error_or_success([&] { (void)features::read_features(path); });
  return 0;
}
