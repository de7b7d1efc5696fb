// Fuzz target: decisions.jsonl of a learn or selfsupervise run (one JSON object a line), read as
// `proprio report` reads it: loop::count_learn_decisions.
#include "fuzz_input.hpp"
#include "proprio/loop/learn_report.hpp"

// NOLINTNEXTLINE(readability-identifier-naming): the name libFuzzer calls
extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace proprio;
  const auto file = fuzz::as_file(fuzz::as_text(data, size), ".jsonl");
  fuzz::expect_error_or_success([&] { (void)loop::count_learn_decisions(file); });
  return 0;
}
