// Fuzz target: the cache of `proprio experiment clutter` as it reads it back
// (loop/clutter_cache.hpp). The input is tried both ways: as a segmented push's views file
// (parse_clutter_views, key kKey and 2 fractions: the seeds carry that key, so mutations get past
// it) and as a trial's manifest (core::parse_json, match_clutter_manifest against kRecording,
// then clutter_manifest_pushes whatever the match says).
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_input.hpp"
#include "proprio/core/json_io.hpp"
#include "proprio/loop/clutter_cache.hpp"

// NOLINTNEXTLINE(readability-identifier-naming): the name libFuzzer calls
extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace proprio;
  static const std::string kKey = R"({"k":1})";
  static const core::Json kRecording{{"seed", 1}, {"pushes", 2}};
  const std::string_view bytes = fuzz::as_text(data, size);
  fuzz::expect_error_or_success([&] {
    const auto views = loop::parse_clutter_views(bytes, kKey, 2);
    if (views && loop::clutter_views_bytes(kKey, *views) != bytes) {
      __builtin_trap();  // a file read back must be the bytes written
    }
  });
  fuzz::expect_error_or_success([&] {
    const core::Json m = core::parse_json(bytes, "clutter_cache.json");
    (void)loop::match_clutter_manifest(m, kRecording);
    (void)loop::clutter_manifest_pushes(m, "clutter_cache.json", 1, "book", 0, "seed_1/book_t1");
  });
  return 0;
}
