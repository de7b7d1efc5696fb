// Fuzz target: corpora and vocabularies (topics/corpus_io). The first byte picks the format:
// UCI docword, LDA-C, MatrixMarket, or a vocabulary file; the rest is the file.
#include "fuzz_input.hpp"
#include "proprio/topics/corpus_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace proprio;
  if (size == 0) return 0;
  const int kind = data[0] % 4;
  const auto file = fuzz::as_file(fuzz::as_text(data + 1, size - 1), ".txt");
  fuzz::expect_error_or_success([&] {
    switch (kind) {
      case 0:
        (void)topics::read_uci(file, {});
        break;
      case 1:
        (void)topics::read_ldac(file, {});
        break;
      case 2:
        (void)topics::read_matrix_market(file, {});
        break;
      default:
        (void)topics::read_vocabulary(file);
        break;
    }
  });
  return 0;
}
