// Fuzz target: CSV inputs: arm.csv (the episode's reader, every problem collected) and point
// files (core::parse_csv with exact columns, as geometry's point readers call it).
#include "../../src/episode/parse.hpp"
#include "fuzz_input.hpp"
#include "proprio/core/csv.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace proprio;
  const std::string text(fuzz::as_text(data, size));
  fuzz::expect_error_or_success([&] {
    episode::detail::ProblemSink sink(false, 20);
    int rows = 0;
    (void)episode::detail::parse_arm_csv(text, "arm.csv", std::nullopt, sink, rows);
    (void)sink.take();
  });
  fuzz::expect_error_or_success([&] {
    core::CsvReadOptions o;
    o.exact_columns = {"u1", "v1", "u2", "v2"};
    (void)core::parse_csv(text, "points.csv", o);
  });
  fuzz::expect_error_or_success([&] { (void)core::parse_csv(text, "any.csv", {}); });
  return 0;
}
