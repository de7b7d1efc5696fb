// Fuzz target: JSON inputs (episode.json, objects.json, scene JSON): core::parse_json, then the
// episode's readers of the parsed value, then writing it back (non-UTF-8 strings, deep values).
#include "../../src/episode/parse.hpp"
#include "fuzz_input.hpp"
#include "proprio/core/json_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace proprio;
  fuzz::expect_error_or_success([&] {
    const core::Json j = core::parse_json(fuzz::as_text(data, size), "fuzz.json");
    episode::detail::ProblemSink collect(false, 20);
    (void)episode::detail::parse_episode_info(j, "episode.json", collect);
    (void)episode::detail::parse_objects(j, "objects.json", collect);
    episode::detail::ProblemSink first(true, 1);
    (void)episode::detail::parse_objects(j, "objects.json", first);
    (void)j.dump(2, ' ', false, core::Json::error_handler_t::replace);
  });
  return 0;
}
