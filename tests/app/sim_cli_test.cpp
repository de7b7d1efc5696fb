// proprio sim record / calibrate / view, run as a user would.
#include <gtest/gtest.h>

#include <array>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "../support/schema_check.hpp"
#include "../support/temp_dir.hpp"
#include "cli_run.hpp"
#include "proprio/core/json_io.hpp"

namespace proprio::app {
namespace {
namespace fs = std::filesystem;
using proprio::test::expect_schema_valid;
using proprio::test::run_cli;

#define EXPECT_HAS(haystack, needle) \
  EXPECT_NE(std::string(haystack).find(needle), std::string::npos) << (haystack)

TEST(SimCli, RecordWritesAnEpisodeThatPassesTheCheck) {
  const proprio::test::TempDir scratch("proprio_sim_cli_");  // removed when the test ends
  const fs::path dir = scratch.path() / "ep";
  const fs::path json = scratch.path() / "rec.json";
  const auto r = run_cli(
      "sim record --scenario push --object mug --background moving --seed 7 "
      "--width 320 --height 240 --speed 0.2 --out " +
      dir.string() + " --json " + json.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_HAS(r.out, "fps:");
  const core::Json j = core::read_json(json);
  EXPECT_GT(j["frames"].get<int>(), 20);
  EXPECT_GT(j["fps"].get<double>(), 0.0);
  EXPECT_GT(j["seconds"].get<double>(), 0.0);
  EXPECT_EQ(j["switches"]["background"], "moving");
  expect_schema_valid("sim_record.schema.json", json);
  const core::Json info = core::read_json(dir / "episode.json");
  EXPECT_EQ(info["provenance"]["switches"]["background"], "moving");
  EXPECT_EQ(info["provenance"]["seed"], 7);
  const auto check = run_cli("episode check " + dir.string());
  EXPECT_EQ(check.code, 0) << check.out << check.err;
  // A second record to the same place is refused and leaves the episode as it was.
  const auto again = run_cli("sim record --width 320 --height 240 --out " + dir.string());
  EXPECT_EQ(again.code, 2);
  EXPECT_HAS(again.err, "already exists");
}

TEST(SimCli, StereoBaselineIsAnOptionRecordedInTheProvenance) {
  const proprio::test::TempDir scratch("proprio_sim_cli_");  // removed when the test ends
  const fs::path dir = scratch.path() / "stereo";
  const fs::path json = scratch.path() / "stereo.json";
  const auto r =
      run_cli("sim record --stereo --baseline 0.25 --speed 0.2 --width 96 --height 72 --out " +
              dir.string() + " --json " + json.string());
  ASSERT_EQ(r.code, 0) << r.err;
  expect_schema_valid("sim_record.schema.json", json);
  EXPECT_EQ(core::read_json(json)["switches"]["stereo_baseline"], 0.25);
  EXPECT_EQ(core::read_json(dir / "episode.json")["provenance"]["switches"]["stereo_baseline"],
            0.25);
  const auto bad = run_cli("sim record --stereo --baseline -1 --out " + (dir / "x").string());
  EXPECT_EQ(bad.code, 2);
  EXPECT_HAS(bad.err, "baseline");
}

TEST(SimCli, UnknownObjectOrScenarioIsOneLineAndNoEpisode) {
  const proprio::test::TempDir scratch("proprio_sim_cli_");  // removed when the test ends
  const fs::path dir = scratch.path() / "bad";
  auto r = run_cli("sim record --object teapot --out " + dir.string());
  EXPECT_EQ(r.code, 2);
  EXPECT_HAS(r.err, "unknown object 'teapot'");
  r = run_cli("sim record --scenario juggle --out " + dir.string());
  EXPECT_EQ(r.code, 2);
  EXPECT_HAS(r.err, "unknown scenario 'juggle'");
  EXPECT_FALSE(fs::exists(dir));
}

TEST(SimCli, CalibrateReachesSubPixelRms) {
  const proprio::test::TempDir scratch("proprio_sim_cli_");  // removed when the test ends
  const fs::path calib = scratch.path() / "calib.yml";
  const fs::path json = scratch.path() / "cal.json";
  const auto r =
      run_cli("sim calibrate --grid 3 --out " + calib.string() + " --json " + json.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_HAS(r.out, "rms_px");
  const core::Json j = core::read_json(json);
  EXPECT_LT(j["rms_px"].get<double>(), 1.0);
  EXPECT_LT(j["true_error_px"].get<double>(), 0.3);
  EXPECT_TRUE(fs::exists(calib));
  expect_schema_valid("sim_calibrate.schema.json", json);
}

TEST(SimCli, ViewWritesAPicture) {
  const proprio::test::TempDir scratch("proprio_sim_cli_");  // removed when the test ends
  const fs::path png = scratch.path() / "view.png";
  const auto r = run_cli("sim view --scenario push --object book --width 320 --height 240 --out " +
                         png.string());
  ASSERT_EQ(r.code, 0) << r.err;
  const cv::Mat img = cv::imread(png.string());
  EXPECT_EQ(img.cols, 320);
  EXPECT_EQ(img.rows, 240);
}

TEST(SimCli, DatasetWritesThePresetsEpisodes) {
  const proprio::test::TempDir scratch("proprio_sim_cli_");  // removed when the test ends
  const fs::path dir = scratch.path() / "dataset";
  const fs::path json = scratch.path() / "dataset.json";
  const auto r = run_cli(
      "sim dataset --preset thesis-ch5 --episodes 2 --frames 3 --width 160 "
      "--height 120 -q --out " +
      dir.string() + " --json " + json.string());
  ASSERT_EQ(r.code, 0) << r.err;
  const core::Json j = core::read_json(json);
  ASSERT_EQ(j["episodes"].size(), 2U);
  EXPECT_EQ(j["frames"], 6);
  expect_schema_valid("sim_dataset.schema.json", json);
  for (const auto& e : j["episodes"]) {
    const auto check = run_cli("episode check " + (dir / e["episode"].get<std::string>()).string());
    EXPECT_EQ(check.code, 0) << check.out;
  }
  const auto bad = run_cli("sim dataset --preset thesis-ch9 --out " + (dir / "x").string());
  EXPECT_NE(bad.code, 0);
}

TEST(SimCli, DatasetMovingEpisodesCarryTheThesisDisturbances) {
  const proprio::test::TempDir scratch("proprio_sim_cli_");  // removed when the test ends
  // Episodes 6-8 of thesis-ch5 are the rabbit's first moving ones: video backdrop and
  // distractors in each, plus camera shake, a lighting change and a nudged neighbour in turn.
  const fs::path dir = scratch.path() / "dataset_moving";
  const fs::path json = scratch.path() / "dataset_moving.json";
  const auto r = run_cli(
      "sim dataset --preset thesis-ch5 --episodes 9 --frames 1 --width 64 --height 48 -q --out " +
      dir.string() + " --json " + json.string());
  ASSERT_EQ(r.code, 0) << r.err;
  const core::Json j = core::read_json(json);
  ASSERT_EQ(j["episodes"].size(), 9U);
  expect_schema_valid("sim_dataset.schema.json", json);
  constexpr std::array<const char*, 3> kSwitch = {"camera_shake", "lighting_change",
                                                  "nudge_neighbour"};
  for (int k = 0; k < 9; ++k) {
    const core::Json& e = j["episodes"][static_cast<std::size_t>(k)];
    const core::Json sw = core::read_json(dir / e["episode"].get<std::string>() /
                                          "episode.json")["provenance"]["switches"];
    const bool moving = k >= 6;
    EXPECT_EQ(
        e["episode"].get<std::string>().find(moving ? "_moving_" : "_static_") != std::string::npos,
        true)
        << e;
    EXPECT_EQ(sw["background"], moving ? "moving" : "static");
    EXPECT_EQ(sw["distractors"].get<int>(), moving ? 2 : 0);
    for (int d = 0; d < 3; ++d) {
      EXPECT_EQ(sw[kSwitch[d]].get<bool>(), moving && (k - 6) % 3 == d) << k << kSwitch[d];
    }
  }
}

TEST(SimCli, ViewsWritesAFolderPerObject) {
  const proprio::test::TempDir scratch("proprio_sim_cli_");  // removed when the test ends
  const fs::path dir = scratch.path() / "views";
  const fs::path json = scratch.path() / "views.json";
  const auto r = run_cli(
      "sim views --objects book,mug --per-object 3 --width 160 --height 120 "
      "--out " +
      dir.string() + " --json " + json.string());
  ASSERT_EQ(r.code, 0) << r.err;
  expect_schema_valid("sim_views.schema.json", json);
  EXPECT_EQ(core::read_json(json)["images"], 6);
  for (const char* o : {"book", "mug"}) {
    for (const char* f : {"000000.png", "000002.png"}) {
      const cv::Mat img = cv::imread((dir / o / f).string());
      ASSERT_FALSE(img.empty()) << o << "/" << f;
      EXPECT_EQ(img.cols, 160);
    }
  }
  // Different views of one object differ.
  const cv::Mat a = cv::imread((dir / "book" / "000000.png").string());
  const cv::Mat b = cv::imread((dir / "book" / "000001.png").string());
  EXPECT_GT(cv::norm(a, b, cv::NORM_L1), 1000.0);
  // --masks: the same colours, and the object's ground-truth mask as the alpha channel.
  const fs::path masked = scratch.path() / "masked";
  ASSERT_EQ(run_cli("sim views --objects book,mug --per-object 3 --width 160 --height 120 "
                    "--masks --out " +
                    masked.string())
                .code,
            0);
  for (const char* o : {"book", "mug"}) {
    const cv::Mat plain = cv::imread((dir / o / "000001.png").string(), cv::IMREAD_UNCHANGED);
    const cv::Mat bgra = cv::imread((masked / o / "000001.png").string(), cv::IMREAD_UNCHANGED);
    ASSERT_EQ(plain.channels(), 3);
    ASSERT_EQ(bgra.channels(), 4) << o;
    cv::Mat colours, alpha;
    cv::cvtColor(bgra, colours, cv::COLOR_BGRA2BGR);
    cv::extractChannel(bgra, alpha, 3);
    EXPECT_EQ(cv::norm(plain, colours, cv::NORM_INF), 0.0) << o;
    // The object fills part of the picture, not all of it; alpha is 0 or 255.
    const int on = cv::countNonZero(alpha);
    EXPECT_GT(on, 100) << o;
    EXPECT_LT(on, alpha.rows * alpha.cols / 2) << o;
    EXPECT_EQ(on, cv::countNonZero(alpha == 255)) << o;
  }
  const auto bad =
      run_cli("sim views --objects teapot --per-object 1 --out " + (dir.string() + "_bad"));
  EXPECT_EQ(bad.code, 2);
  EXPECT_HAS(bad.err, "teapot");
  EXPECT_FALSE(fs::exists(dir.string() + "_bad"));
}

}  // namespace
}  // namespace proprio::app
