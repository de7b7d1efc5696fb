// The push planner (thesis 7.2.1) on synthetic views: a camera looking straight down on the
// table, square patches of features as objects, the standalone arm for reachability.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <opencv2/imgproc.hpp>
#include <optional>

#include "../support/box_depth.hpp"
#include "../support/paths.hpp"
#include "../support/table_views.hpp"
#include "proprio/core/error.hpp"
#include "proprio/planning/push_planner.hpp"

namespace proprio::planning {
namespace {

using test::add_feature_square;
using test::down_camera;  // tests/support/table_views.hpp
using test::draw_checkered_square;

const robot::Arm& arm() {
  static const robot::Arm kArm =
      robot::Arm::load(test::data_dir() / "models" / "arm_standalone.xml");
  return kArm;
}

PushPlanOptions flat_options() {
  PushPlanOptions o;
  o.centre_height = 0.0;  // the squares lie on the table
  return o;
}

// A 2 cm square object at (0.20, 0) and a 1.5 cm square neighbour at `neighbour`, seen from above.
PlanningView object_and_neighbour(const geometry::Camera& cam, const Eigen::Vector2d& neighbour) {
  std::vector<cv::KeyPoint> f;
  add_feature_square(f, cam, {0.20, 0.0}, 0.02);
  add_feature_square(f, cam, neighbour, 0.015);
  return make_planning_view(f, cam, {}, flat_options());
}

// The index of the view's object nearest `p`.
int object_nearest(const PlanningView& view, const Eigen::Vector2d& p) {
  int best = -1;
  for (int i = 0; i < static_cast<int>(view.objects.size()); ++i) {
    const auto d = [&](int k) {
      return (view.objects[static_cast<std::size_t>(k)].centre - p).norm();
    };
    if (best < 0 || d(i) < d(best)) best = i;
  }
  return best;
}

// The scene of the sweep, waypoint and hand tests: the object at (0.20, 0) and a neighbour at
// `neighbour` (object_and_neighbour) seen by the down camera, the arm at rest, and the object's
// target 16 cm along +y. Check view.objects.size() before obj() and other().
struct NeighbourScene {
  explicit NeighbourScene(const Eigen::Vector2d& neighbour)
      : view(object_and_neighbour(cam, neighbour)), a(object_nearest(view, {0.20, 0.0})) {}
  PutativeObject& obj() { return view.objects.at(static_cast<std::size_t>(a)); }
  PutativeObject& other() { return view.objects.at(static_cast<std::size_t>(1 - a)); }
  // A plan of object `index` of `v` (this scene's object by default) toward the target.
  PushPlan plan(const PushPlanOptions& o) { return plan(o, view, a); }
  PushPlan plan(const PushPlanOptions& o, const PlanningView& v, int index) {
    return plan_push(v, index, PushGoal::kTarget, target, {}, state, q0, o);
  }

  geometry::Camera cam = down_camera();
  PlanningView view;
  int a = -1;
  robot::ArmState state{arm()};
  robot::JointVector q0 = robot::JointVector::Zero();
  Eigen::Vector2d target{0.20, 0.16};
};

// The pushed object 20 cm tall (a bottle), the neighbour low (1 cm) and out of the way at
// (0.32, -0.10): the scene of the tests of an arm that comes down on the object it pushes.
struct TallObjectScene : NeighbourScene {
  TallObjectScene() : NeighbourScene({0.32, -0.10}) {
    if (view.objects.size() != 2) return;  // each test asserts the size first
    obj().height = 0.20;
    other().height = 0.01;
  }
};

TEST(PushGeometry, DistanceToHullEdgeIsTheExactIntersection) {
  const std::vector<Eigen::Vector2d> square{{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
  EXPECT_NEAR(distance_to_hull_edge(square, {0, 0}, {1, 0}), 1.0, 1e-12);
  EXPECT_NEAR(distance_to_hull_edge(square, {0.5, 0}, {-1, 0}), 1.5, 1e-12);
  const Eigen::Vector2d diag = Eigen::Vector2d(1, 1).normalized();
  EXPECT_NEAR(distance_to_hull_edge(square, {0, 0}, diag), std::sqrt(2.0), 1e-12);
  EXPECT_EQ(distance_to_hull_edge(square, {3, 0}, {1, 0}), 0.0);  // outside
  // Clockwise hulls too.
  const std::vector<Eigen::Vector2d> cw{{-1, 1}, {1, 1}, {1, -1}, {-1, -1}};
  EXPECT_NEAR(distance_to_hull_edge(cw, {0, 0}, {0, 1}), 1.0, 1e-12);
}

TEST(PushGeometry, StartIsBehindTheObjectAndTheCentreEndsOverTheTarget) {
  const std::vector<Eigen::Vector2d> square{
      {0.18, -0.02}, {0.22, -0.02}, {0.22, 0.02}, {0.18, 0.02}};
  const Eigen::Vector2d c(0.2, 0.0);
  const Eigen::Vector2d t(0.2, 0.1);  // push along +y
  const robot::TablePush p = push_through_centre(square, c, t, 0.03, 0.008, 0.05);
  // n = (p_t - p_s) / |p_t - p_s| points from the start to the target (the sign SPEC §5 fixes).
  EXPECT_NEAR(p.start.x(), 0.2, 1e-12);
  EXPECT_NEAR(p.start.y(), -0.05, 1e-12);  // 2 cm to the edge + 3 cm approach, behind
  EXPECT_NEAR(p.end.y(), 0.08, 1e-12);     // the back edge where the centre is over the target
  const Eigen::Vector2d n = (t - p.start).normalized();
  EXPECT_NEAR(n.y(), 1.0, 1e-12);
  EXPECT_THROW((void)push_through_centre(square, c, c, 0.03, 0.008, 0.05), Error);
  // A pusher of 8 mm radius meets the edge with its side: it stops 8 mm short, from the same start.
  const robot::TablePush r = push_through_centre(square, c, t, 0.03, 0.008, 0.05, 0.008);
  EXPECT_NEAR(r.start.y(), -0.05, 1e-12);
  EXPECT_NEAR(r.end.y(), 0.072, 1e-12);
  EXPECT_NEAR(r.end.x(), 0.2, 1e-12);
}

TEST(PushPlanner, PushesEndShortByThePushersRadius) {
  const geometry::Camera cam = down_camera();
  std::vector<cv::KeyPoint> f;
  add_feature_square(f, cam, {0.28, 0.0}, 0.03);
  const PlanningView view = make_planning_view(f, cam, {}, flat_options());
  ASSERT_EQ(view.objects.size(), 1U);
  robot::ArmState state(arm());
  const robot::JointVector q0 = robot::JointVector::Zero();
  PushPlanOptions o = flat_options();
  o.target_spread = 0;
  const Eigen::Vector2d target(0.22, 0.0);
  const PushPlan axis = plan_push(view, 0, PushGoal::kTarget, target, {}, state, q0, o);
  o.pusher_radius = 0.008;
  const PushPlan side = plan_push(view, 0, PushGoal::kTarget, target, {}, state, q0, o);
  ASSERT_EQ(axis.outcome, PlanOutcome::kPlanned) << axis.message;
  ASSERT_EQ(side.outcome, PlanOutcome::kPlanned) << side.message;
  // The same path (same seed, same sampling), 8 mm shorter.
  EXPECT_NEAR((axis.push.start - side.push.start).norm(), 0.0, 1e-12);
  EXPECT_NEAR((axis.push.end - side.push.end).norm(), 0.008, 1e-9);
  EXPECT_NEAR(axis.push.length() - side.push.length(), 0.008, 1e-9);
}

// Every point's patch lies inside the image, odd patches too (an odd patch reaches one column
// further right than left: the old bounds let its last patch read past the integral image).
TEST(PushPlanner, TexturedPointsKeepTheirPatchesInsideTheImage) {
  cv::Mat1b img(10, 10);
  for (int y = 0; y < img.rows; ++y) {
    for (int x = 0; x < img.cols; ++x) img(y, x) = static_cast<uchar>(((x + y) % 2) * 200);
  }
  PushPlanOptions o;
  o.grid_step = 1;
  o.min_contrast = 1;
  for (const int patch : {4, 5}) {
    o.patch = patch;
    const std::vector<cv::KeyPoint> points = textured_points(img, o);
    // Points x = y = patch / 2 .. 10 - patch + patch / 2: 7 a side for 4 (2..8), 6 for 5 (2..7).
    const int side = 10 - patch + 1;
    EXPECT_EQ(points.size(), static_cast<std::size_t>(side * side)) << "patch " << patch;
    const int half = patch / 2;  // a patch spans [x - half, x - half + patch)
    for (const cv::KeyPoint& k : points) {
      const int x = static_cast<int>(k.pt.x);
      const int y = static_cast<int>(k.pt.y);
      EXPECT_GE(std::min(x, y) - half, 0);
      EXPECT_LE(std::max(x, y) - half + patch, 10) << "patch " << patch;
    }
  }
}

TEST(PushPlanner, FindsTheObjectsAndTheirCentres) {
  const geometry::Camera cam = down_camera();
  std::vector<cv::KeyPoint> f;
  add_feature_square(f, cam, {0.20, 0.10}, 0.04);
  add_feature_square(f, cam, {0.30, -0.12}, 0.03);
  const PlanningView view = make_planning_view(f, cam, {}, flat_options());
  ASSERT_EQ(view.objects.size(), 2U);
  EXPECT_LT((view.objects[0].centre - Eigen::Vector2d(0.20, 0.10)).norm(), 0.005);
  EXPECT_LT((view.objects[1].centre - Eigen::Vector2d(0.30, -0.12)).norm(), 0.005);
  EXPECT_GE(view.objects[0].hull.size(), 4U);
}

TEST(PushPlanner, PathCostCountsOtherObjectsOnTheWayOnly) {
  const geometry::Camera cam = down_camera();
  std::vector<cv::KeyPoint> f;
  add_feature_square(f, cam, {0.20, 0.0}, 0.03);
  add_feature_square(f, cam, {0.30, 0.0}, 0.03);  // in the way along +x
  const PlanningView view = make_planning_view(f, cam, {}, flat_options());
  ASSERT_EQ(view.objects.size(), 2U);
  const auto& o = view.objects[0].centre.x() < 0.25 ? view.objects[0] : view.objects[1];
  const auto through = push_through_centre(o.hull, o.centre, {0.36, 0.0}, 0.03, 0.008, 0.05);
  const auto aside = push_through_centre(o.hull, o.centre, {0.20, 0.16}, 0.03, 0.008, 0.05);
  const cv::Mat1f others = density_of_others(view, view.objects[0].centre.x() < 0.25 ? 0 : 1);
  const double c_through =
      path_cost(others, cam, through, o.hull, o.centre, {0.36, 0.0}, 0.0, 0.005);
  const double c_aside = path_cost(others, cam, aside, o.hull, o.centre, {0.20, 0.16}, 0.0, 0.005);
  EXPECT_GT(c_through, 0.2);          // 6 cm of the obstacle, ~6 features per px of density
  EXPECT_LT(c_aside, c_through / 3);  // only the tail of its own density past the blob
}

TEST(PushPlanner, PlansAroundAnObstacleAndRejectsWhatItCannotDo) {
  const geometry::Camera cam = down_camera();
  std::vector<cv::KeyPoint> f;
  add_feature_square(f, cam, {0.20, 0.05}, 0.03);
  add_feature_square(f, cam, {0.30, 0.05}, 0.03);
  const PlanningView view = make_planning_view(f, cam, {}, flat_options());
  ASSERT_EQ(view.objects.size(), 2U);
  const int a = view.objects[0].centre.x() < 0.25 ? 0 : 1;
  robot::ArmState state(arm());
  const robot::JointVector q0 = robot::JointVector::Zero();
  const TableRegion region;

  // To the edge of the view: the planner takes a path away from the obstacle at +x.
  PushPlan p = plan_push(view, a, PushGoal::kEdge, {0, 0}, region, state, q0, flat_options());
  ASSERT_EQ(p.outcome, PlanOutcome::kPlanned) << p.message;
  EXPECT_TRUE(p.push.start.allFinite() && p.push.end.allFinite());
  EXPECT_LT(p.direction.x(), 0.9);  // not straight into the obstacle
  EXPECT_GE(p.seconds, 0.0);        // recorded; its speed is bench/'s to measure

  // A given target: the centre ends over it, the start is behind on the line.
  const Eigen::Vector2d target(0.22, -0.08);
  p = plan_push(view, a, PushGoal::kTarget, target, region, state, q0, flat_options());
  ASSERT_EQ(p.outcome, PlanOutcome::kPlanned) << p.message;
  EXPECT_LT((p.target - target).norm(), flat_options().target_spread + 1e-9);
  const Eigen::Vector2d n = (p.target - p.push.start).normalized();
  EXPECT_NEAR(n.dot(p.direction), 1.0, 1e-9);

  EXPECT_EQ(
      plan_push(view, a, PushGoal::kTarget, {2.0, 0.0}, region, state, q0, flat_options()).outcome,
      PlanOutcome::kTargetOffTable);
  EXPECT_EQ(
      plan_push(view, a, PushGoal::kTarget, {0.70, 0.0}, region, state, q0, flat_options()).outcome,
      PlanOutcome::kUnreachable);
  EXPECT_EQ(
      plan_push(view, 7, PushGoal::kTarget, target, region, state, q0, flat_options()).outcome,
      PlanOutcome::kUnknownObject);
  EXPECT_EQ(plan_push(view, a, PushGoal::kTarget, view.objects[static_cast<std::size_t>(a)].centre,
                      region, state, q0, flat_options())
                .outcome,
            PlanOutcome::kAtTarget);
  const PlanningView empty = make_planning_view({}, cam, {}, flat_options());
  // Depth of another type or size than the camera's image: an Error naming it.
  for (const cv::Mat& depth :
       {cv::Mat(480, 640, CV_16UC1, cv::Scalar(0)), cv::Mat(240, 320, CV_32FC1, cv::Scalar(0))}) {
    try {
      (void)make_planning_view({}, cam, {}, flat_options(), depth);
      ADD_FAILURE() << "bad depth taken";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("depth image must be CV_32FC1"), std::string::npos)
          << e.what();
    }
  }
  EXPECT_EQ(
      plan_push(empty, 0, PushGoal::kTarget, target, region, state, q0, flat_options()).outcome,
      PlanOutcome::kNoObjects);
  EXPECT_THROW((void)plan_push(view, a, PushGoal::kTarget, {std::nan(""), 0.0}, region, state, q0,
                               flat_options()),
               Error);
  PushPlanOptions bad = flat_options();
  bad.min_approach = 0.1;
  bad.max_approach = 0.05;
  EXPECT_THROW(bad.validate(), Error);
}

TEST(PushGeometry, PolygonDistanceAndPathClearance) {
  const std::vector<Eigen::Vector2d> a{{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  const std::vector<Eigen::Vector2d> b{{2, 0}, {3, 0}, {3, 1}, {2, 1}};
  EXPECT_NEAR(polygon_distance(a, b), 1.0, 1e-12);
  EXPECT_EQ(polygon_distance(a, {{0.5, 0.5}}), 0.0);                   // a point inside
  EXPECT_NEAR(polygon_distance(a, {{0.5, 3}, {0.5, 2}}), 1.0, 1e-12);  // a segment above
  EXPECT_EQ(polygon_distance(a, {{-1, 0.5}, {2, 0.5}}), 0.0);          // a segment across
  // A square pushed along +x toward another: the corridor meets it; pushed along +y it does not.
  const std::vector<Eigen::Vector2d> sq{{-0.02, -0.02}, {0.02, -0.02}, {0.02, 0.02}, {-0.02, 0.02}};
  const std::vector<std::vector<Eigen::Vector2d>> others{
      {{0.08, -0.02}, {0.12, -0.02}, {0.12, 0.02}, {0.08, 0.02}}};
  const Eigen::Vector2d c(0, 0);
  const auto into = push_through_centre(sq, c, {0.10, 0}, 0.03, 0.008, 0.05);
  const auto aside = push_through_centre(sq, c, {0, 0.10}, 0.03, 0.008, 0.05);
  EXPECT_GT(path_clearance(into, sq, c, {0.10, 0}, others, 0.01, 0.02), 0.02);
  EXPECT_EQ(path_clearance(aside, sq, c, {0, 0.10}, others, 0.01, 0.02), 0.0);
  EXPECT_EQ(path_clearance(into, sq, c, {0.10, 0}, others, 0.0, 0.0), 0.0);  // not checked
}

std::vector<Eigen::Vector2d> box(double x0, double y0, double x1, double y1) {
  return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
}

TEST(PushGeometry, SweepLackCountsTheSweptRegionsShortfallOfTheMargin) {
  // A 2 cm square at the origin pushed 10 cm along +x, a 1 cm margin.
  const auto sq = box(-0.01, -0.01, 0.01, 0.01);
  const Eigen::Vector2d c(0, 0);
  const Eigen::Vector2d t(0.10, 0);
  const double m = 0.01;
  // A neighbour on the line: run into, at least the margin.
  EXPECT_GE(sweep_lack(sq, c, t, {box(0.05, -0.01, 0.07, 0.01)}, m), m);
  // 3 cm beside the line: clear.
  EXPECT_EQ(sweep_lack(sq, c, t, {box(0.04, 0.04, 0.06, 0.06)}, m), 0.0);
  // Its lower edge 2 cm off the line: the swept region reaches 1.0-1.23 cm (the square turned
  // 15 degrees at the end reaches 1 cm x (cos 15 + sin 15)), so the gap is 7.7-10 mm; the lack is
  // the margin less the gap.
  const double lack = sweep_lack(sq, c, t, {box(0.04, 0.02, 0.06, 0.04)}, m);
  EXPECT_GT(lack, 0.0);
  EXPECT_LT(lack, 0.0025);
  // Touching already before the push: nothing to keep clear of; no margin: not checked.
  EXPECT_EQ(sweep_lack(sq, c, t, {box(-0.01, 0.01, 0.01, 0.03)}, m), 0.0);
  EXPECT_EQ(sweep_lack(sq, c, t, {box(0.05, -0.01, 0.07, 0.01)}, 0.0), 0.0);
  // The turn allowance: a long thin object (8 x 1 cm) pushed along its length. A neighbour beside
  // the end, 1.5 cm off the corridor without the turn, is within the margin of the object turned
  // by 15 degrees (its front corner 1.52 cm off the line); the corridor without turn
  // (path_clearance) does not see it.
  const auto rod = box(-0.04, -0.005, 0.04, 0.005);
  const std::vector<std::vector<Eigen::Vector2d>> beside{box(0.12, 0.02, 0.14, 0.04)};
  EXPECT_GT(sweep_lack(rod, c, t, beside, m), 0.004);
  const auto push = push_through_centre(rod, c, t, 0.03, 0.008, 0.05);
  EXPECT_EQ(path_clearance(push, rod, c, t, beside, m, 0.0), 0.0);
  // The region holds the object at the start and turned at the end.
  const auto region = sweep_region(rod, c, t);
  EXPECT_EQ(polygon_distance(region, {{-0.04, 0.0}}), 0.0);
  EXPECT_EQ(polygon_distance(region, {{0.135, 0.013}}), 0.0);
  EXPECT_GT(polygon_distance(region, {{0.0, 0.012}}), 0.0);  // not the whole turn along the way
}

TEST(PushGeometry, TheTurnAllowanceGoesByTheFootprintsShape) {
  // A square and a 4 x 3 cm rectangle are box-like; a disc (pi / 4 of its square), a rod
  // (8 x 1 cm) and a triangle (half its rectangle) are not; too few points: the full turn.
  EXPECT_EQ(sweep_turn(box(-0.01, -0.01, 0.01, 0.01)), kBoxTurn);
  EXPECT_EQ(sweep_turn(box(-0.02, -0.015, 0.02, 0.015)), kBoxTurn);
  std::vector<Eigen::Vector2d> disc;
  for (int k = 0; k < 32; ++k) {
    const double a = 2 * std::numbers::pi * k / 32;
    disc.emplace_back(0.03 * std::cos(a), 0.03 * std::sin(a));
  }
  EXPECT_EQ(sweep_turn(disc), kSweepTurn);
  EXPECT_EQ(sweep_turn(box(-0.04, -0.005, 0.04, 0.005)), kSweepTurn);
  EXPECT_EQ(sweep_turn({{0, 0}, {0.04, 0}, {0, 0.04}}), kSweepTurn);
  EXPECT_EQ(sweep_turn({{0, 0}, {0.04, 0}}), kSweepTurn);
  // A box's smaller turn sweeps less: the neighbour 2 cm off the line is 7.7-10 mm from the
  // square turned 15 degrees at the end, farther from it turned 3 degrees, 1 cm from it unturned.
  const auto sq = box(-0.01, -0.01, 0.01, 0.01);
  const std::vector<std::vector<Eigen::Vector2d>> off{box(0.04, 0.02, 0.06, 0.04)};
  const double full = sweep_lack(sq, {0, 0}, {0.10, 0}, off, 0.01);
  const double little = sweep_lack(sq, {0, 0}, {0.10, 0}, off, 0.01, false, kBoxTurn);
  EXPECT_GT(full, 0.001);
  EXPECT_LT(full, 0.0025);
  EXPECT_LT(little, full - 0.0008);
  EXPECT_NEAR(sweep_lack(sq, {0, 0}, {0.10, 0}, off, 0.01, false, 0.0), 0.0, 1e-9);  // no turn
}

TEST(PushGeometry, SweepLackCountsATouchingNeighbourOnlyWhenThePushGoesTowardIt) {
  // A 2 cm square at the origin, a 1 cm margin, neighbours touching it (or overlapping it by
  // 3 mm, as measured footprints do).
  const auto sq = box(-0.01, -0.01, 0.01, 0.01);
  const Eigen::Vector2d c(0, 0);
  const double m = 0.01;
  const std::vector<std::vector<Eigen::Vector2d>> ahead{box(0.01, -0.01, 0.03, 0.01)};
  const std::vector<std::vector<Eigen::Vector2d>> overlapping{box(0.007, -0.01, 0.027, 0.01)};
  const std::vector<std::vector<Eigen::Vector2d>> beside{box(-0.01, 0.007, 0.01, 0.027)};
  const Eigen::Vector2d toward(0.10, 0);
  // Off (the default): a touching neighbour counts nothing, whichever way the push goes.
  EXPECT_EQ(sweep_lack(sq, c, toward, ahead, m), 0.0);
  // On: pushed toward it, the margin; the overlapping one too.
  EXPECT_DOUBLE_EQ(sweep_lack(sq, c, toward, ahead, m, true), m);
  EXPECT_DOUBLE_EQ(sweep_lack(sq, c, toward, overlapping, m, true), m);
  // Pushed away from it, or along the side they touch at: nothing.
  EXPECT_EQ(sweep_lack(sq, c, {-0.10, 0}, ahead, m, true), 0.0);
  EXPECT_EQ(sweep_lack(sq, c, toward, beside, m, true), 0.0);
  // Pushed toward the one beside (+y): the margin; no margin: nothing.
  EXPECT_DOUBLE_EQ(sweep_lack(sq, c, {0, 0.10}, beside, m, true), m);
  EXPECT_EQ(sweep_lack(sq, c, toward, ahead, 0.0, true), 0.0);
}

TEST(PushPlanner, StopsShortWhereThePushedObjectsSweptRegionWouldMeetANeighbour) {
  // The object at (0.20, 0), its target 16 cm along +y, a neighbour 12 cm along the line: the
  // object at its target would lie on the neighbour, so no way round helps. With sweep_margin the
  // planner pushes it along the line only as far as its swept region keeps the margin from the
  // neighbour; without, it pushes it to the target (through the neighbour).
  NeighbourScene s({0.20, 0.12});
  ASSERT_EQ(s.view.objects.size(), 2U);
  const auto& obj = s.obj();
  const auto& other = s.other();
  const Eigen::Vector2d target = s.target;
  PushPlanOptions o = flat_options();
  o.sweep_margin = 0.01;
  const PushPlan p = s.plan(o);
  ASSERT_EQ(p.outcome, PlanOutcome::kPlanned) << p.message;
  EXPECT_EQ(p.blocked, 0.0);
  EXPECT_GT(p.shortened, 0.04);
  EXPECT_NE(p.message.find("short"), std::string::npos) << p.message;
  // The swept region keeps the margin from the neighbour's hull, and the object still goes
  // most of the way there (its front 1 cm + the turn allowance short of the margin).
  EXPECT_GE(polygon_distance(sweep_region(obj.hull, obj.centre, p.target), other.hull),
            o.sweep_margin - 1e-6);
  EXPECT_GT((p.target - obj.centre).norm(), 0.06);
  // On the line to the target (within target_spread's turn of it).
  const Eigen::Vector2d n = (p.target - obj.centre).normalized();
  EXPECT_GT(n.dot((target - obj.centre).normalized()), 0.99);
  // Without the margin: straight to the target, not shortened.
  o.sweep_margin = 0;
  const PushPlan direct = s.plan(o);
  ASSERT_EQ(direct.outcome, PlanOutcome::kPlanned) << direct.message;
  EXPECT_EQ(direct.shortened, 0.0);
  EXPECT_LT((direct.target - target).norm(), o.target_spread + 1e-9);
  EXPECT_EQ(polygon_distance(sweep_region(obj.hull, obj.centre, direct.target), other.hull), 0.0);
  // A neighbour beside the line, clear of the swept region: the margin changes nothing.
  std::vector<cv::KeyPoint> g;
  add_feature_square(g, s.cam, {0.20, 0.0}, 0.02);
  add_feature_square(g, s.cam, {0.30, 0.08}, 0.015);
  const PlanningView clear = make_planning_view(g, s.cam, {}, flat_options());
  ASSERT_EQ(clear.objects.size(), 2U);
  const int b = clear.objects[0].centre.x() < 0.25 ? 0 : 1;
  o.sweep_margin = 0.01;
  const PushPlan aside = s.plan(o, clear, b);
  ASSERT_EQ(aside.outcome, PlanOutcome::kPlanned) << aside.message;
  EXPECT_EQ(aside.shortened, 0.0);
  EXPECT_EQ(aside.blocked, 0.0);
  EXPECT_LT((aside.target - target).norm(), o.target_spread + 1e-9);
  // Bounds.
  PushPlanOptions bad = flat_options();
  bad.sweep_margin = -0.001;
  EXPECT_THROW(bad.validate(), Error);
  bad.sweep_margin = 0.06;
  EXPECT_THROW(bad.validate(), Error);
}

TEST(PushGeometry, DescentBlockedByTheObjectUnderTheForearmOrANeighbourBesideTheHand) {
  // The robot's base at the origin, an object 4 cm square at (0.25, 0). Pushed toward the base
  // the hand comes down beyond it and the forearm hangs over it (the robot refuses: session 15,
  // selfsupervise seed 1); pushed sideways it does not.
  const std::vector<Eigen::Vector2d> sq{{0.23, -0.02}, {0.27, -0.02}, {0.27, 0.02}, {0.23, 0.02}};
  EXPECT_TRUE(descent_blocked({0.30, 0.0}, sq, {}, 0.04));
  EXPECT_FALSE(descent_blocked({0.25, -0.05}, sq, {}, 0.04));
  // A neighbour 2 cm from the hand's way down: blocked with 4 cm, not with 1 cm.
  const std::vector<std::vector<Eigen::Vector2d>> others{
      {{0.23, -0.11}, {0.27, -0.11}, {0.27, -0.07}, {0.23, -0.07}}};
  EXPECT_TRUE(descent_blocked({0.25, -0.05}, sq, others, 0.04));
  EXPECT_FALSE(descent_blocked({0.25, -0.05}, sq, others, 0.01));
  // A start nearer the base than kForearmReach: the forearm is the segment to the base.
  EXPECT_TRUE(
      descent_blocked({0.10, 0.0}, {}, {{{0.03, -0.01}, {0.05, -0.01}, {0.05, 0.01}}}, 0.01));
}

TEST(PushPlanner, DescentClearanceLeavesOutPushesTheArmWouldComeDownOn) {
  // The object at (0.25, 0) pushed toward the base, to (0.17, 0): every path starts beyond it,
  // the forearm over it. With descent_clearance none is planned; without, one is.
  const geometry::Camera cam = down_camera();
  std::vector<cv::KeyPoint> f;
  add_feature_square(f, cam, {0.25, 0.0}, 0.02);
  const PlanningView view = make_planning_view(f, cam, {}, flat_options());
  ASSERT_EQ(view.objects.size(), 1U);
  robot::ArmState state(arm());
  const robot::JointVector q0 = robot::JointVector::Zero();
  PushPlanOptions o = flat_options();
  const PushPlan free = plan_push(view, 0, PushGoal::kTarget, {0.17, 0.0}, {}, state, q0, o);
  ASSERT_EQ(free.outcome, PlanOutcome::kPlanned) << free.message;
  EXPECT_GT(free.push.start.x(), 0.25);
  o.descent_clearance = 0.04;
  const PushPlan checked = plan_push(view, 0, PushGoal::kTarget, {0.17, 0.0}, {}, state, q0, o);
  EXPECT_EQ(checked.outcome, PlanOutcome::kUnreachable) << checked.message;
  // Sideways it is planned.
  const PushPlan aside = plan_push(view, 0, PushGoal::kTarget, {0.25, 0.08}, {}, state, q0, o);
  EXPECT_EQ(aside.outcome, PlanOutcome::kPlanned) << aside.message;
}

TEST(PushPlanner, DescentPosesLeaveOutPushesWhoseArmComesDownOnAMeasuredObject) {
  // The object at (0.20, 0) pushed 16 cm along +y: the pusher starts behind it, 5.5-6 cm from
  // its edge (y near -0.08), and a neighbour stands 2.5-3 cm beyond the start (y from -0.105).
  // 20 cm tall (a bottle), the arm coming down to any such start meets it; 1 cm tall (a CD), the
  // hand passes over it. No depth image: the map is the hulls raised to their heights.
  NeighbourScene s({0.20, -0.12});
  ASSERT_EQ(s.view.objects.size(), 2U);
  s.obj().height = 0.01;
  s.other().height = 0.20;
  const auto meets = [&](const robot::TablePush& p) {
    return descent_meets_object(s.state, p, s.q0, descent_map(s.view, {}), 0.005, false);
  };
  PushPlanOptions o = flat_options();
  o.min_approach = 0.055;
  o.max_approach = 0.06;
  const PushPlan free = s.plan(o);
  ASSERT_EQ(free.outcome, PlanOutcome::kPlanned) << free.message;
  EXPECT_TRUE(meets(free.push).has_value());
  EXPECT_EQ(free.rejected_descent, 0);
  o.descent_pose_margin = 0.005;
  const PushPlan checked = s.plan(o);
  EXPECT_EQ(checked.outcome, PlanOutcome::kUnreachable) << checked.message;
  EXPECT_GT(checked.rejected_descent, 0);
  EXPECT_NE(checked.message.find("way down"), std::string::npos) << checked.message;
  EXPECT_FALSE(checked.descent_met);
  // descent_pose_fallback: every descent meets the neighbour, so the best path is pushed anyway
  // (the one taken without the check), flagged.
  o.descent_pose_fallback = true;
  const PushPlan fallback = s.plan(o);
  ASSERT_EQ(fallback.outcome, PlanOutcome::kPlanned) << fallback.message;
  EXPECT_TRUE(fallback.descent_met);
  EXPECT_GT(fallback.rejected_descent, 0);
  EXPECT_EQ(fallback.push.start, free.push.start);
  EXPECT_NE(fallback.message.find("way down meets"), std::string::npos) << fallback.message;
  o.descent_pose_fallback = false;
  // The usual approach (2-6 cm): a start nearer the object, clear of the neighbour, is planned.
  o.min_approach = flat_options().min_approach;
  o.max_approach = flat_options().max_approach;
  const PushPlan near = s.plan(o);
  ASSERT_EQ(near.outcome, PlanOutcome::kPlanned) << near.message;
  EXPECT_FALSE(near.descent_met);
  o.descent_pose_fallback = true;  // a clear descent exists: the fallback changes nothing
  const PushPlan near_fallback = s.plan(o);
  EXPECT_EQ(near_fallback.push.start, near.push.start);
  EXPECT_FALSE(near_fallback.descent_met);
  o.descent_pose_fallback = false;
  EXPECT_FALSE(meets(near.push).has_value()) << *meets(near.push);
  // A 1 cm neighbour does not block the far starts.
  s.other().height = 0.01;
  EXPECT_FALSE(meets(free.push).has_value()) << *meets(free.push);
  o.min_approach = 0.055;
  o.max_approach = 0.06;
  EXPECT_EQ(s.plan(o).outcome, PlanOutcome::kPlanned);
  // A margin larger than the pusher's lowest point above the table (tip 8 mm): the bare table
  // under the pusher is not an object, so a start far from both is clear; the tall neighbour
  // still blocks the far start.
  const auto meets_wide = [&](const robot::TablePush& p) {
    return descent_meets_object(s.state, p, s.q0, descent_map(s.view, {}), 0.012, false);
  };
  robot::TablePush away = free.push;  // 10 cm and more from both objects
  away.start = {0.30, 0.10};
  away.end = {0.30, 0.16};
  ASSERT_LT(away.height, 0.012);  // the pusher's tip, its lowest point, is within the margin
  EXPECT_FALSE(meets_wide(away).has_value()) << *meets_wide(away);
  s.other().height = 0.20;
  EXPECT_TRUE(meets_wide(free.push).has_value());
  s.other().height = 0.01;
  // Unknown height (no depth): tall.
  s.other().height = std::nullopt;
  EXPECT_TRUE(meets(free.push).has_value());
  // The pushed object itself, 20 cm tall, with the pusher 2 cm behind it: the hand above the
  // pusher comes down on it.
  s.other().height = 0.01;
  s.obj().height = 0.20;
  robot::TablePush close = free.push;
  close.start = {0.20, -0.04};
  EXPECT_TRUE(meets(close).has_value());
  // Bounds: the option and the margin.
  PushPlanOptions bad = flat_options();
  bad.descent_pose_margin = -0.001;
  EXPECT_THROW(bad.validate(), Error);
  bad.descent_pose_margin = 0.06;
  EXPECT_THROW(bad.validate(), Error);
  EXPECT_THROW(
      (void)descent_meets_object(s.state, free.push, s.q0, descent_map(s.view, {}), -1.0, false),
      Error);
}

TEST(PushPlanner, ARetryAfterARefusalTakesAPathWhoseArmComesDownClearOfThePushedObject) {
  // The pushed object itself 20 cm tall (a bottle), pushed 16 cm along +y from starts 1-8 cm
  // behind it; the neighbour low and out of the way. The least-cost path starts near the object
  // and the hand above the pusher comes down on it (the robot refuses it, session 31). After a
  // refusal with refusal_pose_margin, the retry takes a path whose arm keeps clear on its way down.
  TallObjectScene s;
  ASSERT_EQ(s.view.objects.size(), 2U);
  const auto meets = [&](const robot::TablePush& p) {
    return descent_meets_object(s.state, p, s.q0, descent_map(s.view, {}), 0.005, false);
  };
  PushPlanOptions o = flat_options();
  o.min_approach = 0.01;
  o.max_approach = 0.08;
  // Off (the default): a retry is planned with the same options.
  const PushPlanOptions same = after_refusal(o);
  EXPECT_EQ(same.descent_pose_margin, 0.0);
  EXPECT_FALSE(same.descent_pose_fallback);
  const PushPlan plain = s.plan(same);
  ASSERT_EQ(plain.outcome, PlanOutcome::kPlanned) << plain.message;
  EXPECT_TRUE(meets(plain.push).has_value());
  o.refusal_pose_margin = 0.005;
  EXPECT_EQ(s.plan(o).push.start, plain.push.start);  // the first try is unchanged
  const PushPlanOptions retry = after_refusal(o);
  EXPECT_EQ(retry.descent_pose_margin, 0.005);
  EXPECT_TRUE(retry.descent_pose_fallback);
  const PushPlan cleared = s.plan(retry);
  ASSERT_EQ(cleared.outcome, PlanOutcome::kPlanned) << cleared.message;
  EXPECT_FALSE(cleared.descent_met);
  EXPECT_GT(cleared.rejected_descent, 0);
  EXPECT_FALSE(meets(cleared.push).has_value()) << *meets(cleared.push);
  EXPECT_NE(cleared.push.start, plain.push.start);
  // A larger descent margin already asked for is kept.
  o.descent_pose_margin = 0.01;
  EXPECT_EQ(after_refusal(o).descent_pose_margin, 0.01);
  // No clear way down anywhere (starts 1-2 cm behind it): the retry is the path as before.
  o.descent_pose_margin = 0;
  o.min_approach = 0.01;
  o.max_approach = 0.015;
  const PushPlan near = s.plan(o);
  const PushPlan fallback = s.plan(after_refusal(o));
  ASSERT_EQ(fallback.outcome, PlanOutcome::kPlanned) << fallback.message;
  EXPECT_TRUE(fallback.descent_met);
  EXPECT_EQ(fallback.push.start, near.push.start);
  // Bounds.
  PushPlanOptions bad = flat_options();
  bad.refusal_pose_margin = -0.001;
  EXPECT_THROW((void)after_refusal(bad), Error);
  bad.refusal_pose_margin = 0.06;
  EXPECT_THROW((void)after_refusal(bad), Error);
}

TEST(PushPlanner, ATallObjectWhoseHandComesDownOnItIsNotPushedWithTallStartClearance) {
  // The pushed object 20 cm tall (a bottle), pushed 16 cm along +y; the neighbour low and out of
  // the way. Without the option the plan's palm comes down on it (session 31: the bottle toppled
  // and rolled off the table); with tall_start_clearance every path, from 2-6 cm behind it and
  // from 11-15 cm, brings the palm or a link onto it, so nothing is planned (not a fallback).
  TallObjectScene s;
  ASSERT_EQ(s.view.objects.size(), 2U);
  const DescentMap map = descent_map(s.view, {});
  PushPlanOptions o = flat_options();
  const PushPlan plain = s.plan(o);  // off (the default)
  ASSERT_EQ(plain.outcome, PlanOutcome::kPlanned) << plain.message;
  EXPECT_EQ(plain.rejected_tall, 0);
  const std::optional<std::string> met =
      tall_push_meets(s.state, plain.push, s.q0, map, 0.01, false, plain.approach);
  ASSERT_TRUE(met.has_value());
  EXPECT_NE(met->find("arm_palm"), std::string::npos) << *met;
  o.tall_start_clearance = 0.01;
  EXPECT_TRUE(tall_start(s.obj(), plain.push.height, o));
  const PushPlan tall = s.plan(o);
  EXPECT_EQ(tall.outcome, PlanOutcome::kUnreachable) << tall.message;
  EXPECT_GT(tall.rejected_tall, o.candidates);  // the longer approaches were tried too
  EXPECT_NE(tall.message.find("by the tall object"), std::string::npos) << tall.message;
  // An object lower than the palm (5 cm), or of unknown height (no depth): the plan as without it.
  for (const std::optional<double> h : {std::optional<double>(0.05), std::optional<double>()}) {
    s.obj().height = h;
    EXPECT_FALSE(tall_start(s.obj(), plain.push.height, o));
    const PushPlan low = s.plan(o);
    ASSERT_EQ(low.outcome, PlanOutcome::kPlanned) << low.message;
    EXPECT_EQ(low.push.start, plain.push.start);
    EXPECT_EQ(low.rejected_tall, 0);
  }
  // Bounds.
  PushPlanOptions bad = flat_options();
  bad.tall_start_clearance = -0.001;
  EXPECT_THROW(bad.validate(), Error);
  bad.tall_start_clearance = 0.06;
  EXPECT_THROW(bad.validate(), Error);
  EXPECT_THROW((void)tall_push_meets(s.state, plain.push, s.q0, map, -0.01, false, 0.02), Error);
  EXPECT_THROW((void)tall_push_meets(s.state, plain.push, s.q0, map, 0.01, false, -0.02), Error);
}

TEST(PushPlanner, ATallObjectIsPushedHigherAndSlowerByItsMeasuredHeight) {
  // A square object pushed toward -x: with tip_fraction and tall_push_speed set, a measured
  // 15 cm object is pushed at a third of its height (5 cm: kMostTipHeight) and at the tall speed,
  // a 3 cm one at 1 cm and the usual speed, an unmeasured one (no depth) at tip_height and
  // push_speed; with the options off (the defaults) every object as before.
  const geometry::Camera cam = down_camera();
  std::vector<cv::KeyPoint> f;
  add_feature_square(f, cam, {0.28, 0.0}, 0.03);
  PlanningView view = make_planning_view(f, cam, {}, flat_options());
  ASSERT_EQ(view.objects.size(), 1U);
  robot::ArmState state(arm());
  const robot::JointVector q0 = robot::JointVector::Zero();
  const Eigen::Vector2d target(0.22, 0.0);
  PushPlanOptions o = flat_options();
  o.tip_fraction = 1.0 / 3.0;
  o.tall_height = 0.06;
  o.tall_push_speed = 0.02;
  struct Case {
    std::optional<double> height;
    double tip;
    double speed;
  };
  // Taller than tip_raise_height (15 cm, a bottle): the low tip, slowly.
  for (const Case& c :
       {Case{0.19, o.tip_height, 0.02}, Case{0.15, kMostTipHeight, 0.02}, Case{0.09, 0.03, 0.02},
        Case{0.03, 0.01, o.push_speed}, Case{0.012, o.tip_height, o.push_speed},
        Case{std::nullopt, o.tip_height, o.push_speed}}) {
    view.objects[0].height = c.height;
    EXPECT_NEAR(push_tip_height(view.objects[0], o), c.tip, 1e-12);
    EXPECT_NEAR(push_speed_for(view.objects[0], o), c.speed, 1e-12);
    const PushPlan p = plan_push(view, 0, PushGoal::kTarget, target, {}, state, q0, o);
    ASSERT_EQ(p.outcome, PlanOutcome::kPlanned) << p.message;
    EXPECT_NEAR(p.push.height, c.tip, 1e-12);
    EXPECT_NEAR(p.push.speed, c.speed, 1e-12);
    const PushPlan off =
        plan_push(view, 0, PushGoal::kTarget, target, {}, state, q0, flat_options());
    ASSERT_EQ(off.outcome, PlanOutcome::kPlanned) << off.message;
    EXPECT_EQ(off.push.height, flat_options().tip_height);
    EXPECT_EQ(off.push.speed, flat_options().push_speed);
  }
  PushPlanOptions bad = o;
  bad.tip_fraction = 0.9;
  EXPECT_THROW(bad.validate(), Error);
}

TEST(PushPlanner, ALowObjectIsPushedWithTheJawsAlongThePush) {
  // jaws_along_height 2.5 cm, tip at a third of the height: a measured 3.5 cm book (tip 1.17 cm,
  // 3.5 < 3.67) and a 1 cm CD are pushed with the jaws along the push; a 6 cm spirit level (tip
  // 2 cm, 6 > 4.5), an unmeasured object (no depth) and any object with the option off (the
  // default) as the robot holds them.
  const geometry::Camera cam = down_camera();
  std::vector<cv::KeyPoint> f;
  add_feature_square(f, cam, {0.28, 0.0}, 0.03);
  PlanningView view = make_planning_view(f, cam, {}, flat_options());
  ASSERT_EQ(view.objects.size(), 1U);
  robot::ArmState state(arm());
  const robot::JointVector q0 = robot::JointVector::Zero();
  const Eigen::Vector2d target(0.22, 0.0);
  PushPlanOptions o = flat_options();
  o.tip_fraction = 1.0 / 3.0;
  o.jaws_along_height = 0.025;
  struct Case {
    std::optional<double> height;
    robot::JawLine jaws;
  };
  for (const Case& c : {Case{0.035, robot::JawLine::kAlong}, Case{0.01, robot::JawLine::kAlong},
                        Case{0.06, robot::JawLine::kRobot}, Case{0.2, robot::JawLine::kRobot},
                        Case{std::nullopt, robot::JawLine::kRobot}}) {
    view.objects[0].height = c.height;
    const double tip = push_tip_height(view.objects[0], o);
    EXPECT_EQ(push_jaws(view.objects[0], tip, o), c.jaws);
    const PushPlan p = plan_push(view, 0, PushGoal::kTarget, target, {}, state, q0, o);
    ASSERT_EQ(p.outcome, PlanOutcome::kPlanned) << p.message;
    EXPECT_EQ(p.push.jaws, c.jaws);
    const PushPlan off =
        plan_push(view, 0, PushGoal::kTarget, target, {}, state, q0, flat_options());
    ASSERT_EQ(off.outcome, PlanOutcome::kPlanned) << off.message;
    EXPECT_EQ(off.push.jaws, robot::JawLine::kRobot);
  }
  PushPlanOptions bad = o;
  bad.jaws_along_height = -0.01;
  EXPECT_THROW(bad.validate(), Error);
  bad.jaws_along_height = 0.2;
  EXPECT_THROW(bad.validate(), Error);
}

TEST(PushPlanner, LeastPushSetsWhenAnObjectIsAtItsTarget) {
  // 7 mm from its target: at the target by the default least push (1 cm), pushed the 7 mm with
  // least_push 5 mm (a closed loop whose tolerance is under a centimetre), and the push's end is
  // the target less the hull's back distance, as for a long push.
  const geometry::Camera cam = down_camera();
  std::vector<cv::KeyPoint> f;
  add_feature_square(f, cam, {0.28, 0.0}, 0.03);
  const PlanningView view = make_planning_view(f, cam, {}, flat_options());
  ASSERT_EQ(view.objects.size(), 1U);
  robot::ArmState state(arm());
  const robot::JointVector q0 = robot::JointVector::Zero();
  const Eigen::Vector2d target = view.objects[0].centre + Eigen::Vector2d(-0.007, 0.0);
  EXPECT_EQ(plan_push(view, 0, PushGoal::kTarget, target, {}, state, q0, flat_options()).outcome,
            PlanOutcome::kAtTarget);
  PushPlanOptions o = flat_options();
  o.least_push = 0.005;
  o.target_spread = 0;
  const PushPlan p = plan_push(view, 0, PushGoal::kTarget, target, {}, state, q0, o);
  ASSERT_EQ(p.outcome, PlanOutcome::kPlanned) << p.message;
  EXPECT_NEAR((p.target - target).norm(), 0.0, 1e-12);
  EXPECT_NEAR((p.push.end - p.push.start).norm(), p.approach + 0.007, 1e-9);
  o.least_push = 0.001;
  EXPECT_THROW(o.validate(), Error);
}

TEST(PushPlanner, DescentClearanceGoesByMeasuredHeights) {
  // The same push toward the base: a CD's height measured (1 cm), the forearm may pass over it and
  // the push is planned again; a bottle's (19 cm) keeps it refused. A low neighbour beside every
  // start of a sideways push does not block it, a tall one does.
  const geometry::Camera cam = down_camera();
  std::vector<cv::KeyPoint> f;
  add_feature_square(f, cam, {0.25, 0.0}, 0.02);
  PlanningView view = make_planning_view(f, cam, {}, flat_options());
  ASSERT_EQ(view.objects.size(), 1U);
  robot::ArmState state(arm());
  const robot::JointVector q0 = robot::JointVector::Zero();
  PushPlanOptions o = flat_options();
  o.descent_clearance = 0.04;
  view.objects[0].height = 0.01;
  const PushPlan low = plan_push(view, 0, PushGoal::kTarget, {0.17, 0.0}, {}, state, q0, o);
  EXPECT_EQ(low.outcome, PlanOutcome::kPlanned) << low.message;
  view.objects[0].height = 0.19;
  const PushPlan tall = plan_push(view, 0, PushGoal::kTarget, {0.17, 0.0}, {}, state, q0, o);
  EXPECT_EQ(tall.outcome, PlanOutcome::kUnreachable) << tall.message;
  // Pushed sideways toward +y from behind it (starts near (0.25, -0.05)): a neighbour 1 cm
  // past the starts' side.
  std::vector<cv::KeyPoint> g;
  add_feature_square(g, cam, {0.25, 0.0}, 0.02);
  add_feature_square(g, cam, {0.25, -0.10}, 0.02);
  PlanningView two = make_planning_view(g, cam, {}, flat_options());
  ASSERT_EQ(two.objects.size(), 2U);
  const int a = two.objects[0].centre.y() > -0.05 ? 0 : 1;
  const auto b = static_cast<std::size_t>(1 - a);
  two.objects[static_cast<std::size_t>(a)].height = 0.01;
  two.objects[b].height = 0.01;
  const PushPlan past_low = plan_push(two, a, PushGoal::kTarget, {0.25, 0.08}, {}, state, q0, o);
  EXPECT_EQ(past_low.outcome, PlanOutcome::kPlanned) << past_low.message;
  two.objects[b].height = 0.15;
  const PushPlan past_tall = plan_push(two, a, PushGoal::kTarget, {0.25, 0.08}, {}, state, q0, o);
  EXPECT_EQ(past_tall.outcome, PlanOutcome::kUnreachable) << past_tall.message;
  // Heights unknown (no depth): every blob tall, as before.
  two.objects[static_cast<std::size_t>(a)].height.reset();
  two.objects[b].height.reset();
  const PushPlan blind = plan_push(two, a, PushGoal::kTarget, {0.25, 0.08}, {}, state, q0, o);
  EXPECT_EQ(blind.outcome, PlanOutcome::kUnreachable) << blind.message;
}

TEST(PushPlanner, GoesRoundANeighbourInTheLineThroughAWaypoint) {
  // The object at (0.20, 0), its target 16 cm along +y, a neighbour on the line between: the
  // direct push would shove the neighbour along. With waypoints the planner pushes the object
  // beside the line first (its corridor clear of the neighbour), and from there the next push
  // reaches the target clear of it too.
  NeighbourScene s({0.20, 0.07});
  ASSERT_EQ(s.view.objects.size(), 2U);
  const auto& obj = s.obj();
  const auto& other = s.other();
  const Eigen::Vector2d target = s.target;
  PushPlanOptions o = flat_options();
  o.clearance = 0.01;
  o.hand_clearance = 0.03;
  o.via_points = 24;
  const PushPlan p = s.plan(o);
  ASSERT_EQ(p.outcome, PlanOutcome::kPlanned) << p.message;
  EXPECT_TRUE(p.via);
  EXPECT_EQ(p.blocked, 0.0);
  // The corridor the object sweeps to the waypoint, and on from there, keeps clear of the
  // neighbour's hull.
  std::vector<Eigen::Vector2d> swept = obj.hull;
  for (const auto& h : obj.hull) swept.push_back(h + (p.target - obj.centre));
  std::vector<Eigen::Vector2d> on;
  for (const auto& h : obj.hull) on.push_back(h + (p.target - obj.centre));
  for (const auto& h : obj.hull) on.push_back(h + (target - obj.centre));
  // (the convex hulls of these point sets: polygon_distance wants convex polygons)
  const auto hull_of = [](const std::vector<Eigen::Vector2d>& pts) {
    std::vector<cv::Point2f> q;
    q.reserve(pts.size());
    for (const auto& x : pts) q.emplace_back(static_cast<float>(x.x()), static_cast<float>(x.y()));
    std::vector<cv::Point2f> h;
    cv::convexHull(q, h);
    std::vector<Eigen::Vector2d> out;
    out.reserve(h.size());
    for (const auto& x : h) out.emplace_back(x.x, x.y);
    return out;
  };
  EXPECT_GT(polygon_distance(hull_of(swept), other.hull), 0.005);
  EXPECT_GT(polygon_distance(hull_of(on), other.hull), 0.005);
  // Without waypoints (a single push must end at the target) the plan goes straight, blocked.
  o.via_points = 0;
  const PushPlan direct = s.plan(o);
  ASSERT_EQ(direct.outcome, PlanOutcome::kPlanned) << direct.message;
  EXPECT_FALSE(direct.via);
  EXPECT_GT(direct.blocked, 0.0);
  EXPECT_LT((direct.target - target).norm(), o.target_spread + 1e-9);
}

TEST(PushTracking, FindsThePushedObjectWhereItNowTouchesAStillOne) {
  const geometry::Camera cam = down_camera();
  const PushPlanOptions o = flat_options();
  cv::Mat before(480, 640, CV_8U, cv::Scalar(128));
  cv::Mat after = before.clone();
  draw_checkered_square(before, cam, {0.20, 0.06}, 0.03);   // the object, before the push
  draw_checkered_square(before, cam, {0.20, -0.07}, 0.03);  // a still neighbour
  draw_checkered_square(after, cam, {0.20, -0.005}, 0.03);  // pushed by 6.5 cm, now 5 mm from it
  draw_checkered_square(after, cam, {0.20, -0.07}, 0.03);
  const TableRegion region;
  const PlanningView view0 = make_planning_view(textured_points(before, o), cam, region, o);
  ASSERT_EQ(view0.objects.size(), 2U);
  const PutativeObject& pushed =
      view0.objects[0].centre.y() > 0 ? view0.objects[0] : view0.objects[1];
  PlanningView view1 = make_planning_view(textured_points(after, o), cam, region, o);
  ASSERT_EQ(view1.objects.size(), 1U);  // the two blobs merged
  const Eigen::Vector2d expected(0.20, 0.0);
  const int k = find_pushed_object(before, after, view1, pushed, expected, 0.08, region, o);
  ASSERT_GE(k, 0);
  const PutativeObject& found = view1.objects[static_cast<std::size_t>(k)];
  EXPECT_NEAR(found.centre.x(), 0.20, 0.01);
  EXPECT_NEAR(found.centre.y(), -0.005, 0.01);  // not pulled toward the neighbour at -0.07
  // Nothing moved: the object where it was.
  PlanningView same = view0;
  const int s = find_pushed_object(before, before, same, pushed, expected, 0.08, region, o);
  ASSERT_GE(s, 0);
  EXPECT_NEAR(same.objects[static_cast<std::size_t>(s)].centre.y(), pushed.centre.y(), 1e-9);
  EXPECT_EQ(moved_share(before, before, pushed), 0.0);
}

// A mask of the view's size over the table square of half side h at c (the region a push's
// motion segmentation gave one object), grown by `grow` px.
cv::Mat square_region(const geometry::Camera& cam, const Eigen::Vector2d& c, double h, int grow) {
  cv::Mat m(cam.height, cam.width, CV_8U, cv::Scalar(0));
  draw_checkered_square(m, cam, c, h);
  m = m > 0;
  if (grow > 0) {
    cv::dilate(m, m,
               cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * grow + 1, 2 * grow + 1)));
  }
  return m;
}

TEST(PushSplit, AMergedBlobIsSplitByTheRegionThatMovedWithTheArm) {
  const geometry::Camera cam = down_camera();
  const PushPlanOptions o = flat_options();
  const TableRegion region;
  cv::Mat img(480, 640, CV_8U, cv::Scalar(128));
  draw_checkered_square(img, cam, {0.20, 0.0}, 0.03);     // the object pushed last
  draw_checkered_square(img, cam, {0.20, -0.065}, 0.03);  // another, 5 mm from it
  draw_checkered_square(img, cam, {0.32, 0.12}, 0.03);    // a third, apart
  PlanningView view = make_planning_view(textured_points(img, o), cam, region, o);
  ASSERT_EQ(view.objects.size(), 2U);  // the two touching squares are one blob
  const std::vector<cv::Mat> regions{square_region(cam, {0.20, 0.0}, 0.03, 2)};
  const std::vector<int> found = split_putative_objects(view, regions, 10, region, o);
  ASSERT_EQ(view.objects.size(), 3U);
  ASSERT_EQ(found.size(), 1U);
  ASSERT_GE(found[0], 0);
  const PutativeObject& known = view.objects[static_cast<std::size_t>(found[0])];
  EXPECT_NEAR(known.centre.x(), 0.20, 0.01);
  EXPECT_NEAR(known.centre.y(), 0.0, 0.01);
  // The rest of the blob is a putative object of its own, where the other square lies.
  int other = -1;
  for (std::size_t b = 0; b < view.objects.size(); ++b) {
    if ((view.objects[b].centre - Eigen::Vector2d(0.20, -0.065)).norm() < 0.012) {
      other = static_cast<int>(b);
    }
  }
  ASSERT_GE(other, 0);
  EXPECT_NE(other, found[0]);
  // Every feature point of the merged blob is in exactly one of the two parts.
  const std::size_t before = view.objects[static_cast<std::size_t>(found[0])].pixels.size() +
                             view.objects[static_cast<std::size_t>(other)].pixels.size();
  const PlanningView again = make_planning_view(textured_points(img, o), cam, region, o);
  const std::size_t merged = again.objects[0].pixels.size() > again.objects[1].pixels.size()
                                 ? again.objects[0].pixels.size()
                                 : again.objects[1].pixels.size();
  EXPECT_EQ(before, merged);
}

TEST(PushSplit, ABlobIsLeftWholeWhenTheRegionHoldsAllOrNoneOfIt) {
  const geometry::Camera cam = down_camera();
  const PushPlanOptions o = flat_options();
  const TableRegion region;
  cv::Mat img(480, 640, CV_8U, cv::Scalar(128));
  draw_checkered_square(img, cam, {0.20, 0.0}, 0.03);
  draw_checkered_square(img, cam, {0.32, 0.12}, 0.03);
  const PlanningView view0 = make_planning_view(textured_points(img, o), cam, region, o);
  ASSERT_EQ(view0.objects.size(), 2U);
  // The region covers one object whole (and a little table): nothing to split; found.
  PlanningView view = view0;
  std::vector<int> found =
      split_putative_objects(view, {square_region(cam, {0.20, 0.0}, 0.03, 6)}, 10, region, o);
  EXPECT_EQ(view.objects.size(), 2U);
  ASSERT_GE(found[0], 0);
  EXPECT_NEAR(view.objects[static_cast<std::size_t>(found[0])].centre.y(), 0.0, 0.01);
  // A region on the empty table, an unknown (empty) region: nothing found, nothing split.
  view = view0;
  found = split_putative_objects(view, {square_region(cam, {0.30, -0.15}, 0.02, 0), cv::Mat()}, 10,
                                 region, o);
  EXPECT_EQ(view.objects.size(), 2U);
  EXPECT_EQ(found, (std::vector<int>{-1, -1}));
  // A region over a sliver of a blob (fewer than min_features points): left whole.
  view = view0;
  found = split_putative_objects(view, {square_region(cam, {0.20, 0.03}, 0.004, 0)}, 10, region, o);
  EXPECT_EQ(view.objects.size(), 2U);
  EXPECT_THROW((void)split_putative_objects(view, {cv::Mat(10, 10, CV_8U)}, 10, region, o), Error);
}

// The simulated table's camera (sim::SimulatedRobot): from (0.24, -0.40, 0.80) toward
// (0.24, 0.02, 0), 62 degrees below the horizontal; OpenCV axes (x right, y down, z forward).
geometry::Camera oblique_camera() {
  return test::look_at_camera(Eigen::Vector3d(0.24, -0.40, 0.80), Eigen::Vector3d(0.24, 0.02, 0.0),
                              600, 640, 480);
}

// The largest distance between two points of a polygon, m.
double hull_span(const std::vector<Eigen::Vector2d>& hull) {
  double d = 0;
  for (const auto& a : hull) {
    for (const auto& b : hull) d = std::max(d, (a - b).norm());
  }
  return d;
}

// A box standing on the table (centre of its footprint `c`, half sides `hx`, `hy`, height `h`,
// turned `yaw` rad), its faces the camera sees drawn with a 4 px checker into `img` (8-bit grey).
void draw_checkered_box(cv::Mat& img, const geometry::Camera& cam, const Eigen::Vector2d& c,
                        double hx, double hy, double h, double yaw) {
  const Eigen::Matrix2d r = Eigen::Rotation2Dd(yaw).toRotationMatrix();
  const auto corner = [&](double sx, double sy, double z) {
    const Eigen::Vector2d p = c + r * Eigen::Vector2d(sx * hx, sy * hy);
    return Eigen::Vector3d(p.x(), p.y(), z);
  };
  // Faces as corner lists with their outward normals: the top and the four sides.
  std::vector<std::pair<std::vector<Eigen::Vector3d>, Eigen::Vector3d>> faces;
  faces.push_back({{corner(-1, -1, h), corner(1, -1, h), corner(1, 1, h), corner(-1, 1, h)},
                   Eigen::Vector3d::UnitZ()});
  const double s[4][2] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};
  for (const auto& d : s) {
    const double ax = d[0] != 0 ? d[0] : -1;
    const double ay = d[1] != 0 ? d[1] : -1;
    const double bx = d[0] != 0 ? d[0] : 1;
    const double by = d[1] != 0 ? d[1] : 1;
    Eigen::Vector3d n;
    n << r * Eigen::Vector2d(d[0], d[1]), 0.0;
    faces.push_back(
        {{corner(ax, ay, 0), corner(bx, by, 0), corner(bx, by, h), corner(ax, ay, h)}, n});
  }
  for (const auto& [corners, normal] : faces) {
    if (normal.dot(cam.center() - corners[0]) <= 0) continue;  // facing away
    std::vector<cv::Point> poly;
    for (const auto& x : corners) {
      const Eigen::Vector2d p = cam.project(x);
      poly.emplace_back(static_cast<int>(std::lround(p.x())), static_cast<int>(std::lround(p.y())));
    }
    cv::Mat1b mask(img.size(), 0);
    cv::fillConvexPoly(mask, poly, cv::Scalar(255));
    for (int v = 0; v < img.rows; ++v) {
      for (int u = 0; u < img.cols; ++u) {
        if (mask(v, u) != 0) img.at<std::uint8_t>(v, u) = ((u / 4 + v / 4) % 2) != 0 ? 40 : 220;
      }
    }
  }
}

TEST(PushPlanner, TheBaseContourCorrectsATallBoxsParallax) {
  const geometry::Camera cam = oblique_camera();
  const TableRegion region;
  // A tall box (4 x 6 cm, 15 cm high, like the bottle or the giraffe) and a flat one (the CD),
  // turned; their footprints' centres are the known answers.
  struct Case {
    Eigen::Vector2d c;
    double hx, hy, h, yaw;
  };
  for (const Case& k :
       {Case{{0.24, 0.06}, 0.02, 0.03, 0.15, 0.5}, Case{{0.10, -0.05}, 0.03, 0.02, 0.12, -0.3},
        Case{{0.35, 0.12}, 0.06, 0.06, 0.01, 0.2}}) {
    cv::Mat img(480, 640, CV_8U, cv::Scalar(128));
    draw_checkered_box(img, cam, k.c, k.hx, k.hy, k.h, k.yaw);
    PushPlanOptions base;
    base.centre = CentreMethod::kBase;
    const PlanningView view = make_planning_view(textured_points(img, base), cam, region, base);
    ASSERT_EQ(view.objects.size(), 1U);
    const PutativeObject& o = view.objects[0];
    const double err = (o.centre - k.c).norm();
    EXPECT_LT(err, 0.007) << "box at " << k.c.transpose() << " height " << k.h;
    // The footprint holds the true centre and is about the box's size (the features reach half a
    // patch, about 8 mm, beyond its edges).
    EXPECT_GT(distance_to_hull_edge(o.hull, k.c, Eigen::Vector2d::UnitX()), 0.0);
    const double diagonal = 2 * std::hypot(k.hx, k.hy);
    EXPECT_LT(hull_span(o.hull), diagonal + 0.035);
    EXPECT_GT(hull_span(o.hull), diagonal - 0.005);
    // The thesis's centre (mean feature at 3.5 cm) lands beyond a tall box: the parallax.
    PushPlanOptions features;
    const PlanningView fv =
        make_planning_view(textured_points(img, features), cam, region, features);
    ASSERT_EQ(fv.objects.size(), 1U);
    if (k.h > 0.1) {
      EXPECT_GT((fv.objects[0].centre - k.c).norm(), err + 0.008);
    }
  }
}

// The depth image (CV_32FC1, metres along the optical axis) of the table top (z = 0) with the box
// of draw_checkered_box standing on it.
cv::Mat1f render_box_depth(const geometry::Camera& cam, const Eigen::Vector2d& c, double hx,
                           double hy, double h, double yaw) {
  return test::render_boxes_depth(cam, {{c, hx, hy, h, yaw}});
}

TEST(PushPlanner, DepthMeasuresABoxsFootprintAndHeight) {
  const geometry::Camera cam = oblique_camera();
  const TableRegion region;
  struct Case {
    Eigen::Vector2d c;
    double hx, hy, h, yaw;
  };
  for (const Case& k :
       {Case{{0.24, 0.06}, 0.02, 0.03, 0.15, 0.5}, Case{{0.10, -0.05}, 0.03, 0.02, 0.12, -0.3},
        Case{{0.35, 0.12}, 0.06, 0.06, 0.01, 0.2}, Case{{0.45, -0.10}, 0.04, 0.025, 0.05, 1.0}}) {
    cv::Mat img(480, 640, CV_8U, cv::Scalar(128));
    draw_checkered_box(img, cam, k.c, k.hx, k.hy, k.h, k.yaw);
    const cv::Mat1f depth = render_box_depth(cam, k.c, k.hx, k.hy, k.h, k.yaw);
    const PushPlanOptions o;
    const std::vector<cv::KeyPoint> points = textured_points(img, o);
    const PlanningView view = make_planning_view(points, cam, region, o, depth);
    ASSERT_EQ(view.objects.size(), 1U);
    const PutativeObject& m = view.objects[0];
    ASSERT_TRUE(m.height.has_value());
    EXPECT_NEAR(*m.height, k.h, 0.004) << "box at " << k.c.transpose();
    EXPECT_LT((m.centre - k.c).norm(), 0.004) << "box at " << k.c.transpose() << " height " << k.h;
    // The footprint is the box's: its diagonal, within the depth sampling (2 px).
    const double diagonal = 2 * std::hypot(k.hx, k.hy);
    EXPECT_NEAR(hull_span(m.hull), diagonal, 0.008);
    // Without depth: the back-projection at 3.5 cm, exactly as make_planning_view has always
    // made it (no height), which a tall box's parallax puts centimetres off.
    const PlanningView plain = make_planning_view(points, cam, region, o);
    const PlanningView empty = make_planning_view(points, cam, region, o, cv::Mat());
    ASSERT_EQ(plain.objects.size(), 1U);
    ASSERT_EQ(empty.objects.size(), 1U);
    EXPECT_FALSE(plain.objects[0].height.has_value());
    EXPECT_TRUE(plain.depth.empty());
    EXPECT_EQ(plain.objects[0].centre, empty.objects[0].centre);
    EXPECT_EQ(plain.objects[0].hull, empty.objects[0].hull);
    EXPECT_EQ(plain.objects[0].extent, m.extent);  // what the tracking carries is unchanged
    if (k.h > 0.1) {
      EXPECT_GT((plain.objects[0].centre - k.c).norm(), 0.012);
    }
  }
  // A depth image of another size, or not float metres, is bad input.
  const PushPlanOptions o;
  EXPECT_THROW((void)make_planning_view({}, cam, region, o, cv::Mat1f(10, 10, 1.0F)), Error);
  EXPECT_THROW((void)make_planning_view({}, cam, region, o, cv::Mat(480, 640, CV_16U)), Error);
  // Too few points above the table: no footprint.
  EXPECT_FALSE(measure_footprint(cv::Mat1f(480, 640, 0.0F), cam, {{10, 10}, {100, 10}, {100, 100}})
                   .has_value());
}

// The depth image of two square boxes (half side `half`, heights ah and bh) standing on the table.
cv::Mat1f render_two_boxes_depth(const geometry::Camera& cam, const Eigen::Vector2d& a, double ah,
                                 const Eigen::Vector2d& b, double bh, double half) {
  return test::render_boxes_depth(cam, {{a, half, half, ah, 0.0}, {b, half, half, bh, 0.0}});
}

TEST(PushSplit, TwoTouchingBoxesOfDifferentHeightsAreSplitByTheirDepthTops) {
  const geometry::Camera cam = oblique_camera();
  const TableRegion region;
  // A 3 cm high box and a 9 cm high one, 6 cm square, touching side by side (y = 0.03).
  const Eigen::Vector2d low(0.24, 0.0);
  const Eigen::Vector2d high(0.24, 0.06);
  const double half = 0.03;
  const auto scene = [&](double low_h, double high_h) {
    cv::Mat img(480, 640, CV_8U, cv::Scalar(128));
    // The farther one first: the nearer one's faces cover it where they overlap in the image.
    const bool low_nearer =
        (low - cam.center().head<2>()).norm() < (high - cam.center().head<2>()).norm();
    if (low_nearer) {
      draw_checkered_box(img, cam, high, half, half, high_h, 0.0);
      draw_checkered_box(img, cam, low, half, half, low_h, 0.0);
    } else {
      draw_checkered_box(img, cam, low, half, half, low_h, 0.0);
      draw_checkered_box(img, cam, high, half, half, high_h, 0.0);
    }
    return std::make_pair(img, render_two_boxes_depth(cam, low, low_h, high, high_h, half));
  };
  const auto [img, depth] = scene(0.03, 0.09);
  PushPlanOptions o;
  const std::vector<cv::KeyPoint> points = textured_points(img, o);
  // Off (the default): one blob, one putative object between the two.
  const PlanningView merged = make_planning_view(points, cam, region, o, depth);
  ASSERT_EQ(merged.objects.size(), 1U);
  const PutativeObject& both = merged.objects[0];
  const DepthTops tops = depth_tops(depth, cam, both.mask, both.box, 0.01);
  EXPECT_EQ(tops.count, 2);
  EXPECT_EQ(tops.labels.size(), both.box.size());
  PlanningView copy = merged;
  EXPECT_EQ(split_by_depth(copy, region, o), 0);  // depth_split 0: off
  EXPECT_EQ(copy.objects.size(), 1U);
  // On: two putative objects, each with its own box's centre and height.
  o.depth_split = 0.01;
  const PlanningView split = make_planning_view(points, cam, region, o, depth);
  ASSERT_EQ(split.objects.size(), 2U);
  const int a = object_nearest(split, low);
  const int b = object_nearest(split, high);
  ASSERT_NE(a, b);
  const PutativeObject& pa = split.objects[static_cast<std::size_t>(a)];
  const PutativeObject& pb = split.objects[static_cast<std::size_t>(b)];
  EXPECT_LT((pa.centre - low).norm(), 0.008) << pa.centre.transpose();
  EXPECT_LT((pb.centre - high).norm(), 0.008) << pb.centre.transpose();
  ASSERT_TRUE(pa.height.has_value());
  ASSERT_TRUE(pb.height.has_value());
  EXPECT_NEAR(*pa.height, 0.03, 0.004);
  EXPECT_NEAR(*pb.height, 0.09, 0.004);
  EXPECT_EQ(pa.pixels.size() + pb.pixels.size(), both.pixels.size());  // every feature kept
  // A step smaller than the jump (3 vs 4.5 cm with a 2 cm jump), or two tops of the same height:
  // one top, not split.
  PushPlanOptions big = o;
  big.depth_split = 0.02;
  const auto [img2, depth2] = scene(0.03, 0.045);
  EXPECT_EQ(make_planning_view(textured_points(img2, big), cam, region, big, depth2).objects.size(),
            1U);
  const auto [img3, depth3] = scene(0.05, 0.05);
  const PlanningView same = make_planning_view(textured_points(img3, o), cam, region, o, depth3);
  ASSERT_EQ(same.objects.size(), 1U);
  EXPECT_EQ(depth_tops(depth3, cam, same.objects[0].mask, same.objects[0].box, 0.01).count, 1);
  // One box alone: one top. No depth: nothing split.
  cv::Mat one(480, 640, CV_8U, cv::Scalar(128));
  draw_checkered_box(one, cam, low, half, half, 0.03, 0.0);
  const cv::Mat1f one_depth = render_box_depth(cam, low, half, half, 0.03, 0.0);
  const PlanningView single =
      make_planning_view(textured_points(one, o), cam, region, o, one_depth);
  ASSERT_EQ(single.objects.size(), 1U);
  EXPECT_EQ(depth_tops(one_depth, cam, single.objects[0].mask, single.objects[0].box, 0.01).count,
            1);
  EXPECT_EQ(make_planning_view(points, cam, region, o).objects.size(), 1U);
  // Bad input.
  EXPECT_THROW((void)depth_tops(depth, cam, both.mask, both.box, 0.0), Error);
  EXPECT_THROW((void)depth_tops(depth, cam, both.mask, both.box, 0.01, 0), Error);
  EXPECT_THROW((void)depth_tops(depth, cam, cv::Mat1b(3, 3, 255), both.box, 0.01), Error);
  EXPECT_THROW((void)depth_tops(cv::Mat(480, 640, CV_16U), cam, both.mask, both.box, 0.01), Error);
}

// A putative object with a square hull of side 2 * half around `c` and, when given, a height.
PutativeObject square_object(const Eigen::Vector2d& c, double half, std::optional<double> height) {
  PutativeObject o;
  o.centre = c;
  o.hull = {c + Eigen::Vector2d(-half, -half), c + Eigen::Vector2d(half, -half),
            c + Eigen::Vector2d(half, half), c + Eigen::Vector2d(-half, half)};
  o.extent = o.hull;
  o.height = height;
  return o;
}

TEST(PushGeometry, ALowBlobDoesNotBlockADescentATallOneDoes) {
  const double tip = 0.008;
  const double clearance = 0.04;
  // The pushed object 0.40 m out on the x axis, pushed toward the base side... from behind it:
  // the start 0.46 m out, 4 cm behind its edge (its half side 2 cm).
  const Eigen::Vector2d start(0.46, 0.0);
  const PutativeObject pushed_low = square_object({0.40, 0.0}, 0.02, 0.01);
  // A neighbour 2 cm beside the hand (its hull's nearest edge 2 cm from the start).
  const Eigen::Vector2d beside(0.46, 0.04);
  const PutativeObject cd = square_object(beside, 0.02, 0.01);          // 1 cm high
  const PutativeObject calculator = square_object(beside, 0.02, 0.02);  // 2 cm
  const PutativeObject mug = square_object(beside, 0.02, 0.09);         // 9 cm
  const PutativeObject giraffe = square_object(beside, 0.02, 0.16);     // 16 cm
  const PutativeObject unknown = square_object(beside, 0.02, std::nullopt);
  EXPECT_FALSE(descent_blocked(start, pushed_low, {&cd}, clearance, tip));
  EXPECT_FALSE(descent_blocked(start, pushed_low, {&calculator}, clearance, tip));
  EXPECT_TRUE(descent_blocked(start, pushed_low, {&mug}, clearance, tip));
  EXPECT_TRUE(descent_blocked(start, pushed_low, {&giraffe}, clearance, tip));
  // A giraffe 4.5-5.5 cm beside the hand: past the clearance, within the palm's reach.
  const PutativeObject giraffe_past = square_object({0.46, 0.065}, 0.02, 0.16);
  const PutativeObject mug_past = square_object({0.46, 0.065}, 0.02, 0.09);
  EXPECT_TRUE(descent_blocked(start, pushed_low, {&giraffe_past}, clearance, tip));
  EXPECT_FALSE(descent_blocked(start, pushed_low, {&mug_past}, clearance, tip));
  // Without a height: as the height-blind check (every blob tall).
  EXPECT_TRUE(descent_blocked(start, pushed_low, {&unknown}, clearance, tip));
  EXPECT_TRUE(descent_blocked(start, pushed_low.hull, {unknown.hull}, clearance));
  // Height-blind, the low forearm passing over the pushed CD counts as meeting it.
  EXPECT_TRUE(descent_blocked(start, pushed_low.hull, {}, clearance));
  // A neighbour under the low forearm only (10 cm toward the base from the start, 3 cm aside):
  // only one that reaches the palm meets it.
  const Eigen::Vector2d under(0.36, 0.045);
  EXPECT_FALSE(descent_blocked(start, pushed_low, {}, clearance, tip));
  const PutativeObject mug_under = square_object(under, 0.02, 0.09);
  const PutativeObject bottle_under = square_object(under, 0.02, 0.19);
  EXPECT_FALSE(descent_blocked(start, pushed_low, {&mug_under}, clearance, tip));
  EXPECT_TRUE(descent_blocked(start, pushed_low, {&bottle_under}, clearance, tip));

  // The pushed object's own height sets how far behind it the hand may come down (starts on
  // its base side, its edge at 0.38 m: the forearm hangs away from it).
  const Eigen::Vector2d near(0.355, 0.0);  // 2.5 cm behind its edge
  const Eigen::Vector2d mid(0.335, 0.0);   // 4.5 cm
  const Eigen::Vector2d far(0.32, 0.0);    // 6 cm
  const PutativeObject pushed_mug = square_object({0.40, 0.0}, 0.02, 0.09);
  const PutativeObject pushed_bottle = square_object({0.40, 0.0}, 0.02, 0.19);
  const PutativeObject pushed_blind = square_object({0.40, 0.0}, 0.02, std::nullopt);
  EXPECT_FALSE(descent_blocked(near, pushed_low, {}, clearance, tip));
  EXPECT_TRUE(descent_blocked(near, pushed_mug, {}, clearance, tip));  // the fingers, 3 + 1 cm
  EXPECT_FALSE(descent_blocked(mid, pushed_mug, {}, clearance, tip));
  EXPECT_TRUE(descent_blocked(mid, pushed_bottle, {}, clearance, tip));  // the palm, 4.5 + 1 cm
  EXPECT_FALSE(descent_blocked(far, pushed_bottle, {}, clearance, tip));
  EXPECT_FALSE(descent_blocked(near, pushed_blind, {}, clearance, tip));  // height-blind: as before
  // Pushed toward the base (the start beyond it): the low forearm passes over it, which only an
  // object that reaches the palm (or one of unknown height) meets.
  EXPECT_FALSE(descent_blocked({0.47, 0.0}, pushed_mug, {}, clearance, tip));  // 5 cm behind
  EXPECT_TRUE(descent_blocked(start, pushed_bottle, {}, clearance, tip));
  EXPECT_TRUE(descent_blocked(start, pushed_blind, {}, clearance, tip));
  EXPECT_TRUE(descent_blocked(start, pushed_blind.hull, {}, clearance));
}

TEST(PushGeometry, TheHandsFootprintMeetsATallNeighbourBesideThePushNotALowOne) {
  // A push along +x from (0.20, 0) to (0.30, 0), the tip 1 cm up: the jaws (across the push)
  // reach 3 cm to either side from 3.5 cm up (kFingerDrop less kDescentHeightMargin), the palm
  // 4.5 cm from 10.5 cm up.
  const std::vector<Eigen::Vector2d> box = hand_footprint({0.20, 0.0}, {0.30, 0.0}, 0.015, 0.03);
  ASSERT_EQ(box.size(), 4U);
  EXPECT_NEAR((box[0] - Eigen::Vector2d(0.185, -0.03)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((box[2] - Eigen::Vector2d(0.315, 0.03)).norm(), 0.0, 1e-12);
  robot::TablePush push;
  push.start = {0.20, 0.0};
  push.end = {0.30, 0.0};
  push.height = 0.01;
  const double margin = 0.01;
  // A neighbour 3.5-5.5 cm beside the line: 5 mm past the jaws' reach.
  const Eigen::Vector2d beside(0.25, 0.045);
  const PutativeObject low = square_object(beside, 0.01, 0.02);     // under the jaws
  const PutativeObject mug = square_object(beside, 0.01, 0.09);     // the jaws' height
  const PutativeObject bottle = square_object(beside, 0.01, 0.12);  // the palm's
  const PutativeObject unknown = square_object(beside, 0.01, std::nullopt);
  EXPECT_EQ(hand_lack(push, false, {&low}, margin), 0.0);
  EXPECT_NEAR(hand_lack(push, false, {&mug}, margin), 0.005, 1e-9);  // 5 mm short of 1 cm
  // The palm (4.5 cm) runs into the bottle 1 cm deep: the margin and that 1 cm.
  EXPECT_NEAR(hand_lack(push, false, {&bottle}, margin), 0.02, 1e-9);
  EXPECT_NEAR(hand_lack(push, false, {&unknown}, margin), 0.02, 1e-9);  // unknown counts as tall
  // The jaws along the push: the hand 1.5 cm wide to either side (the palm 2.5 cm, 1 cm from
  // the bottle: just the margin): clear.
  EXPECT_EQ(hand_lack(push, true, {&mug}, margin), 0.0);
  EXPECT_NEAR(hand_lack(push, true, {&bottle}, margin), 0.0, 1e-12);
  // The tip raised to 7 cm: the jaws (from 9.5 cm) pass over the mug, not the bottle.
  robot::TablePush raised = push;
  raised.height = 0.07;
  EXPECT_EQ(hand_lack(raised, false, {&mug}, margin), 0.0);
  EXPECT_GT(hand_lack(raised, false, {&bottle}, margin), 0.0);
  // A neighbour 3 cm ahead of the end: clear of the jaws across (1.5 cm ahead), touched by the
  // jaw ahead when they lie along the push (3 cm ahead): the margin.
  const PutativeObject ahead = square_object({0.34, 0.0}, 0.01, 0.09);
  EXPECT_EQ(hand_lack(push, false, {&ahead}, margin), 0.0);
  EXPECT_NEAR(hand_lack(push, true, {&ahead}, margin), 0.01, 1e-9);
  // Summed over the objects; no margin or no objects: nothing; a null entry is skipped.
  EXPECT_NEAR(hand_lack(push, false, {&mug, &ahead, &low, nullptr}, margin), 0.005, 1e-9);
  EXPECT_EQ(hand_lack(push, false, {&mug}, 0.0), 0.0);
  EXPECT_EQ(hand_lack(push, false, {}, margin), 0.0);
  // A tall neighbour under the low forearm only (on the line, 7-9 cm toward the base from the
  // start): the palm-high bottle meets it, the mug does not.
  const PutativeObject bottle_under = square_object({0.12, 0.0}, 0.01, 0.19);
  const PutativeObject mug_under = square_object({0.12, 0.0}, 0.01, 0.09);
  EXPECT_NEAR(hand_lack(push, false, {&bottle_under}, margin), 0.01, 1e-9);
  EXPECT_EQ(hand_lack(push, false, {&mug_under}, margin), 0.0);
  // Bad input.
  EXPECT_THROW((void)hand_footprint({0.2, 0.0}, {0.2, 0.0}, 0.01, 0.01), Error);
  EXPECT_THROW((void)hand_footprint({0.2, 0.0}, {0.3, 0.0}, -0.01, 0.01), Error);
  robot::TablePush bad = push;
  bad.end = bad.start;
  EXPECT_THROW((void)hand_lack(bad, false, {&mug}, margin), Error);
}

TEST(PushPlanner, APlanSaysHowMuchOfItsBlockingIsTheHands) {
  // A tall neighbour beside the pusher's start (behind the object, 4-5.5 cm off the line): the
  // jaws across the push (3 cm either side) meet it at every start, so no shortening clears it.
  // The loop's correction_hand_margin reads PushPlan::hand_blocked.
  NeighbourScene s({0.24, -0.065});
  ASSERT_EQ(s.view.objects.size(), 2U);
  PutativeObject& obj = s.obj();
  PutativeObject& other = s.other();
  obj.height = 0.02;
  other.height = 0.09;
  PushPlanOptions o = flat_options();
  // No hand margin (the default): nothing known of the hand.
  const PushPlan off = s.plan(o);
  ASSERT_EQ(off.outcome, PlanOutcome::kPlanned) << off.message;
  EXPECT_EQ(off.hand_blocked, 0.0);
  EXPECT_GT(hand_lack(off.push, false, {&other}, 0.01), 0.0);
  // With it: planned anyway (every path is blocked), the shortfall the hand's.
  o.hand_margin = 0.01;
  const PushPlan on = s.plan(o);
  ASSERT_EQ(on.outcome, PlanOutcome::kPlanned) << on.message;
  EXPECT_GT(on.hand_blocked, 0.0);
  EXPECT_NEAR(on.hand_blocked, hand_lack(on.push, false, {&other}, 0.01), 1e-12);
  EXPECT_NEAR(on.blocked, on.hand_blocked, 1e-12);  // no other clearance asked
  // A low neighbour (the jaws pass over it): clear.
  other.height = 0.02;
  const PushPlan low = s.plan(o);
  ASSERT_EQ(low.outcome, PlanOutcome::kPlanned) << low.message;
  EXPECT_EQ(low.hand_blocked, 0.0);
  // correction_hand_margin's bounds (the planner does not read it).
  PushPlanOptions bad = flat_options();
  bad.correction_hand_margin = 0.06;
  EXPECT_THROW(bad.validate(), Error);
  bad.correction_hand_margin = -0.001;
  EXPECT_THROW(bad.validate(), Error);
  bad.correction_hand_margin = 0.01;
  EXPECT_NO_THROW(bad.validate());
}

TEST(PushPlanner, AFirstPushWhoseHandIsBlockedTurnsTheJawsOrGoesThroughAWaypoint) {
  // The scene of APlanSaysHowMuchOfItsBlockingIsTheHands: a tall neighbour beside the pusher's
  // start, which the hand (jaws across, 3 cm either side) meets on every straight push to the
  // target and at every shortening. plan_push_hand_clear (the loop's first_hand_margin) keeps
  // the hand clear: jaws along over a low object, else a waypoint; else the push as without it.
  NeighbourScene s({0.24, -0.065});
  ASSERT_EQ(s.view.objects.size(), 2U);
  PutativeObject& obj = s.obj();
  PutativeObject& other = s.other();
  obj.height = 0.02;
  other.height = 0.09;
  const PushPlanOptions o = flat_options();
  const double margin = 0.01;
  const auto clear = [&](int via) {
    return plan_push_hand_clear(s.view, s.a, PushGoal::kTarget, s.target, {}, s.state, s.q0, o,
                                margin, via);
  };
  const PushPlan today = s.plan(o);
  ASSERT_EQ(today.outcome, PlanOutcome::kPlanned) << today.message;
  ASSERT_GT(hand_lack(today.push, false, {&other}, margin), 0.0);  // the blocked first push
  // A low object: the jaws along the push (1.5 cm either side) pass the neighbour, all the way.
  const PushPlan along = clear(kFirstHandVia);
  ASSERT_EQ(along.outcome, PlanOutcome::kPlanned) << along.message;
  EXPECT_TRUE(along.hand_cleared);
  EXPECT_EQ(along.hand_fallback, 0.0);
  EXPECT_EQ(along.push.jaws, robot::JawLine::kAlong);
  EXPECT_FALSE(along.via);
  EXPECT_EQ(along.shortened, 0.0);
  EXPECT_EQ(hand_lack(along.push, true, {&other}, margin), 0.0);
  // A taller object (the jaw ahead would not pass over it): a push to a waypoint round the line
  // whose hand, and the next push's from there to the target, keep clear.
  obj.height = 0.06;
  const PushPlan via = clear(kFirstHandVia);
  ASSERT_EQ(via.outcome, PlanOutcome::kPlanned) << via.message;
  EXPECT_TRUE(via.hand_cleared);
  EXPECT_TRUE(via.via);
  EXPECT_NE(via.push.jaws, robot::JawLine::kAlong);
  EXPECT_EQ(via.blocked, 0.0);
  EXPECT_EQ(hand_lack(via.push, false, {&other}, margin), 0.0);
  EXPECT_GT((via.target - s.target).norm(), 0.02);  // the waypoint, not the target
  // No waypoints allowed (no push follows): nothing clears it, so the push as without the option.
  const PushPlan today_tall = s.plan(o);
  const PushPlan fallback = clear(0);
  ASSERT_EQ(fallback.outcome, PlanOutcome::kPlanned) << fallback.message;
  EXPECT_FALSE(fallback.hand_cleared);
  EXPECT_GT(fallback.hand_fallback, 0.0);  // blocked, or clear only shortened
  EXPECT_NEAR((fallback.push.start - today_tall.push.start).norm(), 0.0, 1e-12);
  EXPECT_NEAR((fallback.push.end - today_tall.push.end).norm(), 0.0, 1e-12);
  EXPECT_EQ(fallback.hand_blocked, 0.0);  // planned as the options say: no hand margin
  // Margin 0: plan_push itself.
  const PushPlan off = plan_push_hand_clear(s.view, s.a, PushGoal::kTarget, s.target, {}, s.state,
                                            s.q0, o, 0.0, kFirstHandVia);
  EXPECT_FALSE(off.hand_cleared);
  EXPECT_EQ(off.hand_fallback, 0.0);
  EXPECT_NEAR((off.push.start - today_tall.push.start).norm(), 0.0, 1e-12);
  // Bad input; first_hand_margin's bounds (the planner does not read it).
  EXPECT_THROW((void)plan_push_hand_clear(s.view, s.a, PushGoal::kTarget, s.target, {}, s.state,
                                          s.q0, o, 0.06, 0),
               Error);
  EXPECT_THROW((void)plan_push_hand_clear(s.view, s.a, PushGoal::kTarget, s.target, {}, s.state,
                                          s.q0, o, 0.01, -1),
               Error);
  PushPlanOptions bad = flat_options();
  bad.first_hand_margin = 0.06;
  EXPECT_THROW(bad.validate(), Error);
  bad.first_hand_margin = 0.01;
  EXPECT_NO_THROW(bad.validate());
}

TEST(PushPlanner, TheHandKeepsClearOfATallNeighbourByStoppingShortTurningTheJawsOrRaisingTheTip) {
  // The object (4 cm square) at (0.20, 0) pushed 16 cm along +y; a neighbour (3 cm square) at
  // (0.245, 0.1225): the object passes 1 cm from it, but the jaws across the push (3 cm either
  // side of the pusher) would run into it near the end of the push when it is as tall as they
  // hang low.
  NeighbourScene s({0.245, 0.1225});
  ASSERT_EQ(s.view.objects.size(), 2U);
  PutativeObject& obj = s.obj();
  PutativeObject& other = s.other();
  obj.height = 0.02;
  other.height = 0.09;
  const Eigen::Vector2d target = s.target;
  PushPlanOptions o = flat_options();
  o.target_spread = 0;  // every candidate on the line: only stopping short, the jaws or the tip
  // Off (the default): straight to the target, the jaws into the neighbour.
  const PushPlan direct = s.plan(o);
  ASSERT_EQ(direct.outcome, PlanOutcome::kPlanned) << direct.message;
  EXPECT_EQ(direct.shortened, 0.0);
  EXPECT_NEAR((direct.target - target).norm(), 0.0, 1e-12);
  EXPECT_GT(hand_lack(direct.push, false, {&other}, 0.01), 0.005);
  // hand_margin: stopped short where the jaws keep 1 cm from it (the pusher's end 1.5 cm behind
  // the jaws' front, the object's back 2 cm behind its centre: about 6 cm short).
  o.hand_margin = 0.01;
  const PushPlan shorter = s.plan(o);
  ASSERT_EQ(shorter.outcome, PlanOutcome::kPlanned) << shorter.message;
  EXPECT_EQ(shorter.blocked, 0.0);
  EXPECT_EQ(hand_lack(shorter.push, false, {&other}, 0.01), 0.0);
  EXPECT_GE(shorter.shortened, 0.05 - 1e-9);
  EXPECT_LE(shorter.shortened, 0.07 + 1e-9);
  EXPECT_EQ(shorter.push.jaws, robot::JawLine::kRobot);
  EXPECT_NEAR(shorter.push.height, o.tip_height, 1e-12);
  // A low neighbour (2 cm: the jaws pass over it): to the target.
  other.height = 0.02;
  const PushPlan over = s.plan(o);
  ASSERT_EQ(over.outcome, PlanOutcome::kPlanned) << over.message;
  EXPECT_EQ(over.shortened, 0.0);
  EXPECT_EQ(over.blocked, 0.0);
  other.height = 0.09;
  // hand_jaws: the object is low, so the jaws may lie along the push (1.5 cm either side): clear
  // all the way to the target.
  o.hand_jaws = true;
  const PushPlan along = s.plan(o);
  ASSERT_EQ(along.outcome, PlanOutcome::kPlanned) << along.message;
  EXPECT_EQ(along.push.jaws, robot::JawLine::kAlong);
  EXPECT_EQ(along.shortened, 0.0);
  EXPECT_EQ(along.blocked, 0.0);
  EXPECT_NEAR((along.target - target).norm(), 0.0, 1e-12);
  EXPECT_NE(along.message.find("jaws along"), std::string::npos) << along.message;
  // ...but not for an object the jaw ahead would run into (6 cm tall): stopped short again.
  obj.height = 0.06;
  const PushPlan tall = s.plan(o);
  ASSERT_EQ(tall.outcome, PlanOutcome::kPlanned) << tall.message;
  EXPECT_EQ(tall.push.jaws, robot::JawLine::kRobot);
  EXPECT_GT(tall.shortened, 0.04);
  // hand_raise: a 5 cm neighbour; the tip raised from 8 mm in 5 mm steps until the jaws (2.5 cm
  // above it, with the height margin) pass over it: 2.8 cm (at most half the object's 6 cm).
  o.hand_jaws = false;
  o.hand_raise = 0.03;
  other.height = 0.05;
  const PushPlan raised = s.plan(o);
  ASSERT_EQ(raised.outcome, PlanOutcome::kPlanned) << raised.message;
  EXPECT_NEAR(raised.push.height, 0.028, 1e-9);
  EXPECT_EQ(raised.shortened, 0.0);
  EXPECT_EQ(raised.blocked, 0.0);
  EXPECT_NE(raised.message.find("raised to 28 mm"), std::string::npos) << raised.message;
  // A neighbour too tall to pass over within the raise: stopped short at the usual tip.
  other.height = 0.09;
  const PushPlan high = s.plan(o);
  ASSERT_EQ(high.outcome, PlanOutcome::kPlanned) << high.message;
  EXPECT_GT(high.shortened, 0.04);
  EXPECT_EQ(high.blocked, 0.0);
  EXPECT_NEAR(high.push.height, o.tip_height, 1e-12);
  // Bounds.
  PushPlanOptions bad = flat_options();
  bad.hand_margin = 0.06;
  EXPECT_THROW(bad.validate(), Error);
  bad.hand_margin = -0.001;
  EXPECT_THROW(bad.validate(), Error);
  bad.hand_margin = 0;
  bad.hand_raise = 0.031;
  EXPECT_THROW(bad.validate(), Error);
  bad.hand_raise = -0.001;
  EXPECT_THROW(bad.validate(), Error);
}

TEST(PushPlanner, AShortenedPushWhoseHandIsNowhereClearKeepsItsShortenedEnd) {
  // The object at (0.20, 0), its target 16 cm along +y; a low neighbour 12 cm along the line
  // (the object at its target would lie on it: the sweep stops the push short) and a tall one
  // behind the object, which the hand meets at the start of every push along this line.
  const geometry::Camera cam = down_camera();
  std::vector<cv::KeyPoint> f;
  add_feature_square(f, cam, {0.20, 0.0}, 0.02);
  add_feature_square(f, cam, {0.20, 0.12}, 0.015);
  add_feature_square(f, cam, {0.20, -0.065}, 0.015);
  PlanningView view = make_planning_view(f, cam, {}, flat_options());
  ASSERT_EQ(view.objects.size(), 3U)
      << view.objects[0].centre.transpose() << " / " << view.objects[1].centre.transpose();
  const int a = object_nearest(view, {0.20, 0.0});
  PutativeObject& obj = view.objects[static_cast<std::size_t>(a)];
  obj.height = 0.02;
  PutativeObject& ahead =
      view.objects[static_cast<std::size_t>(object_nearest(view, {0.20, 0.12}))];
  ahead.height = 0.02;
  PutativeObject& beside =
      view.objects[static_cast<std::size_t>(object_nearest(view, {0.20, -0.065}))];
  beside.height = 0.12;
  robot::ArmState state(arm());
  const robot::JointVector q0 = robot::JointVector::Zero();
  const Eigen::Vector2d target(0.20, 0.16);
  PushPlanOptions o = flat_options();
  o.target_spread = 0;  // every candidate on the line
  o.sweep_margin = 0.01;
  // The sweep alone: stopped short of the low neighbour.
  const PushPlan sweep = plan_push(view, a, PushGoal::kTarget, target, {}, state, q0, o);
  ASSERT_EQ(sweep.outcome, PlanOutcome::kPlanned) << sweep.message;
  EXPECT_GT(sweep.shortened, 0.04);
  // With the hand too (session 22): no point of the line is clear of both, so the full push is
  // made, into the low neighbour.
  o.hand_margin = 0.01;
  const PushPlan full = plan_push(view, a, PushGoal::kTarget, target, {}, state, q0, o);
  ASSERT_EQ(full.outcome, PlanOutcome::kPlanned) << full.message;
  EXPECT_EQ(full.shortened, 0.0);
  EXPECT_GT(full.blocked, 0.0);
  EXPECT_GT(hand_lack(full.push, false, {&beside}, 0.01), 0.0);
  // hand_keep_short: the sweep's shortened end is kept, its hand's shortfall counted.
  o.hand_keep_short = true;
  const PushPlan kept = plan_push(view, a, PushGoal::kTarget, target, {}, state, q0, o);
  ASSERT_EQ(kept.outcome, PlanOutcome::kPlanned) << kept.message;
  EXPECT_NEAR(kept.shortened, sweep.shortened, 1e-9);
  EXPECT_NEAR((kept.target - sweep.target).norm(), 0.0, 1e-9);
  EXPECT_GT(kept.blocked, 0.0);
  EXPECT_LT(kept.blocked, full.blocked);
  EXPECT_NEAR(kept.blocked, hand_lack(kept.push, false, {&beside}, 0.01), 1e-9);
  // Without the sweep margin there is nothing to keep: the option changes nothing.
  o.sweep_margin = 0;
  const PushPlan no_sweep = plan_push(view, a, PushGoal::kTarget, target, {}, state, q0, o);
  o.hand_keep_short = false;
  const PushPlan no_sweep_off = plan_push(view, a, PushGoal::kTarget, target, {}, state, q0, o);
  EXPECT_NEAR((no_sweep.target - no_sweep_off.target).norm(), 0.0, 1e-12);
  EXPECT_EQ(no_sweep.shortened, no_sweep_off.shortened);
}

TEST(PushPlanner, ABlockedLineIsGoneRoundThroughAFanOfWaypoints) {
  // The object at (0.20, 0), its target 16 cm along +y, a neighbour on the line 11 cm along:
  // with sweep_margin alone the push stops short of it (8 cm short scores less than the margin's
  // 1 cm of blocking); with via_blocked it goes round through a waypoint, both legs clear, so
  // that the next push reaches the target.
  NeighbourScene s({0.20, 0.11});
  ASSERT_EQ(s.view.objects.size(), 2U);
  const auto& obj = s.obj();
  const auto& other = s.other();
  const Eigen::Vector2d target = s.target;
  PushPlanOptions o = flat_options();
  o.sweep_margin = 0.01;
  const PushPlan short_push = s.plan(o);
  ASSERT_EQ(short_push.outcome, PlanOutcome::kPlanned) << short_push.message;
  EXPECT_FALSE(short_push.via);
  EXPECT_GT(short_push.shortened, 0.05) << short_push.message << " blocked " << short_push.blocked;
  o.via_blocked = 24;
  const PushPlan round = s.plan(o);
  ASSERT_EQ(round.outcome, PlanOutcome::kPlanned) << round.message;
  EXPECT_TRUE(round.via);
  EXPECT_EQ(round.blocked, 0.0);
  EXPECT_EQ(round.shortened, 0.0);
  EXPECT_NE(round.message.find("waypoint"), std::string::npos) << round.message;
  // The waypoint is one of the fan's: 20-100 degrees off the line and 4-10 cm from the centre,
  // or beside the target (the second leg 20-100 degrees off the line, 4-10 cm long). Here the
  // neighbour lies too near the target for a way round from the start: beside the target.
  const Eigen::Vector2d line = (target - obj.centre).normalized();
  const Eigen::Vector2d w = target - round.target;
  const double off = std::acos(w.normalized().dot(line));
  EXPECT_GE(off, 20.0 * std::numbers::pi / 180.0 - 1e-9);
  EXPECT_LE(off, 100.0 * std::numbers::pi / 180.0 + 1e-9);
  EXPECT_GE(w.norm(), 0.04 - 1e-9);
  EXPECT_LE(w.norm(), 0.10 + 1e-9);
  // Both legs' swept regions keep the margin from the neighbour.
  std::vector<Eigen::Vector2d> moved = obj.hull;
  for (auto& h : moved) h += round.target - obj.centre;
  EXPECT_GE(polygon_distance(sweep_region(obj.hull, obj.centre, round.target), other.hull),
            o.sweep_margin - 1e-6);
  EXPECT_GE(polygon_distance(sweep_region(moved, round.target, target), other.hull),
            o.sweep_margin - 1e-6);
  // The fan is fixed: another plan seed picks the same waypoint.
  o.seed = 7;
  const PushPlan again = s.plan(o);
  ASSERT_EQ(again.outcome, PlanOutcome::kPlanned) << again.message;
  EXPECT_NEAR((again.target - round.target).norm(), 0.0, 1e-12);
  // A clear line: no waypoint, the same plan as without the option.
  const PlanningView clear = object_and_neighbour(s.cam, {0.30, 0.08});
  const int b = object_nearest(clear, {0.20, 0.0});
  const PushPlan direct = s.plan(o, clear, b);
  o.via_blocked = 0;
  const PushPlan direct_off = s.plan(o, clear, b);
  ASSERT_EQ(direct.outcome, PlanOutcome::kPlanned) << direct.message;
  EXPECT_FALSE(direct.via);
  EXPECT_NEAR((direct.target - direct_off.target).norm(), 0.0, 1e-12);
  EXPECT_EQ(direct.sampled, direct_off.sampled);
  // A neighbour at the target (no way round reaches it clear): still stopped short.
  const PlanningView at = object_and_neighbour(s.cam, {0.20, 0.12});
  const int c = object_nearest(at, {0.20, 0.0});
  o.via_blocked = 24;
  const PushPlan stuck = s.plan(o, at, c);
  ASSERT_EQ(stuck.outcome, PlanOutcome::kPlanned) << stuck.message;
  EXPECT_FALSE(stuck.via);
  EXPECT_GT(stuck.shortened, 0.04);
  // Bounds.
  PushPlanOptions bad = flat_options();
  bad.via_blocked = -1;
  EXPECT_THROW(bad.validate(), Error);
  bad.via_blocked = 201;
  EXPECT_THROW(bad.validate(), Error);
}

TEST(PushPlanner, ATargetAgainstANeighbourBecomesTheNearestPointAStraightPushReachesClear) {
  // The object at (0.20, 0), its target 16 cm along +y, a neighbour 19 cm along: the object put
  // at the target would lie against the neighbour, so reaching it pushes the neighbour too.
  // Without free_target_margin the planner pushes it to the target; with it, to the nearest
  // point whose straight push keeps the margin (here short of the target on the same side).
  NeighbourScene s({0.20, 0.19});
  ASSERT_EQ(s.view.objects.size(), 2U);
  const auto& obj = s.obj();
  const auto& other = s.other();
  const Eigen::Vector2d target = s.target;
  const auto at = [&](const Eigen::Vector2d& p) {
    std::vector<Eigen::Vector2d> h = obj.hull;
    for (auto& x : h) x += p - obj.centre;
    return h;
  };
  const double margin = 0.01;
  ASSERT_LT(polygon_distance(at(target), other.hull), margin);
  PushPlanOptions o = flat_options();
  o.target_spread = 0;  // the planned target is the goal itself
  const PushPlan direct = s.plan(o);
  ASSERT_EQ(direct.outcome, PlanOutcome::kPlanned) << direct.message;
  EXPECT_EQ(direct.target_moved, 0.0);
  EXPECT_NEAR((direct.target - target).norm(), 0.0, 1e-12);
  o.free_target_margin = margin;
  const PushPlan moved = s.plan(o);
  ASSERT_EQ(moved.outcome, PlanOutcome::kPlanned) << moved.message;
  EXPECT_GT(moved.target_moved, 0.0);
  EXPECT_NEAR((moved.target - target).norm(), moved.target_moved, 1e-12);
  EXPECT_NE(moved.message.find("lies against"), std::string::npos) << moved.message;
  // The straight push there keeps the margin (its swept region and the footprint at its end)...
  EXPECT_EQ(sweep_lack(obj.hull, obj.centre, moved.target, {other.hull}, margin, false, 0.0), 0.0);
  EXPECT_GE(polygon_distance(at(moved.target), other.hull), margin - 1e-9);
  // ...and it is the nearest such point of the search (one ring step nearer, none is).
  for (int k = 0; k < kFreeTargetAngles; ++k) {
    const double a = 2.0 * std::numbers::pi * k / kFreeTargetAngles;
    const Eigen::Vector2d p =
        target + (moved.target_moved - kFreeTargetStep) * Eigen::Vector2d(std::cos(a), std::sin(a));
    EXPECT_GT(sweep_lack(obj.hull, obj.centre, p, {other.hull}, margin, false, 0.0), 0.0) << k;
  }
  EXPECT_LE(moved.target_moved, 0.03);
  // A clear target: the same plan as without the option.
  const PlanningView clear = object_and_neighbour(s.cam, {0.30, 0.08});
  const int b = object_nearest(clear, {0.20, 0.0});
  const PushPlan with = s.plan(o, clear, b);
  o.free_target_margin = 0;
  const PushPlan without = s.plan(o, clear, b);
  ASSERT_EQ(with.outcome, PlanOutcome::kPlanned) << with.message;
  EXPECT_EQ(with.target_moved, 0.0);
  EXPECT_NEAR((with.target - without.target).norm(), 0.0, 1e-12);
  EXPECT_NEAR((with.push.start - without.push.start).norm(), 0.0, 1e-12);
  // Bounds.
  PushPlanOptions bad = flat_options();
  bad.free_target_margin = -0.001;
  EXPECT_THROW(bad.validate(), Error);
  bad.free_target_margin = 0.06;
  EXPECT_THROW(bad.validate(), Error);
}

// Depth points (table frame, m) of a toy bicycle centred at `c`, its wheels along x: two wheels
// (discs of radius 4 cm in the x-z plane, 3 cm thick) at x = +-5.5 cm and a frame bar 5.7-7.3 cm
// up between them (the catalogue's bike), every 2 mm.
std::vector<Eigen::Vector3d> bike_points(const Eigen::Vector2d& c) {
  std::vector<Eigen::Vector3d> p;
  for (double x = -0.1; x <= 0.1; x += 0.002) {
    for (double z = 0.0; z <= 0.08; z += 0.002) {
      const double w = std::abs(x) - 0.055;
      const bool wheel = w * w + (z - 0.04) * (z - 0.04) <= 0.04 * 0.04;
      const bool frame = std::abs(x) <= 0.05 && z >= 0.057 && z <= 0.073;
      for (double y = -0.015; y <= 0.0151; y += 0.005) {
        if (wheel || (frame && std::abs(y) <= 0.008)) p.emplace_back(c.x() + x, c.y() + y, z);
      }
    }
  }
  return p;
}

// A box's depth points (its top and sides), every 2 mm.
std::vector<Eigen::Vector3d> box_points(const Eigen::Vector2d& c, double hx, double hy, double h) {
  std::vector<Eigen::Vector3d> p;
  for (double x = -hx; x <= hx + 1e-9; x += 0.002) {
    for (double y = -hy; y <= hy + 1e-9; y += 0.002) {
      for (double z = kObjectLeastHeight; z <= h + 1e-9; z += 0.002) {
        p.emplace_back(c.x() + x, c.y() + y, z);
      }
    }
  }
  return p;
}

TEST(PushContact, APushAcrossTheWheelsMeetsTheBikeHighAndTipsItAlongTheWheelsItSlides) {
  const Eigen::Vector2d c(0.30, 0.05);
  const std::vector<Eigen::Vector3d> bike = bike_points(c);
  const double tip = 0.008;
  // Along the wheels' line: the first wheel's rim is met (the jaws' disc, the robot's roll
  // unknown, 3 cm ahead of the rod, meets it from 3.8 cm up), its foot reaches 9 cm ahead: it
  // slides.
  const PushContact along = push_contact(bike, c, {1, 0}, tip);
  EXPECT_TRUE(along.met);
  EXPECT_GT(along.base, 0.08);
  EXPECT_LT(along.ratio, 0.5);
  // The jaws across the push pass beside the 3 cm thick wheels: the rod meets the rim, lower.
  const PushContact rod = push_contact(bike, c, {1, 0}, tip, robot::JawLine::kAcross);
  EXPECT_FALSE(rod.jaws);
  EXPECT_LT(rod.height, along.height + 1e-9);
  EXPECT_LT(rod.ratio, 0.5);
  // Across, through the middle: the rod passes between the wheels under the frame, and the jaws
  // (across, 2-3 cm to either side of the rod) meet the wheels' faces 3.8 cm up; the foot
  // reaches 1.5 cm ahead: it tips (friction 0.8 x 3.8 / 1.5 = 2).
  const PushContact across = push_contact(bike, c, {0, 1}, tip, robot::JawLine::kAcross);
  EXPECT_TRUE(across.met);
  EXPECT_TRUE(across.jaws);
  EXPECT_NEAR(across.height, tip + kFingerDrop, 0.0025);
  EXPECT_NEAR(across.base, 0.015, 0.0025);
  EXPECT_GT(across.ratio, 1.5);
  // The jaws along the push: the one ahead meets the frame and the wheels' inner edges.
  EXPECT_GT(push_contact(bike, c, {0, 1}, tip, robot::JawLine::kAlong).ratio, 1.5);
  // Shifted 5 cm onto a wheel the rod meets the wheel's face at its tip, but the jaws beside it
  // meet the same face 7 mm sooner, 3.8 cm up: this hand tips the bike across its wheels
  // wherever it aims.
  const PushContact wheel =
      push_contact(bike, c, {0, 1}, tip, robot::JawLine::kAcross, false, 0.05);
  EXPECT_TRUE(wheel.jaws);
  EXPECT_GT(wheel.ratio, 1.5);
  // The camera sees one side: half the points (those toward -y) give the same verdicts.
  std::vector<Eigen::Vector3d> half;
  for (const auto& p : bike) {
    if (p.y() <= c.y()) half.push_back(p);
  }
  EXPECT_GT(push_contact(half, c, {0, -1}, tip, robot::JawLine::kAcross).ratio, 1.5);
  EXPECT_LT(push_contact(half, c, {1, 0}, tip).ratio, 0.5);
  // A book (the catalogue's, 15 x 21 x 3.5 cm) slides every way; a 6 mm thin box, lower than
  // the pusher's lowest point (its tip 8 mm up), is not met.
  const std::vector<Eigen::Vector3d> book = box_points(c, 0.075, 0.105, 0.035);
  for (double a = 0; a < 6.28; a += 0.5) {
    const PushContact b = push_contact(book, c, {std::cos(a), std::sin(a)}, tip);
    EXPECT_TRUE(b.met);
    EXPECT_LT(b.ratio, 0.5) << a;
  }
  const PushContact cd = push_contact(box_points(c, 0.06, 0.06, 0.006), c, {1, 0}, tip);
  EXPECT_FALSE(cd.met);
  EXPECT_EQ(cd.ratio, 0.0);
  EXPECT_FALSE(push_contact({}, c, {1, 0}, tip).met);
  // Bad input.
  EXPECT_THROW((void)push_contact(bike, c, {1, 1}, tip), Error);
  EXPECT_THROW((void)push_contact(bike, c, {1, 0}, -0.001), Error);
}

TEST(PushPlanner, ToppleRatioLeavesOutPushesThatWouldTipALeggedObject) {
  // The toy bicycle of boxes (two 8 x 3 x 8 cm wheels, a frame bar 5.7-7.3 cm up between them) at
  // (0.24, 0), seen in depth by the oblique camera: pushed 10 cm across its wheels (+y), the
  // pusher would pass between the wheels under the frame; along them (+x) it meets a wheel.
  const geometry::Camera cam = oblique_camera();
  const Eigen::Vector2d c(0.24, 0.0);
  const std::vector<test::DepthBox> boxes{{{c.x() - 0.055, c.y()}, 0.04, 0.015, 0.08, 0.0},
                                          {{c.x() + 0.055, c.y()}, 0.04, 0.015, 0.08, 0.0},
                                          {c, 0.05, 0.008, 0.073, 0.0, 0.057}};
  cv::Mat img(480, 640, CV_8U, cv::Scalar(128));
  for (const auto& b : boxes) draw_checkered_box(img, cam, b.c, b.hx, b.hy, b.h, b.yaw);
  const cv::Mat1f depth = test::render_boxes_depth(cam, boxes);
  PushPlanOptions o;
  const PlanningView view = make_planning_view(textured_points(img, o), cam, {}, o, depth);
  ASSERT_EQ(view.objects.size(), 1U);
  ASSERT_TRUE(view.objects[0].height.has_value());
  robot::ArmState state(arm());
  const robot::JointVector q0 = robot::JointVector::Zero();
  const auto plan = [&](const Eigen::Vector2d& target) {
    return plan_push(view, 0, PushGoal::kTarget, target, {}, state, q0, o);
  };
  const Eigen::Vector2d across = view.objects[0].centre + Eigen::Vector2d(0.0, 0.10);
  const Eigen::Vector2d along = view.objects[0].centre + Eigen::Vector2d(0.10, 0.0);
  // Off (the default): both planned, nothing judged.
  const PushPlan off = plan(across);
  ASSERT_EQ(off.outcome, PlanOutcome::kPlanned) << off.message;
  EXPECT_EQ(off.rejected_topple, 0);
  EXPECT_EQ(off.topple, 0.0);
  ASSERT_EQ(plan(along).outcome, PlanOutcome::kPlanned);
  // On: across is not planned (every sampled push would tip it), along is.
  o.topple_ratio = 1.0;
  const PushPlan no = plan(across);
  EXPECT_EQ(no.outcome, PlanOutcome::kUnreachable) << no.message;
  EXPECT_GT(no.rejected_topple, 0);
  EXPECT_NE(no.message.find("tip the object over"), std::string::npos) << no.message;
  const PushPlan yes = plan(along);
  ASSERT_EQ(yes.outcome, PlanOutcome::kPlanned) << yes.message;
  EXPECT_GT(yes.topple, 0.0);
  EXPECT_LE(yes.topple, 1.0);
  EXPECT_EQ(yes.offset, 0.0);
  // Without depth the option does nothing.
  PlanningView plain = view;
  plain.depth = cv::Mat();
  const PushPlan blind = plan_push(plain, 0, PushGoal::kTarget, across, {}, state, q0, o);
  EXPECT_EQ(blind.rejected_topple, 0);
  // Bounds.
  PushPlanOptions bad;
  bad.topple_ratio = -0.1;
  EXPECT_THROW(bad.validate(), Error);
  bad.topple_ratio = 1.0;
  bad.topple_offset = 0.06;
  EXPECT_THROW(bad.validate(), Error);
}

TEST(PushPlanner, ToppleOffsetTurnsTheJawsAcrossSoThatTheRodMeetsANarrowTallBoxLow) {
  // A 7 x 3 x 15 cm box at (0.24, 0) pushed 10 cm along its length (+x): with the robot's own
  // roll (unknown) the jaws may reach 3 cm ahead of the rod and meet its end 3.8 cm up
  // (0.8 x 3.8 / 3.5 = 0.87); turned across the push they pass either side of it (2-3 cm off the
  // line, the box 1.5 cm) and the rod meets it at its foot.
  const geometry::Camera cam = oblique_camera();
  const Eigen::Vector2d c(0.24, 0.0);
  cv::Mat img(480, 640, CV_8U, cv::Scalar(128));
  draw_checkered_box(img, cam, c, 0.035, 0.015, 0.15, 0.0);
  const cv::Mat1f depth = render_box_depth(cam, c, 0.035, 0.015, 0.15, 0.0);
  PushPlanOptions o;
  const PlanningView view = make_planning_view(textured_points(img, o), cam, {}, o, depth);
  ASSERT_EQ(view.objects.size(), 1U);
  robot::ArmState state(arm());
  const robot::JointVector q0 = robot::JointVector::Zero();
  const Eigen::Vector2d target = view.objects[0].centre + Eigen::Vector2d(0.10, 0.0);
  o.topple_ratio = 0.7;
  const PushPlan robot_roll = plan_push(view, 0, PushGoal::kTarget, target, {}, state, q0, o);
  EXPECT_EQ(robot_roll.outcome, PlanOutcome::kUnreachable) << robot_roll.message;
  EXPECT_GT(robot_roll.rejected_topple, 0);
  o.topple_offset = 0.02;
  const PushPlan turned = plan_push(view, 0, PushGoal::kTarget, target, {}, state, q0, o);
  ASSERT_EQ(turned.outcome, PlanOutcome::kPlanned) << turned.message;
  EXPECT_EQ(turned.push.jaws, robot::JawLine::kAcross);
  EXPECT_EQ(turned.offset, 0.0);
  EXPECT_LT(turned.topple, 0.5);
  EXPECT_NE(turned.message.find("jaws across"), std::string::npos) << turned.message;
}

}  // namespace
}  // namespace proprio::planning
