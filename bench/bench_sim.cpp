// Simulation benchmarks at 640x480 on the default scene with the ten catalogue objects and the
// arm sweeping over the table: one video frame = 1/30 s of physics + an RGB render + the id-mask
// render (+ optionally writing both as PNG), with shadows and reflections on or off; and the
// parts alone. Software GL renders on worker threads: times and rates are wall-clock.
// Figures: docs/results/sim.md. MUJOCO_GL=egl|osmesa picks the GL backend.
#include <benchmark/benchmark.h>

#include <unistd.h>
#include <filesystem>
#include <memory>
#include <opencv2/imgcodecs.hpp>

#include "proprio/sim/renderer.hpp"
#include "proprio/sim/world.hpp"

namespace {
using namespace proprio;
using sim::World;

constexpr double kFrameSeconds = 1.0 / 30.0;

// CPU time of the whole process (every thread: software GL rasterises on worker threads), ms. On
// a shared machine this, unlike wall-clock time, does not depend on what else runs.
double process_cpu_ms() { return 1000.0 * static_cast<double>(std::clock()) / CLOCKS_PER_SEC; }

void report_cpu(benchmark::State& state, double cpu_start_ms) {
  state.counters["cpu_ms"] = benchmark::Counter((process_cpu_ms() - cpu_start_ms) /
                                                static_cast<double>(state.iterations()));
}

World make_world() {
  sim::SceneDescription d = sim::default_scene();
  struct Place {
    const char* type;
    double x, y, yaw;
  };
  const Place places[] = {{"book", 0.25, -0.25, 0.2},      {"mug", 0.50, -0.25, 1.0},
                          {"bottle", 0.70, -0.22, 0.0},    {"spirit-level", 0.45, -0.03, 0.1},
                          {"rabbit", 0.72, 0.0, -1.3},     {"cd", 0.18, 0.05, 0.5},
                          {"calculator", 0.72, 0.2, -0.3}, {"giraffe", 0.48, 0.18, -1.2},
                          {"bike", 0.25, 0.3, 0.3},        {"box", 0.70, 0.40, 0.6}};
  for (const Place& p : places) {
    sim::PlacedObject o;
    o.type = p.type;
    o.position = {p.x, p.y};
    o.yaw = p.yaw;
    d.objects.push_back(o);
  }
  return World::build(d, sim::ObjectCatalogue::load_default());
}

// Arm targets for time t: j1 sweeps back and forth above the objects.
robot::JointVector arm_at(double t) {
  robot::JointVector q;
  q << 0.8 * std::sin(t), 0.9, -1.2, -0.9, 0.0;
  return q;
}

void advance_one_frame(World& w) {
  w.set_arm_targets(arm_at(w.time()));
  w.step(static_cast<int>(std::lround(kFrameSeconds / w.timestep())));
}

// Args: shadows, reflections, write PNGs.
void BM_Frame(benchmark::State& state) {
  World w = make_world();
  sim::RenderOptions options;
  options.shadows = state.range(0) != 0;
  options.reflections = state.range(1) != 0;
  const bool write_png = state.range(2) != 0;
  sim::Renderer r(w, options);
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("proprio_bench_sim_" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  (void)r.render(w, "camera");  // first frame compiles shaders
  const double cpu_start = process_cpu_ms();
  for (auto _ : state) {
    advance_one_frame(w);
    const sim::Frame f = r.render(w, "camera", sim::kPassRgb | sim::kPassMask);
    if (write_png) {
      cv::imwrite((dir / "rgb.png").string(), f.rgb);
      cv::imwrite((dir / "mask.png").string(), f.mask);
    }
    benchmark::DoNotOptimize(f.rgb.data);
  }
  report_cpu(state, cpu_start);
  std::filesystem::remove_all(dir);
  state.SetItemsProcessed(state.iterations());
  state.SetLabel(sim::to_string(r.backend()));
}
BENCHMARK(BM_Frame)
    ->ArgNames({"shadows", "reflections", "png"})
    ->Args({1, 1, 0})
    ->Args({1, 1, 1})
    ->Args({1, 0, 0})
    ->Args({0, 1, 0})
    ->Args({0, 0, 0})
    ->Args({0, 0, 1})
    ->Unit(benchmark::kMillisecond)
    ->MinTime(3.0)
    ->UseRealTime();

// One pass alone: 0 = RGB, 1 = id mask, 2 = RGB + depth. Shadows and reflections on.
void BM_Pass(benchmark::State& state) {
  World w = make_world();
  sim::Renderer r(w);
  const unsigned passes[] = {sim::kPassRgb, sim::kPassMask, sim::kPassRgb | sim::kPassDepth};
  const unsigned pass = passes[state.range(0)];
  (void)r.render(w, "camera", pass);
  const double cpu_start = process_cpu_ms();
  for (auto _ : state) benchmark::DoNotOptimize(r.render(w, "camera", pass).rgb.data);
  report_cpu(state, cpu_start);
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_Pass)
    ->ArgName("pass")
    ->DenseRange(0, 2)
    ->Unit(benchmark::kMillisecond)
    ->MinTime(2.0)
    ->UseRealTime();

void BM_PhysicsFrame(benchmark::State& state) {
  World w = make_world();
  for (auto _ : state) advance_one_frame(w);
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_PhysicsFrame)->Unit(benchmark::kMillisecond)->UseRealTime();

// A moving background: a new video frame into the backdrop texture (512x288) and to the GPU.
void BM_BackdropVideoFrame(benchmark::State& state) {
  World w = make_world();
  sim::Renderer r(w);
  const cv::Mat frame = sim::read_image(sim::ObjectCatalogue::default_texture_dir() / "aero3.jpg");
  for (auto _ : state) {
    w.set_texture_image(sim::kBackdropTexture, frame);
    r.upload_texture(w, sim::kBackdropTexture);
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_BackdropVideoFrame)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_BuildWorld(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(make_world().time());
}
BENCHMARK(BM_BuildWorld)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
