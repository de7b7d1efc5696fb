// M-L segmentation speed at 640x480 (issue 4: >= 30 frames/s with the translation model, flow
// and over-segmentation included, disk I/O excluded). Frames of one episode are decoded into
// memory first. PROPRIO_BENCH_EPISODE names the episode (default: the thesis-ch5 dataset's
// push_mug_moving_0; BM_MlDepth needs one recorded with `sim record --depth`).
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <filesystem>
#include <opencv2/imgproc.hpp>

#include "proprio/episode/episode.hpp"
#include "proprio/segmentation/ml_segmentation.hpp"
#include "proprio/segmentation/optical_flow.hpp"
#include "proprio/segmentation/region_tracker.hpp"

namespace seg = proprio::segmentation;

namespace {

struct Loaded {
  std::vector<cv::Mat> frames;
  std::vector<std::optional<Eigen::Vector2d>> ee;
  std::vector<bool> touching;
  std::vector<seg::MlSegmenter::DepthFrame> depth;  // when the episode has depth
  std::string error;
};

const Loaded& loaded() {
  static const Loaded l = [] {
    Loaded out;
    const char* env = std::getenv("PROPRIO_BENCH_EPISODE");
    const std::filesystem::path dir = env ? env : "/work/datasets/ch5/push_mug_moving_0";
    try {
      const auto ep = proprio::episode::read_episode(dir);
      for (int i = 0; i < ep.frame_count(); ++i) {
        out.frames.push_back(ep.frame(i));
        out.ee.push_back(ep.ee_image(i));
        out.touching.push_back(ep.arm()[i].touching);
        if (ep.info().has_depth) {
          seg::MlSegmenter::DepthFrame d;
          d.depth = ep.depth(i);
          d.intrinsics = ep.camera().K;
          d.ee_camera = 1000.0 * (ep.camera().R * ep.arm()[i].ee + ep.camera().t);
          d.up = ep.camera().R.col(2);  // as segment_ml: the table cut (table_clearance) runs
          out.depth.push_back(d);
        }
      }
    } catch (const std::exception& e) {
      out.error = e.what();
    }
    return out;
  }();
  return l;
}

bool skip_without_frames(benchmark::State& state) {
  if (loaded().frames.empty()) {
    state.SkipWithError(("no episode: " + loaded().error).c_str());
    return true;
  }
  return false;
}

void run_ml(benchmark::State& state, seg::MlOptions o) {
  if (skip_without_frames(state)) return;
  const auto& l = loaded();
  if (o.use_depth && l.depth.empty()) {
    state.SkipWithError("the episode has no depth (record it with sim record --depth)");
    return;
  }
  o.keep_frame_labels = false;
  seg::MlSummary s;
  for (auto _ : state) {
    seg::MlSegmenter m(o, l.frames[0].size());
    for (size_t i = 0; i < l.frames.size(); ++i) {
      auto out = m.push(l.frames[i], l.ee[i], l.touching[i], o.use_depth ? &l.depth[i] : nullptr);
      benchmark::DoNotOptimize(out.map.data);
    }
    s = m.summary();
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(l.frames.size()));
  state.counters["ms_regions"] = s.mean_ms_regions;
  state.counters["ms_flow"] = s.mean_ms_flow;
  state.counters["ms_model"] = s.mean_ms_model;
  state.counters["ms_total"] = s.mean_ms_total;
  state.counters["frames_per_s"] = 1000.0 / s.mean_ms_total;
}

void BM_MlTranslationDefault(benchmark::State& state) { run_ml(state, seg::MlOptions{}); }
BENCHMARK(BM_MlTranslationDefault)->Unit(benchmark::kMillisecond)->Iterations(1);

// The default without the first-touch pixels carried along the flow (MlOptions::carried_pixels,
// on by default since session 22): what carrying them (and their forward-backward check) costs.
void BM_MlNoCarriedPixels(benchmark::State& state) {
  seg::MlOptions o;
  o.carried_pixels = false;
  run_ml(state, o);
}
BENCHMARK(BM_MlNoCarriedPixels)->Unit(benchmark::kMillisecond)->Iterations(1);

// The baseline's touch cut as evidence (MlOptions::touch_fm): a colour frame kept per frame
// before the touch and one Fitzpatrick & Metta cut at it.
void BM_MlTouchFm(benchmark::State& state) {
  seg::MlOptions o;
  o.touch_fm = 1.0;
  run_ml(state, o);
}
BENCHMARK(BM_MlTouchFm)->Unit(benchmark::kMillisecond)->Iterations(1);

// Arm removal per pixel at the touch (MlOptions::pixel_arm_removal): one grey-level difference
// a frame before the touch, a Sobel at the touch, one warp and two box filters after it.
void BM_MlPixelArmRemoval(benchmark::State& state) {
  seg::MlOptions o;
  o.pixel_arm_removal = true;
  run_ml(state, o);
}
BENCHMARK(BM_MlPixelArmRemoval)->Unit(benchmark::kMillisecond)->Iterations(1);

void BM_MlTranslationHalfScale(benchmark::State& state) {
  seg::MlOptions o;
  o.scale = 0.5;
  run_ml(state, o);
}
BENCHMARK(BM_MlTranslationHalfScale)->Unit(benchmark::kMillisecond)->Iterations(1);

void BM_MlHomography(benchmark::State& state) {
  seg::MlOptions o;
  o.model = seg::MotionModel::kHomography;
  run_ml(state, o);
}
BENCHMARK(BM_MlHomography)->Unit(benchmark::kMillisecond)->Iterations(1);

// The depth variant (thesis 9.2; issue 20: >= 20 frames/s): needs an episode with depth.
void BM_MlDepth(benchmark::State& state) {
  seg::MlOptions o;
  o.use_depth = true;
  run_ml(state, o);
}
BENCHMARK(BM_MlDepth)->Unit(benchmark::kMillisecond)->Iterations(1);

// The same without the table cut (MlOptions::table_clearance = 0): what the cut costs.
void BM_MlDepthNoTableCut(benchmark::State& state) {
  seg::MlOptions o;
  o.use_depth = true;
  o.table_clearance = 0;
  run_ml(state, o);
}
BENCHMARK(BM_MlDepthNoTableCut)->Unit(benchmark::kMillisecond)->Iterations(1);

// Stages alone, one 640x480 frame pair.
void BM_Flow(benchmark::State& state) {
  if (skip_without_frames(state)) return;
  const auto& l = loaded();
  cv::Mat1b a, b;
  cv::cvtColor(l.frames[40 % l.frames.size()], a, cv::COLOR_BGR2GRAY);
  cv::cvtColor(l.frames[41 % l.frames.size()], b, cv::COLOR_BGR2GRAY);
  seg::DenseFlow flow(static_cast<seg::FlowMethod>(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(flow.compute(b, a).data);
}
BENCHMARK(BM_Flow)
    ->ArgName("method")  // 0 DIS ultrafast, 1 DIS fast, 2 DIS medium, 3 Farneback, 4 LK grid
    ->DenseRange(0, 4)
    ->Unit(benchmark::kMillisecond);

void BM_OverSegmentation(benchmark::State& state) {
  if (skip_without_frames(state)) return;
  const auto& l = loaded();
  const cv::Mat& f = l.frames[40 % l.frames.size()];
  seg::OverSegmenter s(static_cast<seg::OverSegmentation>(state.range(0)), 400, 2, f.size());
  int count = 0;
  for (auto _ : state) benchmark::DoNotOptimize(s.segment(f, count).data);
  state.counters["regions"] = count;
}
BENCHMARK(BM_OverSegmentation)
    ->ArgName("method")  // 0 SEEDS, 1 SLIC, 2 mean shift
    ->DenseRange(0, 2)
    ->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
