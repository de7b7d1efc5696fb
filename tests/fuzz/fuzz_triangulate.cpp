// Fuzz target: the whole `proprio calib triangulate` path (geometry::run_calib_triangulate): two
// calib.yml files and a point CSV u1,v1,u2,v2, cut from one input at the lines "---8<---"
// (absent parts are empty files), read, checked against each other, triangulated and written.
#include <string>
#include <string_view>

#include "fuzz_input.hpp"
#include "proprio/core/provenance.hpp"
#include "proprio/geometry/calib_runs.hpp"

// NOLINTNEXTLINE(readability-identifier-naming): the name libFuzzer calls
extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace proprio;
  constexpr std::string_view kCut = "\n---8<---\n";
  std::string_view text = fuzz::as_text(data, size);
  std::string_view parts[3];
  for (int i = 0; i < 3; ++i) {
    const auto at = i < 2 ? text.find(kCut) : std::string_view::npos;
    parts[i] = text.substr(0, at);
    text = at == std::string_view::npos ? std::string_view() : text.substr(at + kCut.size());
  }
  geometry::CalibTriangulateOptions o;
  o.calib1 = fuzz::as_file(parts[0], "_1.yml");
  o.calib2 = fuzz::as_file(parts[1], "_2.yml");
  o.points = fuzz::as_file(parts[2], "_points.csv");
  o.out = fuzz::as_file("", "_out.csv");
  o.refine = size % 2 == 1;  // the input's length picks the Levenberg-Marquardt refinement
  static const core::Provenance kProvenance = core::Provenance::current({"fuzz_triangulate"}, 1);
  fuzz::expect_error_or_success([&] { (void)geometry::run_calib_triangulate(o, kProvenance); });
  return 0;
}
