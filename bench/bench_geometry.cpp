// Geometry benchmarks: DLT on 100 / 1000 points; our two-view triangulation (linear, and with
// Levenberg-Marquardt refinement) against cv::triangulatePoints on 10,000 points.
// Figures: docs/results/geometry.md.
#include <benchmark/benchmark.h>

#include <Eigen/Geometry>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

#include "proprio/core/random.hpp"
#include "proprio/geometry/dlt.hpp"
#include "proprio/geometry/triangulation.hpp"

namespace {
using namespace proprio;
using geometry::Camera;

Camera look_at(const Eigen::Vector3d& centre, const Eigen::Vector3d& target) {
  Camera c;
  c.K << 800, 0, 319.5, 0, 816, 241, 0, 0, 1;
  const Eigen::Vector3d z = (target - centre).normalized();
  const Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ()).normalized();
  c.R.row(0) = x.transpose();
  c.R.row(1) = z.cross(x).transpose();
  c.R.row(2) = z.transpose();
  c.t = -c.R * centre;
  return c;
}

const Camera kCam1 = look_at({0.1, -1.2, 0.8}, {0.0, 0.2, 0.15});
const Camera kCam2 = look_at({0.5, -1.1, 0.8}, {0.0, 0.2, 0.15});

std::vector<Eigen::Vector3d> workspace(int n, core::Rng& rng) {
  std::vector<Eigen::Vector3d> pts;
  for (int i = 0; i < n; ++i) {
    pts.emplace_back(rng.uniform(-0.3, 0.3), rng.uniform(0.0, 0.5), rng.uniform(0.0, 0.4));
  }
  return pts;
}

Eigen::Vector2d noisy(const Camera& c, const Eigen::Vector3d& X, core::Rng& rng) {
  return c.project(X) + Eigen::Vector2d(rng.normal(0, 0.5), rng.normal(0, 0.5));
}

void BM_Dlt(benchmark::State& state) {
  core::Rng rng(1);
  const auto world = workspace(static_cast<int>(state.range(0)), rng);
  std::vector<Eigen::Vector2d> pixels;
  for (const auto& X : world) pixels.push_back(noisy(kCam1, X, rng));
  double rms = 0.0;
  for (auto _ : state) {
    const auto r = geometry::calibrate_dlt(world, pixels);
    rms = r.rms_px;
    benchmark::DoNotOptimize(r.P.data());
  }
  state.counters["rms_px"] = rms;
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_Dlt)->Arg(100)->Arg(1000)->Unit(benchmark::kMicrosecond);

struct Pairs {
  std::vector<Eigen::Vector2d> x1, x2;
  cv::Mat a, b;
};

Pairs make_pairs(int n) {
  core::Rng rng(2);
  Pairs p;
  p.a.create(2, n, CV_64F);
  p.b.create(2, n, CV_64F);
  int i = 0;
  for (const auto& X : workspace(n, rng)) {
    p.x1.push_back(noisy(kCam1, X, rng));
    p.x2.push_back(noisy(kCam2, X, rng));
    p.a.at<double>(0, i) = p.x1.back().x();
    p.a.at<double>(1, i) = p.x1.back().y();
    p.b.at<double>(0, i) = p.x2.back().x();
    p.b.at<double>(1, i) = p.x2.back().y();
    ++i;
  }
  return p;
}

void BM_TriangulateOurs(benchmark::State& state) {
  const Pairs p = make_pairs(static_cast<int>(state.range(0)));
  geometry::TriangulationOptions o;
  o.refine = state.range(1) != 0;
  const geometry::Matrix34d P1 = kCam1.P(), P2 = kCam2.P();
  double rms = 0.0;
  for (auto _ : state) {
    const auto r = geometry::triangulate(P1, P2, p.x1, p.x2, o);
    rms = r.summary.final_rms_px;
    benchmark::DoNotOptimize(r.points.data());
  }
  state.counters["rms_px"] = rms;
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_TriangulateOurs)
    ->ArgNames({"points", "refine"})
    ->Args({10000, 0})
    ->Args({10000, 1})
    ->Unit(benchmark::kMillisecond);

void BM_TriangulateOpenCV(benchmark::State& state) {
  const Pairs p = make_pairs(static_cast<int>(state.range(0)));
  cv::Mat P1, P2;
  cv::eigen2cv(kCam1.P(), P1);
  cv::eigen2cv(kCam2.P(), P2);
  for (auto _ : state) {
    cv::Mat X4;
    cv::triangulatePoints(P1, P2, p.a, p.b, X4);
    benchmark::DoNotOptimize(X4.data);
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_TriangulateOpenCV)->ArgNames({"points"})->Arg(10000)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
