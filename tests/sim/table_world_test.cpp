// The robot's table as the learner's world: backdrops (plain, photo, moving video with
// distractors) advancing with the robot's clock, clutter on the table, and the arm's transit
// between pushes simulated at a safe height.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <numbers>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "proprio/core/error.hpp"
#include "proprio/sim/simulated_robot.hpp"

namespace proprio::sim {
namespace {

TableOptions table(Background background) {
  TableOptions o;
  o.objects = {"book", "bottle", "cd", "giraffe"};
  o.clutter.assign(1, '3');
  o.background = background;
  o.seed = 5;
  o.width = 320;
  o.height = 240;
  return o;
}

double mean_abs_diff(const cv::Mat& a, const cv::Mat& b) {
  cv::Mat d;
  cv::absdiff(a, b, d);
  const cv::Scalar m = cv::mean(d);
  return (m[0] + m[1] + m[2]) / 3.0;
}

void dump(const char* name, const cv::Mat& image) {
  if (const char* dir = std::getenv("PROPRIO_DUMP_DIR")) {
    std::string path(dir);
    path += '/';
    path += name;
    path += ".png";
    cv::imwrite(path, image);
  }
}

TEST(TableWorld, MovingBackdropChangesWithTimeAndPlainDoesNot) {
  const ObjectCatalogue cat = ObjectCatalogue::load_default();
  SimulatedRobot moving(table(Background::kMoving), cat);
  const cv::Mat a = moving.look().image;
  moving.wait(0.5);
  const cv::Mat b = moving.look().image;
  dump("moving_a", a);
  dump("moving_b", b);
  EXPECT_GT(mean_abs_diff(a, b), 0.3);
  // Plain: the view stays as it was while the robot waits (but for a few pixels where two
  // crowded objects still settle against each other).
  SimulatedRobot plain(table(Background::kPlain), cat);
  const cv::Mat c = plain.look().image;
  plain.wait(0.5);
  const cv::Mat d = plain.look().image;
  dump("plain", c);
  EXPECT_LT(cv::countNonZero(cv::Mat(c != d).reshape(1)), 10);
  EXPECT_LT(mean_abs_diff(c, d), 0.01);
  SimulatedRobot photo(table(Background::kPhoto), cat);
  const cv::Mat e = photo.look().image;
  dump("photo", e);
  EXPECT_GT(mean_abs_diff(c, e), 0.3);  // the photograph is seen
}

TEST(TableWorld, SameSeedSameImages) {
  const ObjectCatalogue cat = ObjectCatalogue::load_default();
  SimulatedRobot a(table(Background::kMoving), cat);
  SimulatedRobot b(table(Background::kMoving), cat);
  a.wait(0.7);
  b.wait(0.7);
  const cv::Mat ia = a.look().image;
  const cv::Mat ib = b.look().image;
  EXPECT_EQ(cv::countNonZero(cv::Mat(ia != ib).reshape(1)), 0);
  EXPECT_DOUBLE_EQ(a.time(), b.time());
}

TEST(TableWorld, DistractorsStayBehindTheWorkAreaAndAreInTheMasks) {
  const ObjectCatalogue cat = ObjectCatalogue::load_default();
  SimulatedRobot robot(table(Background::kMoving), cat);
  const ScatterRegion region;
  int distractors = 0;
  int seen = 0;
  for (int k = 0; k < 14; ++k) {  // over a whole slide (1 / 0.15 Hz = 6.7 s)
    robot.wait(0.5);
    const cv::Mat mask = robot.ground_truth_mask();
    distractors = 0;
    for (const ObjectTruth& o : robot.ground_truth()) {
      if (o.role != TableRole::kDistractor) continue;
      ++distractors;
      // footprint_radius bounds the object about its origin (not its box centre, which turns
      // about the origin as the distractor spins).
      EXPECT_GT(o.position.y() - o.footprint_radius, region.max.y()) << o.name;
      EXPECT_TRUE(o.on_table) << o.name;
      if (cv::countNonZero(mask == o.id) > 20) ++seen;
    }
  }
  EXPECT_EQ(distractors, 2);
  EXPECT_GT(seen, 10);  // in view most of the time
}

TEST(TableWorld, HoldingStillTheDistractorsMoveOnAndTheTableAndTheArmDoNot) {
  const ObjectCatalogue cat = ObjectCatalogue::load_default();
  SimulatedRobot robot(table(Background::kMoving), cat);
  robot.wait(1.0);  // anywhere on the slide
  const std::vector<ObjectTruth> before = robot.ground_truth();
  const robot::JointVector q = robot.joints();
  const double t0 = robot.time();
  robot.hold_still(0.3);
  EXPECT_NEAR(robot.time() - t0, 0.3, 0.002 + 1e-9);  // within a physics step (2 ms)
  EXPECT_LT((robot.joints() - q).cwiseAbs().maxCoeff(), 1e-4);
  const std::vector<ObjectTruth> after = robot.ground_truth();
  ASSERT_EQ(after.size(), before.size());
  int distractors = 0;
  constexpr double kPi = std::numbers::pi;
  for (std::size_t i = 0; i < after.size(); ++i) {
    const double shift = (after[i].position - before[i].position).norm();
    if (after[i].role == TableRole::kDistractor) {
      ++distractors;
      // They slide (at most 0.3 m/s) and spin (0.8 rad/s: 0.24 rad in 0.3 s).
      const double turn = std::abs(std::remainder(after[i].yaw - before[i].yaw, 2 * kPi));
      EXPECT_TRUE(shift > 0.005 || turn > 0.2) << after[i].name << " " << shift << " " << turn;
    } else {
      EXPECT_LT(shift, 1e-3) << after[i].name;
    }
  }
  EXPECT_EQ(distractors, 2);
  // Bad times throw and nothing happens.
  const double t1 = robot.time();
  for (const double bad : {-0.1, 10.5, std::nan(""), HUGE_VAL}) {
    EXPECT_THROW(robot.hold_still(bad), Error) << bad;
  }
  EXPECT_DOUBLE_EQ(robot.time(), t1);
  robot.hold_still(0);
  EXPECT_DOUBLE_EQ(robot.time(), t1);
}

TEST(TableWorld, ClutterIsOnTheTableWithItsRole) {
  const ObjectCatalogue cat = ObjectCatalogue::load_default();
  SimulatedRobot robot(table(Background::kPlain), cat);
  const cv::Mat mask = robot.ground_truth_mask();
  int objects = 0;
  int clutter = 0;
  for (const ObjectTruth& o : robot.ground_truth()) {
    if (o.role == TableRole::kObject) ++objects;
    if (o.role != TableRole::kClutter) continue;
    ++clutter;
    EXPECT_TRUE(o.on_table) << o.name;
    EXPECT_GT(cv::countNonZero(mask == o.id), 30) << o.name;
    for (const char* n : {"book", "bottle", "cd", "giraffe"}) EXPECT_NE(o.name, n);
  }
  EXPECT_EQ(objects, 4);
  EXPECT_EQ(clutter, 3);
  EXPECT_EQ(robot.scatter(3).size(), 7U);  // the clutter is scattered with the objects

  TableOptions named = table(Background::kPlain);
  named.clutter = "mug, box";
  SimulatedRobot r2(named, cat);
  EXPECT_EQ(r2.ground_truth().at(4).name, "mug");
  EXPECT_EQ(r2.ground_truth().at(5).role, TableRole::kClutter);
  named.clutter = "book";  // already an object
  EXPECT_THROW(SimulatedRobot(named, cat), Error);
  named.clutter = "teapot";
  EXPECT_THROW(SimulatedRobot(named, cat), Error);
  named.clutter = "5";  // 9 on the table
  EXPECT_THROW(named.validate(), Error);
}

TEST(TableWorld, TransitOverAnObjectDoesNotMoveIt) {
  const ObjectCatalogue cat = ObjectCatalogue::load_default();
  TableOptions o;
  o.objects = {"mug", "cd"};
  o.width = 320;
  o.height = 240;
  SimulatedRobot robot(o, cat);
  // The mug (10 cm tall) on the line from the arm's base to the push's start, the CD aside.
  robot.place({{"mug", {0.24, 0.08}, 0.0}, {"cd", {0.30, -0.22}, 0.0}});
  const auto before = robot.ground_truth();
  robot::TablePush push;
  push.start = {0.40, 0.13};
  push.end = {0.44, 0.13};
  const double t0 = robot.time();
  const robot::PushReport r = robot.push(push, {});
  EXPECT_FALSE(r.touched);
  EXPECT_TRUE(robot.last_push_contacts().empty());
  const auto after = robot.ground_truth();
  for (std::size_t i = 0; i < before.size(); ++i) {
    EXPECT_LT((after[i].position - before[i].position).norm(), 1e-3) << after[i].name;
    EXPECT_TRUE(after[i].upright) << after[i].name;
  }
  // The transit takes the robot's time: seconds beyond the push's own (4 cm at 5 cm/s, lowering
  // and lifting 6 cm at 10 cm/s each).
  EXPECT_GT(robot.time() - t0, 3.0);
  EXPECT_NEAR(r.seconds, robot.time() - t0, 1e-9);
  // The arm is back out of the view.
  const robot::Look look = robot.look();
  EXPECT_LT(cv::countNonZero(look.arm_mask), 320 * 240 / 8);
}

}  // namespace
}  // namespace proprio::sim
