// proprio segment and proprio evaluate segmentation, run as a user would, on small synthetic
// pushes; results checked against their JSON schemas.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "../segmentation/baseline_test_episode.hpp"
#include "../support/schema_check.hpp"
#include "cli_run.hpp"
#include "proprio/core/json_io.hpp"
#include "proprio/segmentation/ml_segmentation.hpp"

namespace proprio::app {
namespace {
using namespace proprio::segmentation::testing;
using proprio::test::expect_schema_valid;
using proprio::test::run_cli;

#define EXPECT_HAS(haystack, needle) \
  EXPECT_NE(std::string(haystack).find(needle), std::string::npos) << (haystack)

TEST(SegmentCli, Help) {
  EXPECT_EQ(run_cli("segment --help").code, 0);
  const auto r = run_cli("evaluate segmentation --help");
  EXPECT_EQ(r.code, 0);
  EXPECT_HAS(r.out, "--methods");
}

TEST(SegmentCli, EveryMethodWritesMapsMasksAndMetrics) {
  ScratchDir tmp;
  const auto ep = write_push_episode(tmp.path() / "ep", PushSpec{});
  for (const char* m : {"ml", "fm", "ml-graphcut"}) {
    const auto out = tmp.path() / (std::string("out_") + m);
    const auto json = tmp.path() / (std::string(m) + ".json");
    const auto r = run_cli("segment " + ep.string() + " --method " + m + " --out " + out.string() +
                           " --json " + json.string());
    ASSERT_EQ(r.code, 0) << m << ": " << r.err;
    EXPECT_HAS(r.out, "Jaccard");
    for (const char* f :
         {"mask.png", "overlay.png", "frame.png", "truth.png", "map.png", "segment.json"}) {
      EXPECT_TRUE(fs::exists(out / f)) << m << " " << f;
    }
    EXPECT_EQ(cv::imread((out / "map.png").string(), cv::IMREAD_UNCHANGED).depth(), CV_16U);
    const core::Json j = core::read_json(json);
    EXPECT_EQ(j["method"], m);
    EXPECT_EQ(j["status"], "ok");
    EXPECT_EQ(j["scored_frame"], push_first_touch(PushSpec{}));
    // M-L's quality is its own tests' business (this 16-frame push is short for it).
    if (std::string(m) == "fm") {
      EXPECT_GT(j["metrics"]["jaccard"].get<double>(), 0.5);
    }
    expect_schema_valid("segment.schema.json", json);
  }
}

// The depth variant's mask has its own fraction (tuned apart from M-L's): its flag reaches the
// options and is recorded; --fraction leaves it alone.
TEST(SegmentCli, DepthFractionIsItsOwnOption) {
  ScratchDir tmp;
  const auto ep = write_push_episode(tmp.path() / "ep", PushSpec{});
  const auto json = tmp.path() / "r.json";
  auto r = run_cli("segment " + ep.string() + " --method ml --fraction 0.6 --depth-fraction 0.3 " +
                   "--out " + (tmp.path() / "out").string() + " --json " + json.string());
  ASSERT_EQ(r.code, 0) << r.err;
  core::Json j = core::read_json(json);
  EXPECT_EQ(j["options"]["mask_fraction"].get<double>(), 0.6);
  EXPECT_EQ(j["options"]["depth_mask_fraction"].get<double>(), 0.3);
  expect_schema_valid("segment.schema.json", json);
  r = run_cli("segment " + ep.string() + " --method ml --fraction 0.6 --out " +
              (tmp.path() / "out2").string() + " --json " + json.string());
  ASSERT_EQ(r.code, 0) << r.err;
  j = core::read_json(json);
  EXPECT_EQ(j["options"]["depth_mask_fraction"].get<double>(),
            segmentation::MlOptions{}.depth_mask_fraction);
  EXPECT_EQ(run_cli("segment " + ep.string() + " --method ml --depth-fraction 0 --out " +
                    (tmp.path() / "out3").string())
                .code,
            2);
}

TEST(SegmentCli, NoTouchIsAResult) {
  ScratchDir tmp;
  PushSpec s;
  s.touch = false;
  const auto ep = write_push_episode(tmp.path() / "ep", s);
  const auto json = tmp.path() / "r.json";
  const auto r = run_cli("segment " + ep.string() + " --method fm --out " +
                         (tmp.path() / "out").string() + " --json " + json.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_HAS(r.out, "no touch");
  const core::Json j = core::read_json(json);
  EXPECT_EQ(j["status"], "no touch");
  EXPECT_TRUE(j["metrics"].is_null());
  expect_schema_valid("segment.schema.json", json);
}

TEST(SegmentCli, BadInput) {
  ScratchDir tmp;
  auto r = run_cli("segment " + (tmp.path() / "nothing").string() + " --method ml --out " +
                   (tmp.path() / "o").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_HAS(r.err, "proprio: ");
  r = run_cli("segment x --method grabcut --out y");
  EXPECT_EQ(r.code, 2);
  r = run_cli("evaluate segmentation " + tmp.path().string() + " --out " +
              (tmp.path() / "o").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_HAS(r.err, "no episodes");
  r = run_cli("evaluate segmentation " + tmp.path().string() + " --methods ml,nope --out " +
              (tmp.path() / "o").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_HAS(r.err, "nope");
}

// Issue 16: `segment ep --out ep --overwrite` deleted the input episode; --overwrite replaced any
// directory at all.
TEST(SegmentCli, OverwriteNeverDeletesAnInputOrAForeignDirectory) {
  ScratchDir tmp;
  const auto ep = write_push_episode(tmp.path() / "ep", PushSpec{});
  auto r = run_cli("segment " + ep.string() + " --method fm --overwrite --out " + ep.string());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_HAS(r.err, "--out is the same file as");
  fs::create_directory_symlink(ep, tmp.path() / "link");
  r = run_cli("segment " + ep.string() + " --method fm --overwrite --out " +
              (tmp.path() / "link").string());
  EXPECT_EQ(r.code, 2) << r.err;
  r = run_cli("segment " + ep.string() + " --method fm --overwrite --out " + tmp.path().string());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_HAS(r.err, "holds the input");
  EXPECT_TRUE(fs::exists(ep / "episode.json"));
  const auto mine = tmp.path() / "notes";
  fs::create_directories(mine);
  std::ofstream(mine / "todo.txt") << "keep me\n";
  r = run_cli("segment " + ep.string() + " --method fm --overwrite --out " + mine.string());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_HAS(r.err, "not a directory proprio wrote");
  EXPECT_TRUE(fs::exists(mine / "todo.txt"));
  // A segmentation is replaced.
  const auto out = tmp.path() / "seg";
  ASSERT_EQ(run_cli("segment " + ep.string() + " --method fm --out " + out.string()).code, 0);
  r = run_cli("segment " + ep.string() + " --method fm --out " + out.string());
  EXPECT_EQ(r.code, 2);
  EXPECT_HAS(r.err, "pass --overwrite");
  EXPECT_EQ(
      run_cli("segment " + ep.string() + " --method fm --overwrite --out " + out.string()).code, 0);
}

TEST(SegmentCli, EvaluateADataset) {
  ScratchDir tmp;
  const auto data = tmp.path() / "data";
  PushSpec a, b, c;
  b.moving_background = true;
  b.seed = 5;
  c.touch = false;
  write_push_episode(data / "a", a);
  write_push_episode(data / "b", b);
  write_push_episode(data / "c", c);
  const auto out = tmp.path() / "eval";
  const auto json = tmp.path() / "eval.json";
  const auto r = run_cli("evaluate segmentation " + data.string() +
                         " --methods ml,fm,ml-graphcut --threads 2 --out " + out.string() +
                         " --json " + json.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_HAS(r.out, "3 episodes");
  for (const char* f : {"summary.json", "episodes.csv", "pr_by_background.png", "pr_by_object.png",
                        "bars_jaccard.png", "bars_l2.png"}) {
    EXPECT_TRUE(fs::exists(out / f)) << f;
  }
  const core::Json j = core::read_json(json);
  EXPECT_EQ(j["episodes"], 3);
  EXPECT_EQ(j["methods"]["ml"]["all"]["no_touch"], 1);
  EXPECT_EQ(j["methods"]["fm"]["static"]["episodes"], 1);
  EXPECT_EQ(j["methods"]["fm"]["moving"]["episodes"], 1);
  EXPECT_TRUE(j["ks"].contains("ml_vs_fm"));
  expect_schema_valid("evaluate_segmentation.schema.json", json);
}

}  // namespace
}  // namespace proprio::app
