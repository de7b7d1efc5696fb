// Fuzz target: vocabulary files (the binary frame of core/binary_file and the words' payload). An
// odd first byte frames the rest with a valid header and checksum, so that mutations reach the
// payload's checks instead of all stopping at the checksum.
#include "fuzz_input.hpp"
#include "proprio/core/binary_file.hpp"
#include "proprio/features/vocabulary.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace proprio;
  if (size == 0) return 0;
  const std::string_view rest = fuzz::as_text(data + 1, size - 1);
  const core::BinaryFormat format{"PRVOCAB1", features::kVocabularyFormatVersion, "vocabulary"};
  const std::string bytes =
      (data[0] & 1) != 0 ? core::frame_binary(format, rest) : std::string(rest);
  const auto path = fuzz::as_file(bytes, ".vocab");
  fuzz::expect_error_or_success([&] { (void)features::read_vocabulary(path); });
  return 0;
}
