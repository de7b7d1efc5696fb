// proprio experiment clutter (thesis 8.2): the cluster naming, the options, and a --quick run
// on a small simulated table whose cache a second run reuses without simulating.
#include "proprio/loop/clutter_experiment.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "../support/schema_check.hpp"
#include "../support/temp_dir.hpp"
#include "proprio/core/error.hpp"
#include "proprio/core/json_io.hpp"

namespace proprio::loop {
namespace {
namespace fs = std::filesystem;

TEST(ClutterExperiment, BestAssignmentMaximisesTheViewsOnTheirOwnObject) {
  // Cluster 0 holds mostly object 1, cluster 1 object 0, cluster 2 object 2.
  EXPECT_EQ(best_assignment({{0, 5, 1}, {4, 0, 0}, {0, 1, 7}}), (std::vector<int>{1, 0, 2}));
  // The greedy choice (cluster 0 -> object 0, its largest) is not the best: 6 + 5 > 6 + 1.
  EXPECT_EQ(best_assignment({{6, 5}, {6, 1}}), (std::vector<int>{1, 0}));
  EXPECT_EQ(best_assignment({{3}}), (std::vector<int>{0}));
  EXPECT_TRUE(best_assignment({}).empty());
  EXPECT_THROW(best_assignment({{1, 2}, {3}}), Error);
  EXPECT_THROW(best_assignment(std::vector<std::vector<int>>(9, std::vector<int>(9, 0))), Error);
}

TEST(ClutterExperiment, DefaultsAreTheIssues) {
  ClutterExperimentOptions o;
  EXPECT_EQ(o.objects, "book,bottle,cd,giraffe");
  EXPECT_EQ(o.background, "moving");
  EXPECT_EQ(o.seeds, (std::vector<std::uint64_t>{1, 2, 3}));
  EXPECT_EQ(o.trials, 3);
  EXPECT_EQ(o.pushes, 10);
  EXPECT_EQ(o.fractions, (std::vector<double>{0.5, 0.6, 0.7, 0.8, 0.9}));
  EXPECT_EQ(o.topics, (std::vector<int>{2, 4, 6, 8, 10, 15, 20, 25}));
  EXPECT_EQ(o.segmentation, PushSegmentation::kDense);
  EXPECT_EQ(o.attempts, 6);  // session 22 (1: the session-21 harness)
  EXPECT_EQ(o.sweep_margin, 0.0);
  EXPECT_EQ(o.depth_split, 0.0);
  EXPECT_EQ(o.erode, 0);
  EXPECT_EQ(o.dense.touch_fm, 1.0);  // MlOptions's default (--seg-touch-fm)
  EXPECT_EQ(o.mot_classifier, ClutterMotClassifier::kPooled);  // session 23 (theta: eq 7.3)
  EXPECT_EQ(o.mot_word_weight, 0.25);
  EXPECT_FALSE(o.mot_word_background);  // session 30
  EXPECT_TRUE(o.mot_word_per_view);     // session 30 (false: the pooled counts)
  EXPECT_FALSE(o.right_angle_words);    // session 31
  EXPECT_THROW(o.validate(), Error);    // no cache
  o.cache = "somewhere";
  EXPECT_NO_THROW(o.validate());
  o.quick = true;
  const ClutterExperimentOptions q = o.resolved();
  EXPECT_EQ(q.seeds.size(), 1U);
  EXPECT_EQ(q.fractions.size(), 2U);
  EXPECT_EQ(q.topics.size(), 2U);
  EXPECT_LT(q.pushes, o.pushes);
}

TEST(ClutterExperiment, BadOptionsNameTheFlag) {
  const auto message = [](auto change) {
    ClutterExperimentOptions o;
    o.cache = "somewhere";
    change(o);
    try {
      o.validate();
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message([](auto& o) {
              o.fractions = {0.5, 1.0};
            }).find("--fractions"),
            std::string::npos);
  EXPECT_NE(message([](auto& o) {
              o.fractions = {0.5, 0.5};
            }).find("--fractions"),
            std::string::npos);
  EXPECT_NE(message([](auto& o) { o.topics = {1}; }).find("--topics"), std::string::npos);
  EXPECT_NE(message([](auto& o) { o.seeds = {}; }).find("--seeds"), std::string::npos);
  EXPECT_NE(message([](auto& o) { o.trials = 0; }).find("--trials"), std::string::npos);
  EXPECT_NE(message([](auto& o) { o.pushes = 0; }).find("--pushes"), std::string::npos);
  EXPECT_NE(message([](auto& o) { o.objects = "book,unicorn"; }).find("unicorn"),
            std::string::npos);
  EXPECT_NE(message([](auto& o) { o.clutter = "book"; }).find("repeated"), std::string::npos);
  EXPECT_NE(message([](auto& o) { o.max_shift = 0.02; }).find("--max-shift"), std::string::npos);
  EXPECT_NE(message([](auto& o) { o.background = "stripes"; }).find("--background"),
            std::string::npos);
  EXPECT_NE(message([](auto& o) { o.attempts = 0; }).find("--attempts"), std::string::npos);
  EXPECT_NE(message([](auto& o) { o.attempts = 21; }).find("--attempts"), std::string::npos);
  EXPECT_NE(message([](auto& o) { o.sweep_margin = -0.01; }).find("--sweep-margin"),
            std::string::npos);
  EXPECT_NE(message([](auto& o) {
              o.depth_split = std::numeric_limits<double>::quiet_NaN();
            }).find("--depth-split"),
            std::string::npos);
  EXPECT_NE(message([](auto& o) { o.erode = -1; }).find("--erode"), std::string::npos);
  EXPECT_NE(message([](auto& o) { o.erode = 51; }).find("--erode"), std::string::npos);
  EXPECT_NE(message([](auto& o) { o.dense.touch_fm = -0.1; }).find("--seg-touch-fm"),
            std::string::npos);
  EXPECT_NE(message([](auto& o) {
              o.dense.touch_fm = std::numeric_limits<double>::quiet_NaN();
            }).find("--seg-touch-fm"),
            std::string::npos);
  EXPECT_NE(message([](auto& o) { o.mot_word_weight = -0.1; }).find("--mot-word-weight"),
            std::string::npos);
  EXPECT_NE(message([](auto& o) { o.mot_word_weight = 1.5; }).find("--mot-word-weight"),
            std::string::npos);
  EXPECT_NE(message([](auto& o) {
              o.mot_word_weight = std::numeric_limits<double>::infinity();
            }).find("--mot-word-weight"),
            std::string::npos);
  EXPECT_NE(message([](auto& o) {
              o.mot_word_background = true;
              o.mot_classifier = ClutterMotClassifier::kTheta;
            }).find("--mot-word-background"),
            std::string::npos);
}

// Session 22: more planning attempts per push, eroded view masks, and the score on held-out
// pushes (the other seed's push views), on two small tables. Session 24: at 10 fps with 4 held-out
// renders (was 15 fps and 6: 100-170 s on a loaded machine); at 160 x 120 no push was executed.
TEST(ClutterExperiment, AttemptsErosionAndOtherSeedsPushes) {
  const test::TempDir temp("proprio_clutter_attempts");
  ClutterExperimentOptions o;
  o.objects = "book,cd";
  o.clutter = "mug";
  o.background = "plain";
  o.seeds = {2, 3};
  o.trials = 1;
  o.pushes = 2;
  o.width = 240;
  o.height = 180;
  o.fps = 10;
  o.fractions = {0.5};
  o.topics = {4};
  o.words = 60;
  o.held_out = 4;
  o.attempts = 3;
  o.erode = 1;
  o.mot_classifier = ClutterMotClassifier::kTheta;  // compared with words and pooled below
  o.cache = temp.path() / "cache";
  o.json = temp.path() / "clutter.json";
  o.progress = false;
  const ClutterExperimentResult r = run_clutter_experiment(o, core::Provenance{});
  ASSERT_EQ(r.pushes.size(), 2U * 2U * 2U);  // 2 seeds x 2 objects x 2 pushes
  for (const auto& p : r.pushes) {
    EXPECT_GE(p.attempts, 1);
    EXPECT_LE(p.attempts, 3);
    // Every attempt before the executed one (or every attempt of a push not executed) failed.
    const auto failed = static_cast<int>(p.failed.size());
    EXPECT_EQ(failed, p.episode.empty() ? p.attempts : p.attempts - 1) << p.object << p.index;
    if (p.episode.empty()) {
      EXPECT_FALSE(p.moved_intended);
    }
  }
  test::expect_schema_valid("experiment_clutter.schema.json", o.json);
  const core::Json manifest =
      core::read_json(o.cache / "seed_2" / "book_t1" / "clutter_cache.json");
  EXPECT_EQ(manifest.at("recording").at("attempts"), 3);
  // The eroded views are cached apart from the uneroded ones.
  int eroded_files = 0;
  for (const auto& e : fs::recursive_directory_iterator(o.cache)) {
    EXPECT_NE(e.path().filename(), "views_dense.bin");
    eroded_files += e.path().filename() == "views_dense_e1.bin" ? 1 : 0;
  }
  EXPECT_GT(eroded_files, 0);
  ASSERT_EQ(r.cells.size(), 2U);
  for (const auto& c : r.cells) {
    if (!c.note.empty()) continue;  // no model on a seed with too few views
    ASSERT_TRUE(c.cross_seed.has_value());
    ASSERT_EQ(c.cross_seed_per_object.size(), 2U);
    // The other seed's views are the held-out pushes: the overall share is the per-object
    // shares weighted by the other seed's views per object.
    const ClutterCell& other = r.cells[c.seed == 2 ? 1 : 0];
    double right = 0;
    int n = 0;
    for (std::size_t k = 0; k < 2; ++k) {
      EXPECT_GE(c.cross_seed_per_object[k], 0.0);
      EXPECT_LE(c.cross_seed_per_object[k], 1.0);
      right += c.cross_seed_per_object[k] * other.views_per_object[k];
      n += other.views_per_object[k];
    }
    ASSERT_GT(n, 0);
    EXPECT_NEAR(*c.cross_seed, right / n, 1e-9);
  }
  // Without erosion (segmented again from the same recording): a mask is never smaller, so a
  // view is never lost.
  o.erode = 0;
  o.overwrite = true;
  const ClutterExperimentResult plain = run_clutter_experiment(o, core::Provenance{});
  ASSERT_EQ(plain.cells.size(), r.cells.size());
  for (std::size_t i = 0; i < r.cells.size(); ++i) {
    EXPECT_GE(plain.cells[i].views, r.cells[i].views);
  }
  // Session 23: the supervised MoT by words, and pooled with the word multinomials, swept again
  // from the cached views (nothing segmented again). Each cell also holds theta's scores, which
  // are the theta run's (the same vocabulary, LDA and MoT); pooled at weight 0 is by words.
  ASSERT_TRUE(std::all_of(plain.cells.begin(), plain.cells.end(),
                          [](const ClutterCell& c) { return !c.theta.has_value(); }));
  o.json = temp.path() / "clutter_words.json";
  o.mot_classifier = ClutterMotClassifier::kWords;
  const ClutterExperimentResult words = run_clutter_experiment(o, core::Provenance{});
  test::expect_schema_valid("experiment_clutter.schema.json", o.json);
  o.json = temp.path() / "clutter_pooled.json";
  o.mot_classifier = ClutterMotClassifier::kPooled;
  o.mot_word_weight = 0;
  const ClutterExperimentResult pooled0 = run_clutter_experiment(o, core::Provenance{});
  o.mot_word_weight = 1;
  const ClutterExperimentResult pooled1 = run_clutter_experiment(o, core::Provenance{});
  test::expect_schema_valid("experiment_clutter.schema.json", o.json);
  ASSERT_EQ(words.cells.size(), plain.cells.size());
  ASSERT_EQ(pooled0.cells.size(), plain.cells.size());
  ASSERT_EQ(pooled1.cells.size(), plain.cells.size());
  bool any_model = false;
  for (std::size_t i = 0; i < plain.cells.size(); ++i) {
    const ClutterCell& t = plain.cells[i];
    for (const ClutterCell* c : {&words.cells[i], &pooled0.cells[i], &pooled1.cells[i]}) {
      ASSERT_TRUE(c->theta.has_value());
      EXPECT_EQ(c->views, t.views);
      EXPECT_DOUBLE_EQ(c->theta->supervised, t.supervised);
      EXPECT_EQ(c->theta->supervised_per_object, t.supervised_per_object);
      EXPECT_EQ(c->theta->cross_seed.has_value(), t.cross_seed.has_value());
      if (t.cross_seed) {
        EXPECT_DOUBLE_EQ(*c->theta->cross_seed, *t.cross_seed);
      }
      EXPECT_EQ(c->theta->cross_seed_per_object, t.cross_seed_per_object);
      EXPECT_EQ(c->cross_seed.has_value(), t.cross_seed.has_value());
      EXPECT_GE(c->supervised, 0.0);
      EXPECT_LE(c->supervised, 1.0);
    }
    EXPECT_DOUBLE_EQ(pooled0.cells[i].supervised, words.cells[i].supervised);
    EXPECT_EQ(pooled0.cells[i].supervised_confusion.counts,
              words.cells[i].supervised_confusion.counts);
    EXPECT_EQ(pooled0.cells[i].cross_seed_per_object, words.cells[i].cross_seed_per_object);
    any_model = any_model || t.note.empty();
  }
  EXPECT_TRUE(any_model);
  // Another pooled variant at word weights 0 and 1 (into `json`): at weight 0 it is the
  // classifier by words, cell by cell; at 1 every cell's score is a share.
  const auto at_weights_0_and_1 = [&](const char* json) {
    o.json = temp.path() / json;
    o.mot_word_weight = 0;
    ClutterExperimentResult r0 = run_clutter_experiment(o, core::Provenance{});
    o.mot_word_weight = 1;
    ClutterExperimentResult r1 = run_clutter_experiment(o, core::Provenance{});
    test::expect_schema_valid("experiment_clutter.schema.json", o.json);
    EXPECT_EQ(r0.cells.size(), words.cells.size());
    EXPECT_EQ(r1.cells.size(), words.cells.size());
    for (std::size_t i = 0; i < std::min(words.cells.size(), r0.cells.size()); ++i) {
      EXPECT_EQ(r0.cells[i].supervised_confusion.counts,
                words.cells[i].supervised_confusion.counts);
    }
    for (const auto& c : r1.cells) {
      EXPECT_GE(c.supervised, 0.0);
      EXPECT_LE(c.supervised, 1.0);
    }
    return r1;
  };
  // Session 30: the multinomials against a shared background.
  o.mot_word_background = true;
  const ClutterExperimentResult background1 = at_weights_0_and_1("clutter_background.json");
  EXPECT_EQ(background1.document.at("options").at("mot_word_background"), true);
  o.mot_word_background = false;
  // Session 30: the pooled counts (every view weighing the same is the default, run above).
  o.mot_word_per_view = false;
  const ClutterExperimentResult counts1 = at_weights_0_and_1("clutter_counts.json");
  EXPECT_EQ(counts1.document.at("options").at("mot_word_per_view"), false);
  EXPECT_EQ(pooled1.document.at("options").at("mot_word_per_view"), true);
  o.mot_word_per_view = true;
  // Session 31: documents with their descriptors' quarter turns (4 times the tokens; the
  // same cached views).
  o.json = temp.path() / "clutter_turns.json";
  o.mot_word_weight = 0.25;
  o.right_angle_words = true;
  const ClutterExperimentResult turns = run_clutter_experiment(o, core::Provenance{});
  test::expect_schema_valid("experiment_clutter.schema.json", o.json);
  EXPECT_EQ(turns.document.at("options").at("right_angle_words"), true);
  EXPECT_EQ(pooled1.document.at("options").at("right_angle_words"), false);
  ASSERT_EQ(turns.cells.size(), words.cells.size());
  for (const auto& c : turns.cells) {
    EXPECT_GE(c.supervised, 0.0);
    EXPECT_LE(c.supervised, 1.0);
  }
  o.right_angle_words = false;
  // The cache holds attempts = 3: a run of the session-21 harness (1) on it is refused.
  o.overwrite = false;
  o.json.clear();
  o.attempts = 1;
  EXPECT_THROW(run_clutter_experiment(o, core::Provenance{}), Error);
}

TEST(ClutterExperiment, QuickRunScoresEveryCellAndReusesItsCache) {
  const test::TempDir temp("proprio_clutter_experiment");
  ClutterExperimentOptions o;
  o.quick = true;
  o.objects = "book,cd";
  o.clutter = "mug";
  o.background = "plain";
  o.seeds = {2};
  o.cache = temp.path() / "cache";
  o.json = temp.path() / "clutter.json";
  o.figure = temp.path() / "fig.png";
  o.progress = false;
  const ClutterExperimentResult r = run_clutter_experiment(o, core::Provenance{});
  ASSERT_EQ(r.pushes.size(), 2U * 3U);  // 2 objects x 1 trial x 3 pushes
  ASSERT_EQ(r.cells.size(), 2U * 2U);   // 2 fractions x 2 topic counts
  for (const auto& c : r.cells) {
    EXPECT_GE(c.supervised, 0.0);
    EXPECT_LE(c.supervised, 1.0);
    EXPECT_GE(c.unsupervised, 0.0);
    EXPECT_LE(c.unsupervised, 1.0);
    // Every held-out render with features is a row of both matrices (objects x objects).
    EXPECT_EQ(c.supervised_confusion.rows, (std::vector<std::string>{"book", "cd"}));
    EXPECT_EQ(c.supervised_confusion.total(), c.unsupervised_confusion.total());
    EXPECT_LE(c.supervised_confusion.total(), 2 * 6);
    EXPECT_FALSE(c.cross_trial.has_value());  // one trial: no trial to leave out
    // The default classifier (pooled) has theta's scores beside.
    ASSERT_TRUE(c.theta.has_value());
    EXPECT_GE(c.theta->supervised, 0.0);
    EXPECT_LE(c.theta->supervised, 1.0);
  }
  EXPECT_TRUE(fs::exists(o.figure));
  const core::Json j = core::read_json(o.json);
  EXPECT_EQ(j.at("format"), kClutterExperimentFormat);
  EXPECT_EQ(j.at("cells").size(), 4U);
  test::expect_schema_valid("experiment_clutter.schema.json", o.json);
  const fs::path manifest = o.cache / "seed_2" / "book_t1" / "clutter_cache.json";
  ASSERT_TRUE(fs::exists(manifest));
  const auto written = fs::last_write_time(manifest);
  // Each executed push's segmented views are cached beside its episode; a damaged file is
  // segmented again (the same figures below).
  std::vector<fs::path> views;
  for (const auto& e : fs::recursive_directory_iterator(o.cache)) {
    if (e.path().filename() == "views_dense.bin") views.push_back(e.path());
  }
  ASSERT_FALSE(views.empty());
  const auto size = fs::file_size(views.front());
  fs::resize_file(views.front(), size / 2);
  // Again from the cache: nothing recorded again, the same figures.
  o.overwrite = true;  // --json and --figure exist
  const ClutterExperimentResult again = run_clutter_experiment(o, core::Provenance{});
  EXPECT_EQ(fs::last_write_time(manifest), written);
  EXPECT_EQ(fs::file_size(views.front()), size);
  ASSERT_EQ(again.cells.size(), r.cells.size());
  for (std::size_t i = 0; i < r.cells.size(); ++i) {
    EXPECT_DOUBLE_EQ(again.cells[i].supervised, r.cells[i].supervised);
  }
  // A cache recorded with other options is refused (without --overwrite).
  o.overwrite = false;
  o.json.clear();
  o.figure.clear();
  o.min_shift = 0.06;
  EXPECT_THROW(run_clutter_experiment(o, core::Provenance{}), Error);
}

}  // namespace
}  // namespace proprio::loop
