// `proprio intercept ...` end to end: the built tool with a small trajectory-cost cache, good
// runs validated against the schemas, determinism, and bad input.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <optional>

#include "../support/schema_check.hpp"
#include "../support/temp_dir.hpp"
#include "cli_run.hpp"
#include "proprio/core/json_io.hpp"

namespace proprio {
namespace {
namespace fs = std::filesystem;
using test::line_count;
using test::run_cli;

class InterceptCli : public ::testing::Test {
 protected:
  // One small cache (4 precision samples) for the whole suite.
  static const fs::path& dir() { return temp_->path(); }
  static void SetUpTestSuite() { temp_.emplace("proprio_intercept_cli"); }
  static void TearDownTestSuite() { temp_.reset(); }
  // NOLINTNEXTLINE(readability-identifier-naming)
  static std::optional<test::TempDir> temp_;
  static std::string path(const std::string& name) { return (dir() / name).string(); }
  static std::string setup() { return " --precision-samples 4 --cache " + path("grid.json"); }
  static void expect_error(const test::CliResult& r, std::initializer_list<std::string> expect) {
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_EQ(line_count(r.err), 1) << r.err;
    for (const auto& e : expect) EXPECT_NE(r.err.find(e), std::string::npos) << r.err;
  }
};
std::optional<test::TempDir> InterceptCli::temp_;

using test::expect_schema_valid;

TEST_F(InterceptCli, RunsTrialsAndWritesTheResult) {
  const auto r =
      run_cli("intercept --noise-cm 0 --trials 2 --seed 3 --json " + path("a.json") + setup());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("2/2 executed"), std::string::npos) << r.out;
  const core::Json j = core::read_json(path("a.json"));
  EXPECT_EQ(j["format"], "proprio.intercept");
  EXPECT_EQ(j["executed"], 2);
  EXPECT_LT(j["mean_miss_mm"].get<double>(), 2.5);
  for (const char* key :
       {"median_miss_mm", "mean_predicted_sigma_mm", "mean_intercept_time_s", "mean_plan_ms"}) {
    EXPECT_TRUE(j.contains(key)) << key;
  }
  EXPECT_EQ(j["provenance"]["seed"], 3);
  expect_schema_valid("intercept.schema.json", path("a.json"));
  // Same seed, same figures; the second run reads the cache.
  const auto again =
      run_cli("intercept --noise-cm 0 --trials 2 --seed 3 --json " + path("b.json") + setup());
  ASSERT_EQ(again.code, 0) << again.err;
  EXPECT_NE(again.out.find("(cache,"), std::string::npos) << again.out;
  EXPECT_EQ(core::read_json(path("b.json"))["mean_miss_mm"], j["mean_miss_mm"]);
}

TEST_F(InterceptCli, ReplanAndPriorsRun) {
  const auto r = run_cli(
      "intercept --noise-cm 1 --trials 2 --replan --prior precision "
      "--transition constant-velocity --json " +
      path("c.json") + setup());
  ASSERT_EQ(r.code, 0) << r.err;
  const core::Json j = core::read_json(path("c.json"));
  EXPECT_EQ(j["replan"], true);
  EXPECT_EQ(j["prior"], "precision");
  EXPECT_GT(j["mean_reaims"].get<double>(), 0);
  expect_schema_valid("intercept.schema.json", path("c.json"));
}

TEST_F(InterceptCli, SweepWritesFiguresAndTable) {
  const auto r = run_cli("intercept sweep --out " + path("sweep") +
                         " --trials 1 --noise 0,1 --transitions constant-velocity "
                         "--choice-draws 2" +
                         setup());
  ASSERT_EQ(r.code, 0) << r.err;
  for (const char* f : {"sweep.json", "energy_grid.png", "interception_constant-velocity.png",
                        "noise_choice_constant-velocity.png"}) {
    EXPECT_TRUE(fs::exists(dir() / "sweep" / f)) << f;
  }
  EXPECT_FALSE(cv::imread(path("sweep/energy_grid.png")).empty());
  const core::Json j = core::read_json(path("sweep/sweep.json"));
  EXPECT_EQ(j["rows"].size(), 4u);                   // 2 noise levels x (open loop, re-planning)
  EXPECT_EQ(j["interception_choices"].size(), 27u);  // 3 priors x 9 noise levels
  expect_schema_valid("intercept_sweep.schema.json", path("sweep/sweep.json"));
  // An existing result is not overwritten without --overwrite.
  const auto again = run_cli("intercept sweep --out " + path("sweep") + " --trials 1" + setup());
  EXPECT_EQ(again.code, 2) << again.err;
}

TEST_F(InterceptCli, BadInputIsOneLineAndExitTwo) {
  expect_error(run_cli("intercept --prior speed" + setup()), {"--prior"});
  expect_error(run_cli("intercept --trials 0" + setup()), {"--trials"});
  expect_error(run_cli("intercept --calib1 " + path("x.yml") + setup()), {"--calib1 and --calib2"});
  expect_error(run_cli("intercept --scene " + path("missing.xml") + setup()), {"missing.xml"});
  expect_error(run_cli("intercept --trials 1 --camera-rate 30" + setup()),
               {"whole number of simulation steps"});
  expect_error(run_cli("intercept --trials 1 --observe-frames 5" + setup()), {"observe_frames"});
  expect_error(run_cli("intercept sweep" + setup()), {"--out"});
}

}  // namespace
}  // namespace proprio
