// Fuzz target: Mixture of Topics model files (the binary frame of core/binary_file and the MoT
// payload, docs/formats/mot-model.md). An odd first byte frames the rest with a valid header and
// checksum (the current version 3; with the second bit set version 1, with the third version 2),
// so that mutations reach the payload's checks instead of all stopping at the checksum.
#include "fuzz_input.hpp"
#include "proprio/core/binary_file.hpp"
#include "proprio/topics/mot_model_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace proprio;
  if (size == 0) return 0;
  const std::string_view rest = fuzz::as_text(data + 1, size - 1);
  const std::uint32_t version = (data[0] & 2) != 0   ? 1
                                : (data[0] & 4) != 0 ? 2
                                                     : topics::kMotModelFormatVersion;
  const core::BinaryFormat format{"PRMOTMDL", version, "Mixture of Topics model"};
  const std::string bytes =
      (data[0] & 1) != 0 ? core::frame_binary(format, rest) : std::string(rest);
  fuzz::expect_error_or_success([&] { (void)topics::parse_mot_model(bytes, "fuzz.mot"); });
  return 0;
}
