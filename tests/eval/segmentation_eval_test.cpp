// The evaluation on small synthetic datasets: every method scored, groups, JSON shape, CSV,
// plots, no-touch episodes counted, bad input.
#include "proprio/eval/segmentation_eval.hpp"

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include "../segmentation/baseline_test_episode.hpp"
#include "proprio/core/error.hpp"
#include "proprio/episode/discovery.hpp"

namespace proprio::eval {
namespace {
using namespace proprio::segmentation::testing;

TEST(SegmentationEval, MethodNames) {
  for (Method m :
       {Method::kMl, Method::kMlHomography, Method::kMlSparse, Method::kFm, Method::kMlGraphCut}) {
    EXPECT_EQ(parse_method(to_string(m)), m);
  }
  EXPECT_EQ(parse_methods("ml,fm,ml-graphcut").size(), 3u);
  EXPECT_THROW(parse_methods("ml,ml"), Error);
  EXPECT_THROW(parse_methods(""), Error);
  try {
    parse_method("grabcut");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("grabcut"), std::string::npos);
  }
  EXPECT_EQ(free_parameter(Method::kFm), "difference_threshold");
  EXPECT_EQ(free_parameter(Method::kMl), "mask_fraction");
}

TEST(SegmentationEval, ScoresEveryMethodOnASyntheticDataset) {
  ScratchDir tmp;
  PushSpec a, b, c;
  b.moving_background = true;
  b.seed = 2;
  c.touch = false;
  c.seed = 3;
  write_push_episode(tmp.path() / "a", a);
  write_push_episode(tmp.path() / "b", b);
  write_push_episode(tmp.path() / "c", c);
  const auto dirs = episode::list_episode_dirs(tmp.path());
  ASSERT_EQ(dirs.size(), 3u);
  const std::vector<Method> methods = {Method::kMl, Method::kFm, Method::kMlGraphCut};
  EvalOptions o;
  o.bootstrap_resamples = 200;
  std::vector<EpisodeEvaluation> evals;
  for (const auto& d : dirs)
    evals.push_back(evaluate_episode(episode::read_episode(d), methods, o));
  ASSERT_EQ(evals[0].outcomes.size(), 3u);
  EXPECT_EQ(evals[0].background, "static");
  EXPECT_EQ(evals[1].background, "moving");
  EXPECT_EQ(evals[0].object, "mug");
  EXPECT_EQ(evals[0].scenario, "push");
  for (const auto& oc : evals[0].outcomes) {
    EXPECT_EQ(oc.status, "ok") << to_string(oc.method) << ": " << oc.message;
    EXPECT_EQ(oc.scored_frame, push_first_touch(a));
    EXPECT_EQ(oc.sweep_precision.size(),
              oc.method == Method::kFm ? o.threshold_sweep.size() : o.fraction_sweep.size());
  }
  EXPECT_GT(evals[0].outcomes[1].metrics.jaccard, 0.5);  // the baseline on a static push
  EXPECT_TRUE(evals[0].outcomes[0].all_frames_jaccard.has_value());
  for (const auto& oc : evals[2].outcomes) EXPECT_EQ(oc.status, "no touch") << oc.message;

  const core::Json j = dataset_summary_json(evals, methods, o);
  for (const char* m : {"ml", "fm", "ml-graphcut"}) {
    for (const char* g : {"static", "moving", "all"}) {
      const auto& s = j["methods"][m][g];
      for (const char* k : {"mean_jaccard", "mean_jaccard_ci95", "mean_precision", "mean_recall",
                            "mean_l2", "episodes"}) {
        EXPECT_TRUE(s.contains(k)) << m << "/" << g << "/" << k;
      }
    }
    EXPECT_EQ(j["methods"][m]["all"]["episodes"], 2);
    EXPECT_EQ(j["methods"][m]["all"]["no_touch"], 1);
    EXPECT_EQ(j["methods"][m]["static"]["episodes"], 1);
  }
  EXPECT_TRUE(j["ks"].contains("ml_vs_fm"));
  EXPECT_TRUE(j["ks"]["ml_vs_fm"].contains("p_value"));
  EXPECT_TRUE(j["ks"].contains("fm_vs_ml-graphcut"));

  const std::string csv = episodes_csv(evals);
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 1 + 3 * 3);
  EXPECT_NE(csv.find("no touch"), std::string::npos);

  const auto files = write_plots(tmp.path(), evals, methods, o);
  EXPECT_EQ(files.size(), 4u);
  for (const auto& f : files) {
    const cv::Mat img = cv::imread((tmp.path() / f).string());
    EXPECT_FALSE(img.empty()) << f;
  }
}

TEST(SegmentationEval, SummaryOfKnownOutcomes) {
  // Two hand-made episodes: the means, the P-R curve's best point, the bootstrap interval.
  std::vector<EpisodeEvaluation> ev(2);
  const double jac[2] = {0.5, 0.9};
  for (int k = 0; k < 2; ++k) {
    ev[k].background = k == 0 ? "static" : "moving";
    ev[k].object = "mug";
    MethodOutcome o;
    o.status = "ok";
    o.metrics.jaccard = jac[k];
    o.metrics.precision = 0.8;
    o.metrics.recall = 0.6 + 0.2 * k;
    o.metrics.l2 = 0.1;
    o.sweep_precision = {0.2, 0.9, 1.0};
    o.sweep_recall = {1.0, 0.8, 0.1};
    ev[k].outcomes.push_back(o);
  }
  EvalOptions opt;
  const GroupSummary g = summarise(ev, 0, {0.1, 0.5, 0.9}, opt);
  EXPECT_EQ(g.episodes, 2);
  EXPECT_DOUBLE_EQ(g.mean_jaccard, 0.7);
  EXPECT_DOUBLE_EQ(g.mean_recall, 0.7);
  EXPECT_EQ(g.pr_best, 1);
  EXPECT_GE(g.jaccard_ci95.lower, 0.5);
  EXPECT_LE(g.jaccard_ci95.upper, 0.9);
  EXPECT_EQ(summarise(ev, 0, {0.1, 0.5, 0.9}, opt, "moving").episodes, 1);
  EXPECT_EQ(summarise(ev, 0, {0.1, 0.5, 0.9}, opt, kAnyGroup, "book").episodes, 0);
}

TEST(SegmentationEval, BadDatasets) {
  ScratchDir tmp;
  EvalOptions o;
  o.fraction_sweep = {1.5};
  EXPECT_THROW(o.validate(), Error);
}

}  // namespace
}  // namespace proprio::eval
