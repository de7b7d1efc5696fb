// Recording speed of `proprio sim record` (issue 3: 25 frames/s or more at 640x480 with the
// default look, physics and writing included): records the push scenario several times and
// prints frames/s (wall clock) and where the time went (physics, backdrop video, RGB pass, mask
// pass, PNG writing on the writer thread, setup, finish). On a shared machine the best run is the
// fairest figure; every run is printed. Figures: docs/results/sim-record.md.
//
//   bench_sim_record [--runs N] [--frames N] [--background static|moving] [--shadows]
//                    [--reflections] [--width W] [--height H] [--object NAME]
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <string>

#include "proprio/core/error.hpp"
#include "proprio/sim/recorder.hpp"

namespace {
using namespace proprio;
namespace fs = std::filesystem;

double cpu_seconds() { return static_cast<double>(std::clock()) / CLOCKS_PER_SEC; }

int run(int argc, char** argv) {
  sim::RecordOptions o;
  o.overwrite = true;
  int runs = 3;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw Error(a + " needs a value");
      return argv[++i];
    };
    if (a == "--runs") {
      runs = std::stoi(value());
    } else if (a == "--frames") {
      o.max_frames = std::stoi(value());
    } else if (a == "--background") {
      o.moving_background = value() == "moving";
    } else if (a == "--shadows") {
      o.shadows = true;
    } else if (a == "--reflections") {
      o.reflections = true;
    } else if (a == "--width") {
      o.width = std::stoi(value());
    } else if (a == "--height") {
      o.height = std::stoi(value());
    } else if (a == "--object") {
      o.object = value();
    } else {
      throw Error("unknown argument '" + a + "'");
    }
  }
  const auto catalogue = sim::ObjectCatalogue::load_default();
  const fs::path dir =
      fs::temp_directory_path() / ("proprio_bench_sim_record_" + std::to_string(getpid()));
  std::printf("push of '%s', %dx%d, background %s, shadows %d, reflections %d\n", o.object.c_str(),
              o.width, o.height, o.moving_background ? "moving" : "static", o.shadows ? 1 : 0,
              o.reflections ? 1 : 0);
  std::printf(
      "run frames wall_s fps cpu_s | ms/frame: physics backdrop rgb mask write(thread) wait | "
      "setup_s finish_s\n");
  double best = 0.0;
  for (int r = 0; r < runs; ++r) {
    const double cpu0 = cpu_seconds();
    const sim::RecordSummary s = sim::record_episode(
        dir, o, core::Provenance::current({"bench_sim_record"}, o.seed), catalogue);
    const double cpu = cpu_seconds() - cpu0;
    const auto& t = s.timing;
    const double k = 1000.0 / s.frames;
    std::printf("%d %d %.3f %.2f %.2f | %.2f %.2f %.2f %.2f %.2f %.2f | %.3f %.3f\n", r, s.frames,
                s.seconds, s.fps, cpu, k * t.physics, k * t.backdrop, k * t.render_rgb,
                k * t.render_mask, k * t.write, k * t.write_wait, t.setup, t.finish);
    std::fflush(stdout);
    best = std::max(best, s.fps);
  }
  fs::remove_all(dir);
  std::printf("best fps: %.2f\n", best);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_sim_record: %s\n", e.what());
    return 2;
  }
}
