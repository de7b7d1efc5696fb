// Timings of the interception planner (docs/results/interception.md): learning the target's
// transition and filtering, one plan (sparse sample + Gauss-Newton, target < 10 ms), one
// trajectory's energy and precision, and whole simulated trials.

#include <benchmark/benchmark.h>

#include <memory>
#include <vector>

#include "proprio/core/data_dir.hpp"
#include "proprio/planning/interception_trial.hpp"

namespace {

using namespace proprio::planning;

const proprio::robot::Arm& arm() {
  static const proprio::robot::Arm a =
      proprio::robot::Arm::load(proprio::core::data_directory() / "models" / "intercept.xml");
  return a;
}

// The full 252-trajectory grid; the precision uses few samples here, which changes the costs'
// values a little but not the planner's work.
const std::shared_ptr<const GridCostModel>& model() {
  static const std::shared_ptr<const GridCostModel> m = [] {
    GridCostOptions o;
    o.precision_samples = 6;
    return std::make_shared<const GridCostModel>(compute_grid_costs(arm(), o));
  }();
  return m;
}

const InterceptionSimulator& simulator() {
  static const InterceptionSimulator s(arm(), model(), default_stereo_rig());
  return s;
}

// 20 stereo measurements of 16 random targets (as the experiment draws them) at `noise_cm`.
std::vector<std::vector<PositionMeasurement>> measurements(double noise_cm) {
  std::vector<std::vector<PositionMeasurement>> out;
  TrialOptions o;
  const double px = simulator().pixel_noise_for(noise_cm);
  proprio::core::Rng rng(1);
  for (int k = 0; k < 16; ++k) {
    const TargetMotion t =
        random_target(model()->grid(), simulator().plan_time(o), o.scenario, rng);
    std::vector<PositionMeasurement> ms;
    for (int i = 0; i < o.observe_frames; ++i) {
      const double time = i * 0.04;
      const auto m = measure(simulator().rig(), t.position(time), px, rng);
      ms.push_back({time, m->position, m->covariance});
    }
    out.push_back(ms);
  }
  return out;
}

void BM_FilterLearnAndTrack(benchmark::State& state) {
  const auto data = measurements(state.range(0) / 10.0);
  FilterOptions o;
  o.transition = state.range(1) ? TransitionModel::kConstantVelocity : TransitionModel::kLearned;
  std::size_t k = 0;
  for (auto _ : state) {
    TargetFilter f(data[k++ % data.size()], o);
    benchmark::DoNotOptimize(f.estimate().mean);
  }
}
BENCHMARK(BM_FilterLearnAndTrack)->ArgsProduct({{0, 15}, {0, 1}})->ArgNames({"noise_mm", "cv"});

void BM_PlanInterception(benchmark::State& state) {
  const auto data = measurements(state.range(0) / 10.0);
  FilterOptions fo;
  fo.transition = state.range(1) ? TransitionModel::kConstantVelocity : TransitionModel::kLearned;
  std::vector<TargetFilter> filters;
  for (const auto& d : data) filters.emplace_back(d, fo);
  PlannerOptions po;
  po.time_quantum = 0.002;
  std::size_t k = 0;
  int iterations = 0, evaluations = 0;
  for (auto _ : state) {
    const TargetFilter& f = filters[k++ % filters.size()];
    const InterceptionPlan p = plan_interception(f, *model(), f.estimate().t, po);
    iterations += p.summary.iterations;
    evaluations += p.summary.evaluations;
    benchmark::DoNotOptimize(p.psi);
  }
  state.counters["gn_iterations"] =
      benchmark::Counter(iterations, benchmark::Counter::kAvgIterations);
  state.counters["evaluations"] =
      benchmark::Counter(evaluations, benchmark::Counter::kAvgIterations);
}
BENCHMARK(BM_PlanInterception)
    ->ArgsProduct({{0, 15, 30}, {0, 1}})
    ->ArgNames({"noise_mm", "cv"})
    ->Unit(benchmark::kMillisecond);

void BM_TrajectoryCosts(benchmark::State& state) {
  GridCostOptions o;
  o.grid.theta = {0.3, 0.3, 1};
  o.grid.length = {0.14, 0.14, 1};
  o.grid.gamma = {0.0, 0.0, 1};
  o.precision_samples = static_cast<int>(state.range(0));
  o.threads = 1;
  for (auto _ : state) benchmark::DoNotOptimize(compute_grid_costs(arm(), o).points[0].rho);
}
BENCHMARK(BM_TrajectoryCosts)->Arg(20)->ArgName("samples")->Unit(benchmark::kMillisecond);

void BM_Trial(benchmark::State& state) {
  TrialOptions o;
  o.noise_cm = 1.0;
  o.replan = state.range(0) != 0;
  o.filter.transition = TransitionModel::kConstantVelocity;
  proprio::core::Rng rng(2);
  std::uint64_t seed = 1;
  for (auto _ : state) {
    const TargetMotion t =
        random_target(model()->grid(), simulator().plan_time(o), o.scenario, rng);
    benchmark::DoNotOptimize(simulator().run(t, o, seed++).miss);
  }
}
BENCHMARK(BM_Trial)->Arg(0)->Arg(1)->ArgName("replan")->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
