// proprio episode info / check / import, run as a user would.
#include <gtest/gtest.h>

#include <sys/stat.h>

#include <cmath>
#include <cstdio>

#include "../episode/episode_test_support.hpp"
#include "cli_run.hpp"
#include "proprio/core/files.hpp"
#include "proprio/core/json_io.hpp"
#include "proprio/episode/episode.hpp"

namespace proprio::episode {
namespace {
using namespace testing;
using proprio::test::line_count;
using proprio::test::run_cli;

#define EXPECT_HAS(haystack, needle) \
  EXPECT_NE(std::string(haystack).find(needle), std::string::npos) << (haystack)

TEST(EpisodeCli, HelpForEveryVerb) {
  for (const char* verb : {"info", "check", "import"}) {
    const auto r = run_cli(std::string("episode ") + verb + " --help");
    EXPECT_EQ(r.code, 0) << verb;
    EXPECT_HAS(r.out, "Usage");
  }
}

TEST(EpisodeCli, InfoSummarisesAndWritesJson) {
  TempDir tmp;
  SyntheticSpec spec;
  spec.depth = true;
  const auto dir = write_synthetic(tmp.path() / "ep", spec);
  const auto json = tmp.path() / "info.json";
  const auto r = run_cli("episode info " + dir.string() + " --json " + json.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_HAS(r.out, "frames: 5 at 30 fps");
  EXPECT_HAS(r.out, "image: 64x48 (png)");
  EXPECT_HAS(r.out, "arm: katana (2 joints)");
  EXPECT_HAS(r.out, "source: simulated, seed 42");
  EXPECT_HAS(r.out, "scenario: push {\"clutter\":true,\"objects\":3}");
  EXPECT_HAS(r.out, "target: 1 (mug)");
  EXPECT_HAS(r.out, "objects: 1 mug (target), 2 katana (arm), 3 book (object)");
  EXPECT_HAS(r.out, "first touch: frame 3");
  EXPECT_HAS(r.out, "masks: yes");
  EXPECT_HAS(r.out, "depth: yes");
  EXPECT_HAS(r.out, "stereo: no");
  const core::Json j = core::read_json(json);
  EXPECT_EQ(j["format"], "proprio.episode.info");
  EXPECT_TRUE(j["provenance"]["command_line"].get<std::string>().find("episode info") !=
              std::string::npos);
  EXPECT_EQ(j["frames"], 5);
  EXPECT_EQ(j["first_touch_frame"], 3);
  EXPECT_EQ(j["target_name"], "mug");
  EXPECT_NEAR(j["duration_s"].get<double>(), 5 / 30.0, 1e-12);
}

TEST(EpisodeCli, CheckOfAValidEpisode) {
  TempDir tmp;
  const auto dir = write_synthetic(tmp.path() / "ep");
  const auto r = run_cli("episode check " + dir.string());
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.out, dir.string() + ": valid episode\n");
  EXPECT_EQ(r.err, "");
}

TEST(EpisodeCli, CheckPrintsEveryProblemAndExitsTwo) {
  TempDir tmp;
  const auto dir = write_synthetic(tmp.path() / "ep");
  fs::remove(dir / "calib.yml");
  fs::resize_file(image_path(dir, "frames", 2), 50);
  fs::remove(image_path(dir, "masks", 4));
  const auto json = tmp.path() / "check.json";
  const auto r = run_cli("episode check " + dir.string() + " --json " + json.string());
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(line_count(r.out), 3) << r.out;
  EXPECT_HAS(r.out, (dir / "calib.yml").string() + ": missing");
  EXPECT_HAS(r.out, image_path(dir, "frames", 2).string() + ": truncated PNG");
  EXPECT_HAS(r.out, image_path(dir, "masks", 4).string() + ": missing");
  EXPECT_EQ(r.err, "proprio: " + dir.string() + ": not a valid episode (3 problems)\n");
  const core::Json j = core::read_json(json);
  EXPECT_EQ(j["format"], "proprio.episode.check");
  EXPECT_EQ(j["valid"], false);
  EXPECT_EQ(j["problems"].size(), 3u);
}

TEST(EpisodeCli, InfoOfABrokenEpisodeIsOneLineAndExitTwo) {
  TempDir tmp;
  const auto dir = write_synthetic(tmp.path() / "ep");
  core::Json j = core::read_json(dir / "episode.json");
  j["format_version"] = 99;
  core::write_json_atomic(dir / "episode.json", j);
  const auto r = run_cli("episode info " + dir.string());
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(line_count(r.err), 1) << r.err;
  EXPECT_HAS(r.err, (dir / "episode.json").string() + ": format_version 99 is newer");
  const auto missing = run_cli("episode info " + (tmp.path() / "nope").string());
  EXPECT_EQ(missing.code, 2);
  EXPECT_EQ(missing.err,
            "proprio: " + (tmp.path() / "nope").string() + ": no such episode directory\n");
}

// Issue 16: deep nesting in episode.json / objects.json crashed (SIGSEGV); 1e400 exited 1; a
// FIFO as arm.csv hung; non-UTF-8 bytes in a problem made `check --json` exit 1.
TEST(EpisodeCli, HostileEpisodeFilesAreOneLineAndExitTwo) {
  TempDir tmp;
  auto expect_bad = [](const fs::path& dir, const std::string& expect) {
    for (const char* verb : {"info", "check"}) {
      const auto r = run_cli(std::string("episode ") + verb + " " + dir.string());
      EXPECT_EQ(r.code, 2) << verb << ": " << r.err;
      EXPECT_EQ(line_count(r.err), 1) << r.err;
      EXPECT_HAS(r.out + r.err, expect);
    }
  };
  const auto deep = write_synthetic(tmp.path() / "deep");
  core::write_file_atomic(deep / "objects.json", "{\"objects\": " + std::string(300000, '[') +
                                                     std::string(300000, ']') + "}");
  expect_bad(deep, "objects.json:1: invalid JSON: nested deeper than 256 levels");
  const auto info = write_synthetic(tmp.path() / "info");
  core::write_file_atomic(info / "episode.json", std::string(300000, '{'));
  expect_bad(info, "episode.json:1: invalid JSON: nested deeper");
  const auto big = write_synthetic(tmp.path() / "big");
  std::string text = core::read_file(big / "episode.json");
  text.insert(text.find('{') + 1, "\"extra\": 1e400,");
  core::write_file_atomic(big / "episode.json", text);
  expect_bad(big, "episode.json: invalid JSON: number overflow");
  const auto fifo = write_synthetic(tmp.path() / "fifo");
  fs::remove(fifo / "arm.csv");
  ASSERT_EQ(::mkfifo((fifo / "arm.csv").c_str(), 0600), 0);
  expect_bad(fifo, "arm.csv: is not a regular file");
  const auto frame = write_synthetic(tmp.path() / "frame");
  fs::remove(image_path(frame, "frames", 2));
  ASSERT_EQ(::mkfifo(image_path(frame, "frames", 2).c_str(), 0600), 0);
  const auto checked = run_cli("episode check " + frame.string());
  EXPECT_EQ(checked.code, 2) << checked.err;
  EXPECT_HAS(checked.out, "000002.png: is not a regular file");

  const auto odd = write_synthetic(tmp.path() / "odd\xff\xfe");
  fs::remove(odd / "calib.yml");
  const auto json = tmp.path() / "check.json";
  const auto r = run_cli("episode check '" + odd.string() + "' --json " + json.string());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_EQ(core::read_json(json)["problems"].size(), 1U);
}

class EpisodeImportCli : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(video_)) GTEST_SKIP() << video_ << " not installed";
    geometry::Camera cam;
    cam.K << 650.0, 0.0, 383.5, 0.0, 650.0, 287.5, 0.0, 0.0, 1.0;
    cam.R << 1, 0, 0, 0, -1, 0, 0, 0, -1;
    cam.t = Eigen::Vector3d(0.0, 0.0, 1.0);
    cam.dist = {-0.15, 0.02, 0.0, 0.0, 0.0};
    geometry::write_calib(calib_, cam);
    std::string csv = "t,ee_x,ee_y,ee_z,touching\n";
    char buf[128];
    for (int k = 0; k <= 60; ++k) {  // 20 Hz over 3 s
      std::snprintf(buf, sizeof buf, "%.2f,%.4f,0.02,0.05,%d\n", k * 0.05, 0.01 * k,
                    k >= 30 ? 1 : 0);
      csv += buf;
    }
    core::write_file_atomic(log_, csv);
  }

  TempDir tmp_;
  fs::path video_ = fs::path(PROPRIO_OPENCV_SAMPLES) / "vtest.avi";
  fs::path calib_ = tmp_.path() / "calib.yml";
  fs::path log_ = tmp_.path() / "arm.csv";
  fs::path out_ = tmp_.path() / "ep";
  std::string args() const {
    return "episode import -q --video " + video_.string() + " --arm-log " + log_.string() +
           " --calib " + calib_.string() + " --out " + out_.string();
  }
};

TEST_F(EpisodeImportCli, ImportsARealVideo) {
  const auto json = tmp_.path() / "import.json";
  const auto r =
      run_cli(args() + " --max-frames 8 --time-offset 0.05 --arm ur5 --json " + json.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_HAS(r.out, "frames: 8 written");
  EXPECT_HAS(r.out, "lens distortion: removed from every frame");
  const core::Json j = core::read_json(json);
  EXPECT_EQ(j["format"], "proprio.episode.import");
  EXPECT_EQ(j["frames_written"], 8);
  EXPECT_EQ(j["dropped_before_log"], 0);
  EXPECT_EQ(j["stop_reason"], "max_frames reached");
  const auto check = run_cli("episode check " + out_.string());
  EXPECT_EQ(check.code, 0) << check.out;
  const Episode ep = read_episode(out_);
  EXPECT_EQ(ep.info().arm_name, "ur5");
  EXPECT_EQ(ep.info().joint_count, 0);
  EXPECT_NEAR(ep.arm()[0].t, 0.05, 1e-12);
  EXPECT_NEAR(ep.arm()[2].ee.x(), 0.05, 1e-12);  // t = 0.25: sample 5 exactly

  // An existing episode is not replaced without --force.
  const auto again = run_cli(args() + " --max-frames 4");
  EXPECT_EQ(again.code, 2);
  EXPECT_HAS(again.err, "exists and is not empty (pass --overwrite to replace it)");
  EXPECT_EQ(run_cli(args() + " --max-frames 4 --force").code, 0);
  EXPECT_EQ(read_episode(out_).frame_count(), 4);
  EXPECT_EQ(run_cli(args() + " --max-frames 3 --overwrite").code, 0);
  EXPECT_EQ(read_episode(out_).frame_count(), 3);
}

TEST_F(EpisodeImportCli, BadInputIsOneLineAndExitTwo) {
  const std::string missing_video =
      "episode import -q --video " + (tmp_.path() / "x.avi").string() + " --arm-log " +
      log_.string() + " --calib " + calib_.string() + " --out " + out_.string();
  for (const std::string& a : {missing_video, args() + " --frames gif", args() + " --fps -3",
                               args() + " --max-frames 0", std::string("episode import --out x")}) {
    const auto r = run_cli(a);
    EXPECT_EQ(r.code, 2) << a;
    EXPECT_EQ(line_count(r.err), 1) << a << ": " << r.err;
    EXPECT_EQ(r.err.rfind("proprio: ", 0), 0u) << r.err;
  }
  EXPECT_HAS(run_cli(missing_video).err, "x.avi: no such video file");
  EXPECT_FALSE(fs::exists(out_));
}

}  // namespace
}  // namespace proprio::episode
