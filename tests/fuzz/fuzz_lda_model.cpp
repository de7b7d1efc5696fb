// Fuzz target: LDA model files (the binary frame of core/binary_file and topics' payload). An odd
// first byte frames the rest with a valid header and checksum, so that mutations reach the
// payload's checks instead of all stopping at the checksum; its second bit picks the version
// framed (1, or 2 with word weights).
#include "fuzz_input.hpp"
#include "proprio/core/binary_file.hpp"
#include "proprio/topics/lda_model_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace proprio;
  if (size == 0) return 0;
  const std::string_view rest = fuzz::as_text(data + 1, size - 1);
  const core::BinaryFormat format{
      "PRLDAMDL", (data[0] & 2) != 0 ? topics::kLdaModelFormatVersion : 1U, "LDA model"};
  const std::string bytes =
      (data[0] & 1) != 0 ? core::frame_binary(format, rest) : std::string(rest);
  fuzz::expect_error_or_success([&] { (void)topics::parse_lda_model(bytes, "fuzz.lda"); });
  return 0;
}
