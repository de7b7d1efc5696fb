// The evaluation's targets (loop::draw_push_target, PushEvaluationOptions::target_clearance):
// the issue's draw (5-12 cm from the object, inside the scatter region) unchanged by default, and
// with the option only targets where the object's footprint keeps the gap from every other one.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <numbers>
#include <vector>

#include "proprio/core/error.hpp"
#include "proprio/core/random.hpp"
#include "proprio/loop/push_run.hpp"
#include "proprio/sim/simulated_robot.hpp"

namespace proprio::loop {
namespace {

sim::BoxFootprint box(double x, double y, double hx, double hy, double yaw = 0) {
  sim::BoxFootprint b;
  b.centre = {x, y};
  b.half = {hx, hy};
  b.yaw = yaw;
  return b;
}

TEST(PushTargets, FootprintOverlapIsTheLeastPenetrationOfTheBoxesGrownByTheGap) {
  // Two 4 cm squares 2 cm apart along x: clear by 1 cm, not by 3 cm (1 cm short).
  const sim::BoxFootprint a = box(0.0, 0.0, 0.02, 0.02);
  const sim::BoxFootprint b = box(0.06, 0.0, 0.02, 0.02);
  EXPECT_EQ(sim::footprint_overlap(a, b, 0.01), 0.0);
  EXPECT_NEAR(sim::footprint_overlap(a, b, 0.03), 0.01, 1e-12);
  // The same square turned 45 degrees reaches 0.02 * sqrt(2) toward a: 0.0083 m short of 3 cm.
  const sim::BoxFootprint c = box(0.06, 0.0, 0.02, 0.02, std::numbers::pi / 4);
  EXPECT_NEAR(sim::footprint_overlap(a, c, 0.03), 0.03 - (0.04 - 0.02 * std::sqrt(2.0)), 1e-12);
  EXPECT_THROW((void)sim::footprint_overlap(a, b, -0.01), Error);
}

TEST(PushTargets, ByDefaultTheDrawIsTheIssuesFirstInTheScatterRegion) {
  // The draw every figure before the option used: directions and distances from the stream, the
  // first inside the scatter region, whatever lies there.
  const sim::BoxFootprint object = box(0.25, 0.0, 0.03, 0.03);
  const std::vector<sim::BoxFootprint> others{box(0.33, 0.0, 0.03, 0.10)};
  const PushEvaluationOptions options;
  EXPECT_EQ(options.target_clearance, 0.0);  // off by default
  const sim::ScatterRegion scatter;
  for (std::uint64_t seed = 1; seed <= 50; ++seed) {
    auto rng = core::Rng::stream(seed, 7);
    auto same = core::Rng::stream(seed, 7);
    const PushTarget t = draw_push_target(object, others, options, rng);
    Eigen::Vector2d expected = object.centre;
    for (int k = 0; k < 100; ++k) {
      const double a = same.uniform(-std::numbers::pi, std::numbers::pi);
      const double d = same.uniform(options.min_shift, options.max_shift);
      const Eigen::Vector2d c = object.centre + d * Eigen::Vector2d(std::cos(a), std::sin(a));
      if (c.x() >= scatter.min.x() && c.x() <= scatter.max.x() && c.y() >= scatter.min.y() &&
          c.y() <= scatter.max.y() && c.norm() >= scatter.base_clearance) {
        expected = c;
        break;
      }
    }
    EXPECT_EQ(t.point, expected) << seed;
    EXPECT_TRUE(t.clear);
  }
}

TEST(PushTargets, WithAClearanceEveryTargetLeavesTheObjectRoomBesideTheOthers) {
  // A long neighbour 2 cm beyond the object's +x side and a square one below it: by default a
  // good share of the targets put the object on one of them; with 1 cm clearance none does,
  // and each is still 5-12 cm away inside the scatter region.
  const sim::BoxFootprint object = box(0.25, 0.0, 0.03, 0.03, 0.3);
  const std::vector<sim::BoxFootprint> others{box(0.34, 0.0, 0.03, 0.12),
                                              box(0.20, -0.10, 0.04, 0.04, 0.5)};
  const auto blocked = [&](const Eigen::Vector2d& p, double gap) {
    sim::BoxFootprint there = object;
    there.centre = p;
    for (const sim::BoxFootprint& o : others) {
      if (sim::footprint_overlap(there, o, gap) > 0) return true;
    }
    return false;
  };
  PushEvaluationOptions options;
  int blocked_by_default = 0;
  for (std::uint64_t seed = 1; seed <= 100; ++seed) {
    auto rng = core::Rng::stream(seed, 7);
    blocked_by_default += blocked(draw_push_target(object, others, options, rng).point, 0.01);
  }
  EXPECT_GT(blocked_by_default, 20);
  options.target_clearance = 0.01;
  const sim::ScatterRegion scatter;
  for (std::uint64_t seed = 1; seed <= 100; ++seed) {
    auto rng = core::Rng::stream(seed, 7);
    const PushTarget t = draw_push_target(object, others, options, rng);
    EXPECT_TRUE(t.clear) << seed;
    EXPECT_FALSE(blocked(t.point, 0.01)) << seed;
    EXPECT_GE(t.draws, 1);
    const double d = (t.point - object.centre).norm();
    EXPECT_GE(d, options.min_shift - 1e-12);
    EXPECT_LE(d, options.max_shift + 1e-12);
    EXPECT_TRUE(t.point.x() >= scatter.min.x() && t.point.x() <= scatter.max.x() &&
                t.point.y() >= scatter.min.y() && t.point.y() <= scatter.max.y());
  }
  // Deterministic in the stream.
  auto r1 = core::Rng::stream(3, 7);
  auto r2 = core::Rng::stream(3, 7);
  EXPECT_EQ(draw_push_target(object, others, options, r1).point,
            draw_push_target(object, others, options, r2).point);
}

TEST(PushTargets, NoClearPlaceKeepsTheFirstDrawInTheRegionFlagged) {
  // A neighbour covering every place within 12 cm of the object: no clear target.
  const sim::BoxFootprint object = box(0.25, 0.0, 0.03, 0.03);
  const std::vector<sim::BoxFootprint> others{box(0.25, 0.0, 0.20, 0.20)};
  PushEvaluationOptions options;
  options.target_clearance = 0.01;
  auto rng = core::Rng::stream(5, 7);
  auto plain = core::Rng::stream(5, 7);
  const PushTarget t = draw_push_target(object, others, options, rng);
  EXPECT_FALSE(t.clear);
  EXPECT_EQ(t.draws, kClearTargetDraws);
  options.target_clearance = 0;
  EXPECT_EQ(t.point, draw_push_target(object, others, options, plain).point);
}

TEST(PushTargets, TheClosedLoopsDefaultsAreItsOwnNotThePlanners) {
  // The decisions of sessions 28-32 (docs/results/push.md): each a default of the push loop's
  // options (`proprio push`, `proprio evaluate push`), the planner's own default left off.
  struct Default {
    const char* what;
    double planning::PushPlanOptions::*field;
    double loop_constant;
    double value;
  };
  const std::array<Default, 5> defaults{{
      {"depth_split (session 28)", &planning::PushPlanOptions::depth_split, kLoopDepthSplit, 0.01},
      {"free_target_margin (session 28)", &planning::PushPlanOptions::free_target_margin,
       kLoopFreeTargetMargin, 0.01},
      {"correction_hand_margin (session 29)", &planning::PushPlanOptions::correction_hand_margin,
       kLoopCorrectionHandMargin, 0.01},
      {"first_hand_margin (session 30)", &planning::PushPlanOptions::first_hand_margin,
       kLoopFirstHandMargin, 0.01},
      {"tall_start_clearance (session 32)", &planning::PushPlanOptions::tall_start_clearance,
       kLoopTallStartClearance, 0.001},
  }};
  const PushOptions push;
  const PushEvaluationOptions evaluation;
  const planning::PushPlanOptions planner;
  for (const Default& d : defaults) {
    SCOPED_TRACE(d.what);
    EXPECT_EQ(d.loop_constant, d.value);
    EXPECT_EQ(push.plan.*d.field, d.value);
    EXPECT_EQ(evaluation.plan.*d.field, d.value);
    EXPECT_EQ(planner.*d.field, 0.0);
  }
}

TEST(PushTargets, TheClearanceIsBounded) {
  PushEvaluationOptions options;
  options.target_clearance = -0.01;
  EXPECT_THROW(options.validate(), Error);
  options.target_clearance = 0.2;
  EXPECT_THROW(options.validate(), Error);
  options.target_clearance = 0.02;
  EXPECT_NO_THROW(options.validate());
}

}  // namespace
}  // namespace proprio::loop
