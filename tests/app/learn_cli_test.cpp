// proprio learn, run as a user would: a tiny run on a simulated table (one object to learn, one
// of clutter, two pushes, 200 x 150) writing the run directory of the learn/report contract, and
// bad input as one line and exit 2.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <string>

#include "../support/temp_dir.hpp"
#include "cli_run.hpp"
#include "proprio/core/files.hpp"
#include "proprio/core/json_io.hpp"
#include "proprio/core/text.hpp"

namespace proprio::app {
namespace {
namespace fs = std::filesystem;
using proprio::test::run_cli;

#define EXPECT_HAS(haystack, needle) \
  EXPECT_NE((haystack).find(needle), std::string::npos) << (haystack)

class LearnCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { temp_.emplace("proprio_learn_cli"); }
  static void TearDownTestSuite() { temp_.reset(); }
  static std::string file(const std::string& name) { return (dir() / name).string(); }
  static const fs::path& dir() { return temp_->path(); }
  // NOLINTNEXTLINE(readability-identifier-naming)
  static std::optional<test::TempDir> temp_;
};
std::optional<test::TempDir> LearnCli::temp_;

TEST_F(LearnCli, TinyRunWritesTheRunDirectory) {
  fs::create_directories(dir());
  const auto r = run_cli(
      "learn --objects book --clutter bottle --background plain --pushes 2 --width 200 "
      "--height 150 --words 20 --topics 2 --held-out 3 --min-features 3 --seed 3 "
      "--mot-word-weight 0.5 --mot-word-per-view --headline pooled --write-documents -q --out " +
      file("run") + " --json " + file("run.json"));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_HAS(r.out, "learned");
  const fs::path run = dir() / "run";
  const core::Json j = core::read_json(run / "learn.json");
  EXPECT_EQ(j["format"], "proprio.learn");
  EXPECT_EQ(j["format_version"], 1);
  EXPECT_TRUE(j["complete"].get<bool>());
  EXPECT_FALSE(fs::exists(run / "INCOMPLETE"));
  EXPECT_TRUE(fs::exists(run / "decisions.jsonl"));
  EXPECT_TRUE(fs::exists(run / "table.png"));
  // The robot learns what lies on the table, the clutter too (--learn-clutter, the default).
  ASSERT_EQ(j["objects"].size(), 2U);
  EXPECT_EQ(j["objects"][0]["class"], "object_1");
  EXPECT_TRUE(j["options"].contains("objects"));
  EXPECT_TRUE(j["timing"].is_array());
  EXPECT_EQ(j["clock"], "wall");
  ASSERT_TRUE(j["pushes"].is_array());
  ASSERT_FALSE(j["pushes"].empty());
  EXPECT_GT(j["objects"][0]["views"].get<int>(), 0);
  EXPECT_EQ(j["objects"][0]["truth"], "book");
  ASSERT_TRUE(j.contains("held_out"));
  EXPECT_TRUE(fs::exists(run / "vocabulary.vocab"));
  EXPECT_TRUE(fs::exists(run / "lda.model"));
  EXPECT_TRUE(fs::exists(run / "model.mot"));
  // --write-documents: every training view and every held-out view, one lda-c line each
  // ("count word:count ..."), after a header naming the words (the vocabulary's and 28 colour
  // words) and one line a model class.
  {
    std::istringstream in(core::read_file(run / "documents.txt"));
    std::string line;
    std::getline(in, line);
    EXPECT_EQ(line, "# proprio learn documents, version 1");
    std::getline(in, line);
    std::istringstream head(line);
    std::string k1;
    std::string k2;
    std::string k3;
    int words = 0;
    int vocabulary = 0;
    int classes = 0;
    head >> k1 >> words >> k2 >> vocabulary >> k3 >> classes;
    EXPECT_EQ(k1 + k2 + k3, "wordsvocabularyclasses");
    EXPECT_GT(vocabulary, 0);
    EXPECT_EQ(words, vocabulary + 28);  // colour words (the default)
    int views = 0;
    int named_views = 0;
    int held = 0;
    int class_lines = 0;
    while (std::getline(in, line)) {
      std::istringstream f(line);
      std::string kind;
      std::string skip;
      f >> kind;
      if (kind == "class") {
        ++class_lines;
        continue;
      }
      if (kind == "view") {
        ++views;
        std::string shows;
        f >> skip >> skip >> skip >> shows;  // its class, push, intended object, object
        // The ground-truth masks are recorded with --write-documents: a view names what it shows.
        if (shows != "-") ++named_views;
      } else if (kind == "held") {
        ++held;
        f >> skip;  // its object
      } else {
        ADD_FAILURE() << line;
        continue;
      }
      int n = -1;
      f >> n;
      int pairs = 0;
      std::string pair;
      while (f >> pair) {
        ++pairs;
        const std::size_t colon = pair.find(':');
        ASSERT_NE(colon, std::string::npos) << line;
        const int w = std::stoi(pair.substr(0, colon));
        EXPECT_TRUE(w >= 0 && w < words) << line;
        EXPECT_GT(std::stoi(pair.substr(colon + 1)), 0) << line;
      }
      EXPECT_EQ(pairs, n) << line;
    }
    int want_views = 0;
    for (const auto& o : j["objects"]) want_views += o["views"].get<int>();
    EXPECT_EQ(views, want_views);
    EXPECT_GT(named_views, views / 2);
    int want_held = 0;
    for (const auto& o : j["held_out_words"]["objects"]) want_held += o["held_out"].get<int>();
    EXPECT_GT(want_held, 0);
    EXPECT_EQ(held, want_held);
    EXPECT_EQ(class_lines, classes);
    EXPECT_GT(classes, 0);
  }
  double robot_seconds = 0;
  double perception = 0;
  for (const auto& p : j["pushes"]) {
    if (!p["executed"].get<bool>()) continue;
    const fs::path d = run / p["dir"].get<std::string>();
    for (const char* f : {"before.png", "after.png", "map.png", "mask.png", "frame.png"}) {
      EXPECT_TRUE(fs::exists(d / f)) << d / f;
    }
    EXPECT_EQ(p["plan"]["start_px"].size(), 2U);
    EXPECT_TRUE(p.contains("moved_intended"));
    // Issue 21's speed goal: each executed push's duration and its perception's processor time.
    EXPECT_GT(p["robot_seconds"].get<double>(), 0.0);
    EXPECT_GT(p["perception_cpu_seconds"].get<double>(), 0.0);
    robot_seconds += p["robot_seconds"].get<double>();
    perception += p["perception_cpu_seconds"].get<double>();
  }
  // The pushes' durations add up to the robot-clock stage; their perception is the perception
  // stages' processor time, less what the looks before the first push took.
  std::map<std::string, core::Json> stage;
  for (const auto& t : j["timing"]) stage[t["stage"].get<std::string>()] = t;
  EXPECT_NEAR(stage.at("push_robot_clock")["seconds"].get<double>(), robot_seconds, 1e-9);
  EXPECT_FALSE(stage.at("push_robot_clock").contains("cpu_seconds"));  // not this process's
  double perception_stages = 0;
  for (const char* s : {"segmentation", "words", "recognition"}) {
    if (stage.contains(s)) perception_stages += stage.at(s)["cpu_seconds"].get<double>();
  }
  EXPECT_GT(stage.at("segmentation")["cpu_seconds"].get<double>(), 0.0);
  EXPECT_LE(perception, perception_stages + 1e-9);
  EXPECT_GE(perception + 1e-9, stage.at("segmentation")["cpu_seconds"].get<double>());
  EXPECT_EQ(j["held_out"]["views_per_object"], 3);
  EXPECT_TRUE(j["held_out"]["mot"].contains("counts"));
  EXPECT_TRUE(j["held_out"]["argmax"].contains("accuracy"));
  // The held-out views classified by their words too, beside the MoT by theta of the same
  // documents (the same figure as held_out.mot), the pooled figure at --mot-word-weight.
  ASSERT_GT(j["model_classes"].size(), 0U);  // this run learns both objects
  {
    ASSERT_TRUE(j.contains("held_out_words")) << j.dump();
    const core::Json& w = j["held_out_words"];
    EXPECT_EQ(w["weight"].get<double>(), 0.5);
    EXPECT_EQ(w["theta"].get<double>(), j["held_out"]["mot"]["accuracy"].get<double>());
    ASSERT_EQ(w["word_weights"].size(), w["grid"].size());
    EXPECT_EQ(w["word_weights"][3].get<double>(), 0.5);
    EXPECT_EQ(w["grid"][3].get<double>(), w["pooled"].get<double>());
    EXPECT_EQ(w["grid"][0].get<double>(), w["words"].get<double>());
    ASSERT_EQ(w["objects"].size(), j["ground_truth"]["objects"].size());
    for (std::size_t i = 0; i < w["objects"].size(); ++i) {
      EXPECT_EQ(w["objects"][i]["held_out"], j["ground_truth"]["objects"][i]["held_out"]);
      EXPECT_EQ(w["objects"][i]["theta"].get<double>(),
                j["ground_truth"]["objects"][i]["mot_accuracy"].get<double>());
    }
    EXPECT_HAS(r.out, core::printf_string("pooled with word multinomials (weight 0.50) %.1f%%",
                                          100 * w["pooled"].get<double>()));
    // Both word multinomials scored in the one run: the pooled counts (pooled, grid) and every
    // view alike (pooled_per_view, grid_per_view); --mot-word-per-view makes the latter learn's.
    EXPECT_TRUE(j["options"]["mot_word_per_view"].get<bool>());
    EXPECT_TRUE(w["per_view"].get<bool>());
    ASSERT_EQ(w["grid_per_view"].size(), w["word_weights"].size());
    EXPECT_EQ(w["grid_per_view"][3].get<double>(), w["pooled_per_view"].get<double>());
    for (const auto& o : w["objects"]) {
      EXPECT_TRUE(o.contains("pooled_per_view")) << o.dump();
      EXPECT_EQ(o["grid_per_view"].size(), w["word_weights"].size());
    }
    EXPECT_HAS(r.out, core::printf_string("with per-view word multinomials (the pooled "
                                          "classifier): pooled %.1f%%",
                                          100 * w["pooled_per_view"].get<double>()));
    // --headline pooled: the pooled classifier (per view) is the headline, printed first.
    EXPECT_EQ(j["options"]["headline"], "pooled");
    ASSERT_TRUE(j.contains("headline")) << j.dump();
    EXPECT_EQ(j["headline"]["classifier"], "pooled_per_view");
    EXPECT_EQ(j["headline"]["accuracy"].get<double>(), w["pooled_per_view"].get<double>());
    EXPECT_EQ(j["headline"]["objects"].size(), w["objects"].size());
    const auto head = r.out.find(
        "held-out accuracy (headline, pooled words (weight 0.50, "
        "per-view word multinomials)): ");
    EXPECT_NE(head, std::string::npos) << r.out;
    EXPECT_LT(head, r.out.find("held-out accuracy: Mixture of Topics")) << r.out;
  }
  std::ifstream log(run / "decisions.jsonl");
  std::string first;
  std::getline(log, first);
  EXPECT_EQ(core::Json::parse(first)["event"], "start");
  // The same directory again without --overwrite: exit 2, the run left alone.
  const auto again = run_cli("learn --objects book --out " + file("run"));
  EXPECT_EQ(again.code, 2);
  EXPECT_HAS(again.err, "already exists");
  EXPECT_TRUE(fs::exists(run / "learn.json"));
}

TEST_F(LearnCli, TinyRunOnTheMovingBackdropCompletesAndWritesItsPage) {
  fs::create_directories(dir());
  const auto r = run_cli(
      "learn --objects book --clutter bottle --background moving --pushes 1 --width 200 "
      "--height 150 --words 20 --topics 2 --held-out 2 --min-features 3 --seed 3 -q --out " +
      file("moving"));
  ASSERT_EQ(r.code, 0) << r.err;
  const core::Json j = core::read_json(dir() / "moving" / "learn.json");
  EXPECT_TRUE(j["complete"].get<bool>());
  EXPECT_EQ(j["options"]["background"], "moving");
  EXPECT_TRUE(fs::exists(dir() / "moving" / "report.html"));     // written as the run's last step
  EXPECT_FALSE(fs::exists(dir() / "moving" / "documents.txt"));  // --write-documents is off
  EXPECT_HAS(r.out, "report: ");
  // One held-out figure everywhere: the printout, learn.json and the page's summary.
  const std::string key = "held-out accuracy: Mixture of Topics ";
  const auto at = r.out.find(key);
  ASSERT_NE(at, std::string::npos) << r.out;
  const std::string printed = r.out.substr(at + key.size(), r.out.find('%', at) - at - key.size());
  const double acc = j["held_out"]["mot"]["accuracy"].get<double>();
  EXPECT_EQ(printed, core::printf_string("%.1f", 100 * acc));
  EXPECT_EQ(j["ground_truth"]["mot_confusion"]["accuracy"].get<double>(), acc);
  EXPECT_EQ(j["ground_truth"]["mot_accuracy"].get<double>(), acc);
  // Coverage (ground truth): per named object the turns that pushed it as intended, printed.
  ASSERT_EQ(j["coverage"].size(), 1U);
  EXPECT_EQ(j["coverage"][0]["name"], "book");
  const int turns = j["coverage"][0]["turns"].get<int>();
  EXPECT_EQ(j["covered"].get<int>(), turns > 0 ? 1 : 0);
  EXPECT_HAS(r.out, core::printf_string("coverage (turns that pushed it as the intended object): "
                                        "book %d, %d of 1 named objects covered",
                                        turns, turns > 0 ? 1 : 0));
  // The headline is the colour words alone by default with colour words (--headline auto,
  // session 39's third rule): the same figure in the printout, learn.json and the page; the
  // pooled words classifier is still scored and printed beside it.
  EXPECT_EQ(j["options"]["headline"], "colour");  // the working options: auto resolved
  EXPECT_FALSE(j["options"]["mot_word_per_view"].get<bool>());
  EXPECT_FALSE(j["options"]["ladder_pooled"].get<bool>());  // session 33: off by default
  EXPECT_EQ(j["headline"]["classifier"], "colour");
  const double colour = j["held_out_words"]["colour"].get<double>();
  EXPECT_EQ(j["headline"]["accuracy"].get<double>(), colour);
  EXPECT_HAS(r.out, core::printf_string("held-out accuracy (headline, colour words (per-view "
                                        "colour multinomials)): %.1f%%",
                                        100 * colour));
  const double pooled = j["held_out_words"]["pooled"].get<double>();
  EXPECT_HAS(r.out, core::printf_string("(weight 0.25) %.1f%%", 100 * pooled));
  const std::string page = core::read_file(dir() / "moving" / "report.html");
  EXPECT_HAS(page, core::printf_string("Mixture of Topics <b>%.1f%%</b>", 100 * acc));
  EXPECT_HAS(page, core::printf_string("held-out accuracy (headline, colour words (per-view "
                                       "colour multinomials)) <b>%.1f%%</b>",
                                       100 * colour));
}

TEST_F(LearnCli, BadInputIsOneLineAndExit2) {
  fs::create_directories(dir());
  const std::string out = " --out " + file("bad");
  const struct {
    std::string args;
    std::string message;
  } cases[] = {
      {"--objects book,unicorn" + out, "unknown object 'unicorn'"},
      {"--objects book,cd,book" + out, "named twice"},
      {"--objects book,cd --clutter cd" + out, "named twice"},
      {"--objects book --pushes 0" + out, "pushes"},
      {"--objects book --rounds -1" + out, "rounds"},
      {"--objects book --rounds 1001" + out, "rounds"},
      {"--objects book --known-margin -2" + out, "known"},
      {"--objects book --known-margin 1001" + out, "known"},
      {"--objects book --identity-margin -2" + out, "identity-margin"},
      {"--objects book --identity-margin 1001" + out, "identity-margin"},
      {"--objects book --match-ratio 0" + out, "match"},
      {"--objects book --match-ratio 1.5" + out, "match"},
      {"--objects book --match-known -0.1" + out, "match"},
      {"--objects book --match-known 1.5" + out, "match"},
      {"--objects book --carry-regions=maybe" + out, "carry-regions"},
      {"--objects book --new-object nearest" + out, "new"},
      {"--objects book --candidates hull" + out, "candidates"},
      {"--objects book --candidate-height 0" + out, "candidate-height"},
      {"--objects book --candidate-height 0.5" + out, "candidate-height"},
      {"--objects book --candidate-step 0" + out, "candidate-step"},
      {"--objects book --candidate-step 1" + out, "candidate-step"},
      {"--objects book --start-clearance -0.01" + out, "start-clearance"},
      {"--objects book --start-clearance 0.5" + out, "start-clearance"},
      {"--objects book --candidate-footprint=maybe" + out, "candidate-footprint"},
      {"--objects book --prefer-pushable=maybe" + out, "prefer-pushable"},
      {"--objects book --mot-word-weight -0.1" + out, "mot-word-weight"},
      {"--objects book --mot-word-weight 1.5" + out, "mot-word-weight"},
      {"--objects book --mot-word-per-view=maybe" + out, "mot-word-per-view"},
      {"--objects book --headline best" + out, "headline"},
      {"--objects book --headline colour --no-colour-words" + out, "it needs colour words"},
      {"--objects book --ladder-pooled" + out, "needs --oracle-ladder"},
      {"--objects book --oracle-ladder" + out, "needs --no-colour-words"},
      {"--objects book --colour-words=maybe" + out, "colour-words"},
      {"--objects book --colour-weight 0" + out, "colour-weight"},
      {"--objects book --colour-weight 1001" + out, "colour-weight"},
      {"--objects book --new-object colour --known-margin 1" + out, "not with --new-object colour"},
      {"--objects book --region-agree 0.6" + out, "region-agree"},
      {"--objects book --lost-rechoose --region-agree 0" + out, "needs --region-agree"},
      {"--objects book --quick-pushes 0" + out, "quick-pushes"},
      {"--objects book --passes 0" + out, "passes"},
      {"--objects book --passes 101" + out, "passes"},
      {"--objects book --passes 2 --revisit-top-down --region-agree 0" + out,
       "needs --region-agree"},
      {"--objects book --region-agree 0.08 --revisit-top-down" + out, "--passes > 1"},
      {"--objects book --moving-wait -1" + out, "moving-wait"},
      {"--objects book --moving-wait 6" + out, "moving-wait"},
      {"--objects book --candidates blobs --moving-wait 0.3" + out, "needs the depth image"},
      {"--objects book --seg-touch-fm -0.1" + out, "seg-touch-fm"},
      {"--objects book --seg-touch-fm 1.5" + out, "seg-touch-fm"},
      {"--objects book,mug,bottle,rabbit,cd,calculator --clutter giraffe,bike,box" + out,
       "do not fit on the table"},
      {"--objects book --background stripes" + out, "background"},
      {"--objects book", "--out"},
  };
  for (const auto& c : cases) {
    const auto r = run_cli("learn -q " + c.args);
    EXPECT_EQ(r.code, 2) << c.args << "\n" << r.err;
    EXPECT_HAS(r.err, c.message);
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists(dir() / "bad")) << c.args;
  }
}

}  // namespace
}  // namespace proprio::app
