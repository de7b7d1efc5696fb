// Timings of the push planner (docs/results/push.md; target: a plan in under 20 ms): the view
// of a 640 x 480 image's features (density through the FFT, blobs, back-projection) and one plan
// (sampled paths, their cost integrals, reachability and the chosen motion's check).

#include <benchmark/benchmark.h>

#include <algorithm>
#include <vector>

#include "../tests/support/table_views.hpp"
#include "proprio/core/data_dir.hpp"
#include "proprio/planning/push_planner.hpp"

namespace {

using namespace proprio;

// Five 6-8 cm objects as squares of grid features, like the dense features of a table.
std::vector<cv::KeyPoint> table_features(const geometry::Camera& cam) {
  std::vector<cv::KeyPoint> f;
  for (const Eigen::Vector3d& o : std::vector<Eigen::Vector3d>{{0.20, 0.10, 0.04},
                                                               {0.32, -0.12, 0.03},
                                                               {0.15, -0.18, 0.035},
                                                               {0.35, 0.15, 0.04},
                                                               {0.28, 0.0, 0.03}}) {
    test::add_feature_square(f, cam, o.head<2>(), o.z());
  }
  return f;
}

const robot::Arm& arm() {
  static const robot::Arm a =
      robot::Arm::load(core::data_directory() / "models" / "arm_standalone.xml");
  return a;
}

void BM_PlanningView(benchmark::State& state) {
  const geometry::Camera cam = test::down_camera();
  const auto f = table_features(cam);
  planning::PushPlanOptions o;
  o.centre_height = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(planning::make_planning_view(f, cam, {}, o));
  }
}
BENCHMARK(BM_PlanningView)->Unit(benchmark::kMillisecond);

void BM_PlanPush(benchmark::State& state) {
  const geometry::Camera cam = test::down_camera();
  planning::PushPlanOptions o;
  o.centre_height = 0;
  const planning::PlanningView view = planning::make_planning_view(table_features(cam), cam, {}, o);
  robot::ArmState s(arm());
  const auto goal = static_cast<planning::PushGoal>(state.range(0));
  for (auto _ : state) {
    const planning::PushPlan p =
        planning::plan_push(view, 0, goal, {0.26, 0.16}, {}, s, robot::JointVector::Zero(), o);
    if (p.outcome != planning::PlanOutcome::kPlanned) state.SkipWithError(p.message.c_str());
  }
}
BENCHMARK(BM_PlanPush)->Arg(0)->Arg(1)->ArgNames({"edge"})->Unit(benchmark::kMillisecond);

// The closed loop's look after a push: the pushed object found from the motion between two
// 640 x 480 looks (motion image, moving features' blobs, the whole blob when alone).
void BM_FindPushedObject(benchmark::State& state) {
  const geometry::Camera cam = test::down_camera();
  planning::PushPlanOptions o;
  o.centre_height = 0;
  cv::Mat before(480, 640, CV_8UC3, cv::Scalar(128, 128, 128));
  cv::Mat after = before.clone();
  test::draw_checkered_square(before, cam, {0.20, 0.06}, 0.03);
  test::draw_checkered_square(after, cam, {0.20, -0.005}, 0.03);
  for (cv::Mat* m : {&before, &after}) {
    test::draw_checkered_square(*m, cam, {0.20, -0.07}, 0.03);
    test::draw_checkered_square(*m, cam, {0.35, 0.15}, 0.04);
  }
  const planning::PlanningView v0 =
      planning::make_planning_view(planning::textured_points(before, o), cam, {}, o);
  const planning::PlanningView v1 =
      planning::make_planning_view(planning::textured_points(after, o), cam, {}, o);
  const Eigen::Vector2d was(0.20, 0.06);
  const auto& pushed =
      *std::min_element(v0.objects.begin(), v0.objects.end(), [&](const auto& a, const auto& b) {
        return (a.centre - was).norm() < (b.centre - was).norm();
      });
  for (auto _ : state) {
    planning::PlanningView v = v1;
    const int k = planning::find_pushed_object(before, after, v, pushed, {0.20, 0.0}, 0.08, {}, o);
    if (k < 0) state.SkipWithError("not found");
  }
}
BENCHMARK(BM_FindPushedObject)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
