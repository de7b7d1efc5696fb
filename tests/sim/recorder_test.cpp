// Recording simulated episodes: the episode checks, masks, first touch, determinism, bad input.
#include "proprio/sim/recorder.hpp"

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include "proprio/core/csv.hpp"
#include "proprio/core/error.hpp"
#include "proprio/core/files.hpp"
#include "proprio/episode/check.hpp"
#include "proprio/geometry/camera.hpp"
#include "sim_test_util.hpp"

namespace proprio::sim {
namespace {

namespace fs = std::filesystem;

RecordOptions fast_options() {
  RecordOptions o;
  o.width = 320;
  o.height = 240;
  o.push_speed = 0.2;
  o.still_before = 0.08;
  o.still_after = 0.08;
  o.clutter = 2;
  return o;
}

core::Provenance run_provenance(std::uint64_t seed) {
  return core::Provenance::current({"recorder_test"}, seed);
}

const ObjectCatalogue& catalogue() {
  static const ObjectCatalogue c = ObjectCatalogue::load_default();
  return c;
}

TEST(Recorder, PushEpisodePassesTheChecksAndTouchesTheTarget) {
  const fs::path out = test::temp_dir() / "push";
  fs::remove_all(out);
  const RecordSummary s = record_episode(out, fast_options(), run_provenance(7), catalogue());
  EXPECT_GT(s.frames, 20);
  const auto problems = episode::check_episode(out);
  for (const auto& p : problems) ADD_FAILURE() << p.message;
  ASSERT_TRUE(s.first_touch_frame.has_value());
  EXPECT_GT(*s.first_touch_frame, 0);
  EXPECT_GT(s.target_moved, 0.03);  // pushed, not just brushed
  const core::Json info = core::read_json(out / "episode.json");
  EXPECT_EQ(info["provenance"]["scenario"], "push");
}

TEST(Recorder, MasksAgreeWithTheRenderedObjectsAndTouchWithContact) {
  const fs::path out = test::temp_dir() / "masks";
  fs::remove_all(out);
  RecordOptions o = fast_options();
  const RecordSummary s = record_episode(out, o, run_provenance(3), catalogue());
  // The target (id 1) is visible in the first frame, and the arm (0xFFFF) too.
  const cv::Mat mask = cv::imread((out / "masks" / "000000.png").string(), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(mask.type(), CV_16UC1);
  EXPECT_GT(cv::countNonZero(mask == 1), 200);
  EXPECT_GT(cv::countNonZero(mask == 0xFFFF), 50);
  // Where the mask says "target", the frame shows the object's photograph, not the grey
  // background or the table: the masked colours differ from the table's mean colour.
  const cv::Mat rgb = cv::imread((out / "frames" / "000000.png").string());
  const cv::Scalar in = cv::mean(rgb, mask == 1);
  const cv::Scalar table = cv::mean(rgb, mask == 0);
  EXPECT_GT(cv::norm(in - table), 10.0);
  // arm.csv's first touching row is the summary's first touch, and before it nothing touched.
  const auto table_csv = core::read_csv(out / "arm.csv");
  int first = -1;
  for (std::size_t r = 0; r < table_csv.rows.size(); ++r) {
    if (table_csv.rows[r].back() == 1.0) {
      first = static_cast<int>(r);
      break;
    }
  }
  ASSERT_TRUE(s.first_touch_frame.has_value());
  EXPECT_EQ(first, *s.first_touch_frame);
  // At first touch the pusher is near the target's back face; in the frame before the target has
  // not moved yet (its mask is unchanged from frame 0 up to one pixel row of noise).
  const cv::Mat m0 = cv::imread((out / "masks" / "000000.png").string(), cv::IMREAD_UNCHANGED);
  char name[32];
  std::snprintf(name, sizeof name, "%06d.png", first - 1);
  const cv::Mat before = cv::imread((out / "masks" / name).string(), cv::IMREAD_UNCHANGED);
  EXPECT_LT(cv::countNonZero((m0 == 1) != (before == 1)), 40);
}

TEST(Recorder, SameSeedGivesIdenticalFramesAndLogs) {
  const fs::path a = test::temp_dir() / "rep_a";
  const fs::path b = test::temp_dir() / "rep_b";
  fs::remove_all(a);
  fs::remove_all(b);
  RecordOptions o = fast_options();
  o.moving_background = true;
  record_episode(a, o, run_provenance(7), catalogue());
  record_episode(b, o, run_provenance(7), catalogue());
  EXPECT_EQ(core::read_file(a / "arm.csv"), core::read_file(b / "arm.csv"));
  EXPECT_EQ(core::read_file(a / "objects.json"), core::read_file(b / "objects.json"));
  for (const char* f : {"frames/000000.png", "frames/000010.png", "masks/000015.png"}) {
    EXPECT_EQ(core::read_file(a / f), core::read_file(b / f)) << f;
  }
  const core::Json objects = core::read_json(a / "objects.json");
  int distractors = 0;
  for (const auto& obj : objects["objects"]) distractors += obj["role"] == "distractor";
  EXPECT_EQ(distractors, 2);
}

TEST(Recorder, BadInputIsAClearErrorAndLeavesNoEpisode) {
  const fs::path out = test::temp_dir() / "bad";
  fs::remove_all(out);
  auto expect_error = [&](RecordOptions o, const std::string& part) {
    try {
      record_episode(out, o, run_provenance(1), catalogue());
      ADD_FAILURE() << "no error for " << part;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
    }
    EXPECT_FALSE(fs::exists(out));
  };
  RecordOptions o = fast_options();
  o.object = "teapot";
  expect_error(o, "teapot");
  o = fast_options();
  o.scenario = "juggle";
  expect_error(o, "unknown scenario 'juggle'");
  o = fast_options();
  o.moving_background = true;
  o.background_video = test::temp_dir() / "missing.avi";
  expect_error(o, "missing.avi");
  o = fast_options();
  o.pusher_height = 0.0;
  expect_error(o, "pusher height");
}

TEST(Recorder, SceneFileWithACustomObject) {
  const fs::path scene = test::temp_dir() / "scene.json";
  core::write_file_atomic(scene, R"({
    "objects": [
      {"name": "crate", "shape": "box", "size": [0.04, 0.04, 0.04], "texture": "fruits.jpg",
       "mass": 0.2, "friction": 0.6, "x": 0.21, "y": 0.0},
      {"type": "mug", "x": 0.45, "y": 0.25, "yaw": 1.0}
    ],
    "target": "crate"
  })");
  const fs::path out = test::temp_dir() / "scene_ep";
  fs::remove_all(out);
  RecordOptions o = fast_options();
  o.width = 160;
  o.height = 120;
  o.scenario = scene.string();
  const RecordSummary s = record_episode(out, o, run_provenance(2), catalogue());
  for (const auto& p : episode::check_episode(out)) ADD_FAILURE() << p.message;
  EXPECT_TRUE(s.first_touch_frame.has_value());
  EXPECT_GT(s.target_moved, 0.03);
  // A target that is not among the objects names the file and the target.
  core::write_file_atomic(scene, R"({"objects": [{"type": "mug", "x": 0.2, "y": 0}],
                                     "target": "crate"})");
  fs::remove_all(out);
  try {
    record_episode(out, o, run_provenance(2), catalogue());
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("scene.json"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("'crate'"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(out));
}

TEST(Recorder, EveryScenarioWritesAValidEpisode) {
  for (const std::string scenario : {"push-rotate", "clutter", "scatter", "hold-3d"}) {
    const fs::path out = test::temp_dir() / ("scen_" + scenario);
    fs::remove_all(out);
    RecordOptions o = fast_options();
    o.width = 160;
    o.height = 120;
    o.scenario = scenario;
    const RecordSummary s = record_episode(out, o, run_provenance(5), catalogue());
    for (const auto& p : episode::check_episode(out))
      ADD_FAILURE() << scenario << ": " << p.message;
    EXPECT_GT(s.target_moved, 0.02) << scenario;
    const core::Json info = core::read_json(out / "episode.json");
    EXPECT_EQ(info["provenance"]["scenario"], scenario);
    if (scenario == "hold-3d") {
      EXPECT_EQ(s.first_touch_frame, 0);
    }
  }
}

TEST(Recorder, DisturbancesAreRecordedAndTheEpisodeStaysValid) {
  const fs::path out = test::temp_dir() / "disturbed";
  fs::remove_all(out);
  RecordOptions o = fast_options();
  o.width = 160;
  o.height = 120;
  o.camera_shake = true;
  o.lighting_change = true;
  o.nudge_neighbour = true;
  o.noise = 5.0;
  o.motion_blur = true;
  o.stereo = true;
  o.stereo_baseline = 0.15;
  o.depth = true;
  o.distractors = 1;
  record_episode(out, o, run_provenance(9), catalogue());
  for (const auto& p : episode::check_episode(out)) ADD_FAILURE() << p.message;
  const core::Json sw = core::read_json(out / "episode.json")["provenance"]["switches"];
  for (const char* key :
       {"camera_shake", "lighting_change", "nudge_neighbour", "motion_blur", "stereo", "depth"}) {
    EXPECT_EQ(sw[key], true) << key;
  }
  EXPECT_EQ(sw["noise"], 5.0);
  EXPECT_EQ(sw["distractors"], 1);
  EXPECT_EQ(sw["stereo_baseline"], 0.15);
  const double baseline = (geometry::read_calib(out / "calib_right.yml").center() -
                           geometry::read_calib(out / "calib.yml").center())
                              .norm();
  EXPECT_NEAR(baseline, 0.15, 1e-6);
  const cv::Mat depth = cv::imread((out / "depth" / "000000.png").string(), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(depth.type(), CV_16UC1);
  // The target (id 1) is 0.4-1.0 m from the camera.
  const cv::Mat mask = cv::imread((out / "masks" / "000000.png").string(), cv::IMREAD_UNCHANGED);
  const double target_mm = cv::mean(depth, mask == 1)[0];
  EXPECT_GT(target_mm, 400.0);
  EXPECT_LT(target_mm, 1000.0);
  // Two distractors: the sliding one and the nudged neighbour.
  int distractors = 0;
  const core::Json objects = core::read_json(out / "objects.json");
  for (const auto& obj : objects["objects"]) distractors += obj["role"] == "distractor";
  EXPECT_EQ(distractors, 2);
}

}  // namespace
}  // namespace proprio::sim
