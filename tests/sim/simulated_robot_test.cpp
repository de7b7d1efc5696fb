// The simulated robot behind robot::Robot: a persistent table, pushes that move what they touch,
// the touch flag, episodes without ground truth, re-scattering.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "proprio/core/error.hpp"
#include "proprio/episode/episode.hpp"
#include "proprio/sim/simulated_robot.hpp"
#include "sim_test_util.hpp"

namespace proprio::sim {
namespace {
namespace fs = std::filesystem;

TableOptions small_table() {
  TableOptions o;
  o.objects = {"book", "mug", "calculator"};
  o.seed = 3;
  o.width = 320;
  o.height = 240;
  return o;
}

const ObjectTruth& truth_of(const std::vector<ObjectTruth>& t, const std::string& name) {
  for (const ObjectTruth& o : t) {
    if (o.name == name) return o;
  }
  throw Error("no object " + name);
}

// A 6 cm push of `o` outward along its line from the arm's base, starting 3 cm behind its edge.
robot::TablePush outward_push(const ObjectTruth& o) {
  const Eigen::Vector2d c = o.centre.head<2>();
  const Eigen::Vector2d n = c.normalized();
  robot::TablePush push;
  push.start = c - n * (o.footprint_radius + 0.03);
  push.end = c - n * 0.02 + n * 0.06;
  return push;
}

// A recording at 10 frames/s into a fresh `dir`.
robot::PushRecording recording_into(const fs::path& dir) {
  fs::remove_all(dir);
  robot::PushRecording rec;
  rec.episode_dir = dir;
  rec.fps = 10;
  return rec;
}

TEST(ScatterPlacements, AreSeededAndDoNotOverlap) {
  const ObjectCatalogue cat = ObjectCatalogue::load_default();
  std::vector<const ObjectType*> types;
  for (const char* n : {"book", "mug", "cd", "box", "bottle"}) types.push_back(&cat.get(n));
  const ScatterRegion region;
  const auto a = scatter_placements(types, region, 11);
  const auto b = scatter_placements(types, region, 11);
  const auto c = scatter_placements(types, region, 12);
  ASSERT_EQ(a.size(), types.size());
  EXPECT_EQ(a[2].position, b[2].position);
  EXPECT_NE(a[2].position, c[2].position);
  for (std::size_t i = 0; i < a.size(); ++i) {
    // Apart by more than their narrowest extents (the boxes are yawed).
    for (std::size_t j = 0; j < i; ++j) {
      EXPECT_GE((a[i].position - a[j].position).norm(),
                types[i]->half_extents().head<2>().minCoeff() +
                    types[j]->half_extents().head<2>().minCoeff());
    }
  }
}

// Separating-axis overlap of two yawed footprint boxes grown by `gap` / 2 each (0: apart).
double box_overlap(const ObjectType& ta, const Placement& a, const ObjectType& tb,
                   const Placement& b, double gap) {
  const Eigen::Matrix2d ra = Eigen::Rotation2Dd(a.yaw).toRotationMatrix();
  const Eigen::Matrix2d rb = Eigen::Rotation2Dd(b.yaw).toRotationMatrix();
  const Eigen::Vector2d ca = a.position + ra * ta.center().head<2>();
  const Eigen::Vector2d cb = b.position + rb * tb.center().head<2>();
  const Eigen::Vector2d ha = ta.half_extents().head<2>();
  const Eigen::Vector2d hb = tb.half_extents().head<2>();
  double least = 1e9;
  for (const Eigen::Matrix2d* r : {&ra, &rb}) {
    for (int k = 0; k < 2; ++k) {
      const Eigen::Vector2d axis = r->col(k);
      const double ea =
          ha.x() * std::abs(axis.dot(ra.col(0))) + ha.y() * std::abs(axis.dot(ra.col(1)));
      const double eb =
          hb.x() * std::abs(axis.dot(rb.col(0))) + hb.y() * std::abs(axis.dot(rb.col(1)));
      least = std::min(least, ea + eb + gap - std::abs(axis.dot(cb - ca)));
    }
  }
  return std::max(0.0, least);
}

// The default world of `proprio learn` (4 objects and 3 of clutter) fits the default region
// without overlap on every seed tried: no blobs merged from the start.
TEST(ScatterPlacements, SevenObjectsOfTheDefaultWorldHaveRoom) {
  const ObjectCatalogue cat = ObjectCatalogue::load_default();
  std::vector<const ObjectType*> types;
  for (const char* n : {"book", "bottle", "cd", "giraffe", "mug", "rabbit", "calculator"}) {
    types.push_back(&cat.get(n));
  }
  const ScatterRegion region;
  for (std::uint64_t seed = 1; seed <= 12; ++seed) {
    const auto p = scatter_placements(types, region, seed);
    ASSERT_EQ(p.size(), types.size());
    for (std::size_t i = 0; i < p.size(); ++i) {
      EXPECT_EQ(p[i].name, types[i]->name);
      EXPECT_GE(p[i].position.norm(), region.base_clearance) << "seed " << seed;
      for (std::size_t j = 0; j < i; ++j) {
        // Apart by at least most of the gap (the placer's box is the same up to rounding).
        EXPECT_EQ(box_overlap(*types[i], p[i], *types[j], p[j], 0.5 * region.gap), 0.0)
            << "seed " << seed << ": " << p[i].name << " and " << p[j].name;
      }
    }
  }
}

TEST(SimulatedRobot, LooksPushesAndKeepsTheScene) {
  const ObjectCatalogue cat = ObjectCatalogue::load_default();
  SimulatedRobot robot(small_table(), cat);
  const robot::Look look = robot.look();
  ASSERT_EQ(look.image.cols, 320);
  ASSERT_EQ(look.image.rows, 240);
  EXPECT_EQ(look.camera.width, 320);
  if (const char* dump = std::getenv("PROPRIO_DUMP_LOOK")) cv::imwrite(dump, look.image);
  // Every object is in view and none is hidden by the parked arm.
  const cv::Mat mask = robot.ground_truth_mask();
  for (const ObjectTruth& o : robot.ground_truth()) {
    EXPECT_GT(cv::countNonZero(mask == o.id), 50) << o.name;
    EXPECT_TRUE(o.on_table) << o.name;
  }
  // The parked arm (its base stays in view) covers little of the image.
  EXPECT_LT(cv::countNonZero(mask == kArmId), 320 * 240 / 8);

  // Push the mug 6 cm along its line from the base, starting 4 cm behind it.
  const ObjectTruth mug = truth_of(robot.ground_truth(), "mug");
  const Eigen::Vector2d n = mug.centre.head<2>().normalized();
  const robot::TablePush push = outward_push(mug);
  const fs::path dir = test::temp_dir() / "robot_push";
  robot::PushRecording rec = recording_into(dir);
  rec.run.seed = 3;
  const robot::PushReport r = robot.push(push, rec);
  EXPECT_TRUE(r.touched);
  ASSERT_TRUE(r.first_touch_frame.has_value());
  EXPECT_GT(*r.first_touch_frame, 0);
  ASSERT_EQ(robot.last_push_contacts().size(), 1U);
  const auto after = robot.ground_truth();
  const ObjectTruth moved = truth_of(after, "mug");
  EXPECT_GT((moved.centre - mug.centre).head<2>().dot(n), 0.03);
  EXPECT_LT(
      (truth_of(after, "book").position - truth_of(robot.ground_truth(), "book").position).norm(),
      1e-3);

  // The episode: frames and the touch flag, no ground truth.
  const episode::Episode e = episode::read_episode(dir);
  EXPECT_EQ(e.frame_count(), r.frames);
  EXPECT_FALSE(e.info().has_masks);
  EXPECT_TRUE(e.objects().empty());
  EXPECT_EQ(e.first_touch_frame(), r.first_touch_frame);

  // The scene persists: a second look sees the mug where the push left it.
  const auto again = robot.ground_truth();
  EXPECT_LT((truth_of(again, "mug").position - moved.position).norm(), 1e-3);
  fs::remove_all(dir);
}

TEST(SimulatedRobot, RecordsGroundTruthMasksOnlyWhenAskedForScoring) {
  // TableOptions::record_masks (the oracle ladder's ground truth): each frame's object ids, with
  // objects.json naming every object and the arm; the learner's episodes stay without it.
  const ObjectCatalogue cat = ObjectCatalogue::load_default();
  TableOptions t = small_table();
  t.record_masks = true;
  SimulatedRobot robot(t, cat);
  const ObjectTruth mug = truth_of(robot.ground_truth(), "mug");
  const robot::TablePush push = outward_push(mug);
  const fs::path dir = test::temp_dir() / "robot_push_masks";
  const robot::PushRecording rec = recording_into(dir);
  const robot::PushReport r = robot.push(push, rec);
  ASSERT_TRUE(r.first_touch_frame.has_value());
  const episode::Episode e = episode::read_episode(dir);
  ASSERT_TRUE(e.info().has_masks);
  ASSERT_EQ(e.objects().size(), 4U);  // book, mug, calculator, the arm
  const episode::ObjectInfo* arm = e.object(kArmId);
  ASSERT_NE(arm, nullptr);
  EXPECT_EQ(arm->role, episode::ObjectRole::kArm);
  const cv::Mat touch = e.mask(*r.first_touch_frame);
  EXPECT_GT(cv::countNonZero(touch == kArmId), 20);
  EXPECT_GT(cv::countNonZero(touch == mug.id), 20);
  const cv::Mat last = e.mask(e.frame_count() - 1);
  EXPECT_GT(cv::countNonZero(last == truth_of(robot.ground_truth(), "book").id), 50);
  fs::remove_all(dir);
}

TEST(SimulatedRobot, RollAcrossTurnsTheHandForAPushAcrossTheArmsRadius) {
  // TableOptions::roll_across reaches the push's motion: a push across the arm's radius is made
  // with the roll j5 near +-pi/2 (the jaws across the push); without it j5 stays at the park's 0.
  const ObjectCatalogue cat = ObjectCatalogue::load_default();
  for (const bool across : {false, true}) {
    TableOptions t = small_table();
    t.roll_across = across;
    SimulatedRobot robot(t, cat);
    const ObjectTruth mug = truth_of(robot.ground_truth(), "mug");
    const Eigen::Vector2d c = mug.centre.head<2>();
    const Eigen::Vector2d side(-c.y() / c.norm(), c.x() / c.norm());  // across the radius
    robot::TablePush push;
    push.start = c - side * (mug.footprint_radius + 0.03);
    push.end = c + side * 0.02;
    const fs::path dir = test::temp_dir() / "robot_push_roll";
    const robot::PushRecording rec = recording_into(dir);
    (void)robot.push(push, rec);
    const episode::Episode e = episode::read_episode(dir);
    ASSERT_GT(e.arm().size(), 2U);
    const double j5 = e.arm()[e.arm().size() / 2].q[4];
    if (across) {
      EXPECT_GT(std::abs(j5), 1.0) << j5;
    } else {
      EXPECT_LT(std::abs(j5), 0.05) << j5;
    }
    fs::remove_all(dir);
  }
}

TEST(SimulatedRobot, NamesTheArmsPartsAndTheObjectsThatMetInAPush) {
  // Ground truth for diagnosis: the arm's parts that touched each object, and the pairs of
  // objects that came into contact. The book (3.5 cm tall) pushed at the 8 mm tip into the mug:
  // the pusher touches the book, and the book meets the mug in the push, a pair that was not
  // touching before.
  EXPECT_EQ(arm_part_name("arm_pusher"), "pusher");
  EXPECT_EQ(arm_part_name("arm_finger_left_geom"), "jaws");
  EXPECT_EQ(arm_part_name("arm_finger_right_geom"), "jaws");
  EXPECT_EQ(arm_part_name("arm_palm"), "palm");
  EXPECT_EQ(arm_part_name("arm_link3_geom"), "links");
  const ObjectCatalogue cat = ObjectCatalogue::load_default();
  SimulatedRobot robot(small_table(), cat);
  const auto before = robot.ground_truth();
  const ObjectTruth book = truth_of(before, "book");
  const ObjectTruth mug = truth_of(before, "mug");
  const Eigen::Vector2d c = book.centre.head<2>();
  const Eigen::Vector2d to_mug = mug.centre.head<2>() - c;
  const Eigen::Vector2d n = to_mug.normalized();
  robot::TablePush push;
  // 2 cm behind the book's back edge (its box, 7.5 x 10.5 cm half extents, turned by its yaw).
  const Eigen::Vector2d ax(std::cos(book.yaw), std::sin(book.yaw));
  const Eigen::Vector2d ay(-ax.y(), ax.x());
  push.start = c - n * (0.075 * std::abs(n.dot(ax)) + 0.105 * std::abs(n.dot(ay)) + 0.02);
  push.end = c + n * (to_mug.norm() - 0.07);  // the book well into the mug's place
  (void)robot.push(push, {});
  const auto after = robot.ground_truth();
  EXPECT_GT((truth_of(after, "mug").centre - mug.centre).head<2>().norm(), 0.005);
  const auto& arm = robot.last_push_contact_phases();
  const auto on_book =
      std::find_if(arm.begin(), arm.end(), [&](const ArmContact& a) { return a.id == book.id; });
  ASSERT_NE(on_book, arm.end());
  EXPECT_EQ(on_book->phase, ContactPhase::kPush);
  // The pusher touched it (the jaws may too: their lowest edge is only 3 mm above the book's top
  // where the hand points straight down, and the book tilts against the mug).
  EXPECT_NE(std::find(on_book->parts.begin(), on_book->parts.end(), "pusher"),
            on_book->parts.end());
  const std::vector<std::string> known{"pusher", "jaws", "palm", "links"};
  for (const ArmContact& a : arm) {
    EXPECT_FALSE(a.parts.empty());
    for (const std::string& p : a.parts) {
      EXPECT_NE(std::find(known.begin(), known.end(), p), known.end()) << p;
    }
  }
  const auto& met = robot.last_push_object_contacts();
  const auto pair = std::find_if(met.begin(), met.end(), [&](const ObjectContact& m) {
    return m.a == std::min(mug.id, book.id) && m.b == std::max(mug.id, book.id);
  });
  ASSERT_NE(pair, met.end());
  EXPECT_FALSE(pair->already);
  EXPECT_EQ(pair->phase, ContactPhase::kPush);
  for (const ObjectContact& m : met) EXPECT_LT(m.a, m.b);  // each pair names its lower id first
}

TEST(SimulatedRobot, BacksAwayFromATallObjectBeforeGoingBack) {
  // The mug is 10 cm tall: pushed until the pusher stops against it, the lifted hand (6 cm up)
  // still touches it; the hand backs away along the push and goes back to the park by its
  // transit, not put there at once.
  const ObjectCatalogue cat = ObjectCatalogue::load_default();
  SimulatedRobot robot(small_table(), cat);
  const ObjectTruth mug = truth_of(robot.ground_truth(), "mug");
  const Eigen::Vector2d c = mug.centre.head<2>();
  const Eigen::Vector2d n = c.normalized();
  robot::TablePush push;
  push.start = c - n * (mug.footprint_radius + 0.03);
  push.end = c + n * 0.02;
  const robot::PushReport r = robot.push(push, {});
  EXPECT_TRUE(r.touched);
  EXPECT_TRUE(r.backed_away);
  EXPECT_FALSE(r.parked_at_once);
  const ObjectTruth after = truth_of(robot.ground_truth(), "mug");
  EXPECT_TRUE(after.upright);
  EXPECT_GT((after.centre - mug.centre).head<2>().dot(n), 0.01);
}

TEST(SimulatedRobot, ObjectsBesideTheBaseDoNotBlockTheTransit) {
  // A bottle (the tallest catalogue object, 19 cm) and a mug swept beside the arm's base, 13-14
  // cm from its axis, as a push may leave them: the transit passes above them, so pushes
  // elsewhere go ahead (before, every later transit was refused) and leave them where they are.
  TableOptions o = small_table();
  o.objects = {"calculator", "bottle", "mug"};
  const ObjectCatalogue cat = ObjectCatalogue::load_default();
  SimulatedRobot robot(o, cat);
  robot.place({{"calculator", {0.30, 0.05}, 0.0},
               {"bottle", {0.09, -0.10}, 0.0},
               {"mug", {0.02, 0.13}, 0.0}});
  const auto before = robot.ground_truth();
  for (int k = 0; k < 2; ++k) {
    const ObjectTruth calc = truth_of(robot.ground_truth(), "calculator");
    robot::TablePush push;
    push.start = calc.centre.head<2>() - Eigen::Vector2d(0.07, 0.0);
    push.end = calc.centre.head<2>();
    robot::PushReport r;
    ASSERT_NO_THROW(r = robot.push(push, {})) << "push " << k;
    EXPECT_FALSE(r.parked_at_once) << "push " << k;
    EXPECT_TRUE(r.touched);
  }
  const auto after = robot.ground_truth();
  for (const std::string name : {"bottle", "mug"}) {
    EXPECT_LT((truth_of(after, name).centre - truth_of(before, name).centre).norm(), 0.003) << name;
    EXPECT_TRUE(truth_of(after, name).upright) << name;
  }
  EXPECT_GT(truth_of(after, "calculator").centre.x() - truth_of(before, "calculator").centre.x(),
            0.03);
}

TEST(SimulatedRobot, AnObjectRestingAgainstTheBaseIsNoObstacle) {
  // A book pressed against the arm's base (as a push toward the base leaves it): the base does
  // not move, so the contact is there at every pose of any path; it neither refuses the transit
  // nor puts the arm at the park at once on its way back (it did before).
  TableOptions o = small_table();
  o.objects = {"calculator", "book"};
  const ObjectCatalogue cat = ObjectCatalogue::load_default();
  SimulatedRobot robot(o, cat);
  robot.place({{"calculator", {0.30, 0.05}, 0.0}, {"book", {0.0, -0.175}, 0.0}});
  const ObjectTruth calc = truth_of(robot.ground_truth(), "calculator");
  const ObjectTruth book = truth_of(robot.ground_truth(), "book");
  robot::TablePush push;
  push.start = calc.centre.head<2>() - Eigen::Vector2d(0.07, 0.0);
  push.end = calc.centre.head<2>();
  robot::PushReport r;
  ASSERT_NO_THROW(r = robot.push(push, {}));
  // The book touches the arm (its base) throughout: the precondition of this test.
  const auto& touched = robot.last_push_contacts();
  ASSERT_NE(std::find(touched.begin(), touched.end(), book.id), touched.end());
  EXPECT_FALSE(r.parked_at_once);
  EXPECT_LT((truth_of(robot.ground_truth(), "book").centre - book.centre).norm(), 0.003);
  ASSERT_NO_THROW((void)robot.push(push, {}));  // and the next transit goes ahead too
}

TEST(SimulatedRobot, RejectsUnreachableAndBadPushesWithoutMoving) {
  const ObjectCatalogue cat = ObjectCatalogue::load_default();
  SimulatedRobot robot(small_table(), cat);
  const auto before = robot.ground_truth();
  robot::TablePush far;
  far.start = {0.9, 0.0};
  far.end = {1.0, 0.0};
  EXPECT_THROW((void)robot.push(far, {}), Error);
  robot::TablePush nan;
  nan.start = {std::nan(""), 0.0};
  EXPECT_THROW((void)robot.push(nan, {}), Error);
  const auto after = robot.ground_truth();
  for (std::size_t i = 0; i < before.size(); ++i) {
    EXPECT_LT((before[i].position - after[i].position).norm(), 1e-6);
  }
}

TEST(SimulatedRobot, ScatterMovesEveryObject) {
  const ObjectCatalogue cat = ObjectCatalogue::load_default();
  SimulatedRobot robot(small_table(), cat);
  const auto before = robot.ground_truth();
  const auto places = robot.scatter(99);
  const auto after = robot.ground_truth();
  ASSERT_EQ(places.size(), before.size());
  for (std::size_t i = 0; i < before.size(); ++i) {
    EXPECT_GT((before[i].position - after[i].position).norm(), 1e-3);
    EXPECT_LT((after[i].position.head<2>() - places[i].position).norm(), 0.01);
    EXPECT_TRUE(after[i].on_table);
  }
}

// The robot keeps its own copies of the object types: built from a catalogue that is gone by the
// time it scatters (as the CLI's and Python's temporaries are), it still works (ASan would report
// the use after free).
TEST(SimulatedRobot, OutlivesTheCatalogueItWasBuiltFrom) {
  std::unique_ptr<SimulatedRobot> robot;
  {
    const ObjectCatalogue temporary = ObjectCatalogue::load_default();
    robot = std::make_unique<SimulatedRobot>(small_table(), temporary);
  }
  const auto places = robot->scatter(5);
  ASSERT_EQ(places.size(), 3u);
  EXPECT_EQ(places[1].name, "mug");
  EXPECT_EQ(robot->ground_truth()[2].name, "calculator");
}

// The camera-frame depth (metres along the optical axis) of world point `x`.
double camera_depth(const geometry::Camera& c, const Eigen::Vector3d& x) {
  return (c.R * x + c.t).z();
}

TEST(SimulatedRobot, AnRgbdLookHasTheDepthOfAKnownBox) {
  // The catalogue's box is a 10 cm cube: its top's centre, and the table beside it, are at known
  // depths along the optical axis.
  const ObjectCatalogue cat = ObjectCatalogue::load_default();
  TableOptions t = small_table();
  t.objects = {"box"};
  t.depth = true;
  robot::Look look;
  {
    SimulatedRobot robot(t, cat);  // one GL context at a time
    look = robot.look();
    ASSERT_FALSE(look.depth.empty());
    ASSERT_EQ(look.depth.type(), CV_32FC1);
    ASSERT_EQ(look.depth.size(), look.image.size());
    const ObjectTruth box = truth_of(robot.ground_truth(), "box");
    EXPECT_NEAR(box.centre.z(), 0.05, 0.002);
    const auto depth_at = [&](const Eigen::Vector3d& x) {
      const Eigen::Vector2d p = look.camera.project(x);
      return static_cast<double>(look.depth.at<float>(static_cast<int>(std::lround(p.y())),
                                                      static_cast<int>(std::lround(p.x()))));
    };
    // A pixel's centre sees a point up to half a pixel (about 1.5 mm at 320 px) off the aimed one.
    const Eigen::Vector3d top(box.centre.x(), box.centre.y(), 0.10);
    EXPECT_NEAR(depth_at(top), camera_depth(look.camera, top), 0.003);
    const Eigen::Vector3d table(box.centre.x() + (box.centre.x() > 0.3 ? -0.15 : 0.15),
                                box.centre.y(), 0.0);
    EXPECT_NEAR(depth_at(table), camera_depth(look.camera, table), 0.003);
    // Every pixel of the box back-projects to a point of the cube (within a pixel's reach).
    const cv::Mat mask = robot.ground_truth_mask() == box.id;
    const Eigen::Matrix3d k_inv = look.camera.K.inverse();
    int seen = 0;
    for (int v = 0; v < mask.rows; ++v) {
      for (int u = 0; u < mask.cols; ++u) {
        if (mask.at<std::uint8_t>(v, u) == 0) continue;
        const double d = look.depth.at<float>(v, u);
        const Eigen::Vector3d x =
            look.camera.R.transpose() * (d * (k_inv * Eigen::Vector3d(u, v, 1.0)) - look.camera.t);
        EXPECT_LT(x.z(), 0.105);
        EXPECT_GT(x.z(), -0.003);
        EXPECT_LT((x.head<2>() - box.centre.head<2>()).norm(), 0.05 * std::sqrt(2.0) + 0.006);
        ++seen;
      }
    }
    EXPECT_GT(seen, 100);
  }
  // Without the option the look has no depth, and the same image.
  t.depth = false;
  SimulatedRobot plain(t, cat);
  const robot::Look colour = plain.look();
  EXPECT_TRUE(colour.depth.empty());
  EXPECT_EQ(cv::norm(colour.image, look.image, cv::NORM_INF), 0.0);
}

}  // namespace
}  // namespace proprio::sim
