// proprio selfsupervise, run as a user would: a tiny run on a simulated table of two objects
// (blob views, one push each, a vocabulary and LDA model made here), and bad options as one line
// and exit 2.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <optional>
#include <string>

#include "../support/temp_dir.hpp"
#include "cli_run.hpp"
#include "proprio/core/json_io.hpp"
#include "proprio/core/text.hpp"
#include "proprio/topics/lda_model_io.hpp"
#include "tiny_models.hpp"

namespace proprio::app {
namespace {
namespace fs = std::filesystem;
using proprio::test::run_cli;

#define EXPECT_HAS(haystack, needle) \
  EXPECT_NE(std::string(haystack).find(needle), std::string::npos) << (haystack)

class SelfSuperviseCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    temp_.emplace("proprio_selfsup_cli");
    topics::LdaModel m = test::write_tiny_vocabulary_and_model(dir(), "selfsupervise_cli_test");
    m.lambda.conservativeResize(Eigen::NoChange, m.lambda.cols() + 1);
    m.lambda.rightCols(1).setOnes();
    topics::save_lda_model(m, dir() / "other.lda");
    // A model of the vocabulary's 24 words and the 28 colour words (--colour-words).
    m.lambda.conservativeResize(Eigen::NoChange, 24 + 28);
    m.lambda.rightCols(28).setOnes();
    topics::save_lda_model(m, dir() / "colour.lda");
  }
  static void TearDownTestSuite() { temp_.reset(); }
  static std::string file(const std::string& name) { return (dir() / name).string(); }
  static std::string inputs(const std::string& lda = "m.lda") {
    return " --model " + file(lda) + " --vocabulary " + file("v.vocab");
  }
  static const fs::path& dir() { return temp_->path(); }
  // NOLINTNEXTLINE(readability-identifier-naming)
  static std::optional<test::TempDir> temp_;
};
std::optional<test::TempDir> SelfSuperviseCli::temp_;

TEST_F(SelfSuperviseCli, LearnsTwoObjectsAndWritesWhatHappened) {
  const auto r = run_cli(
      "selfsupervise --objects book,bottle --pushes 1 --clear-pushes 1 "
      "--views blob --held-out 3 --width 160 --height 120 --step 4 "
      "--min-features 3 --seed 3 -q" +
      inputs() + " --out " + file("run") + " --json " + file("run.json"));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_HAS(r.out, "held-out accuracy: Mixture of Topics");
  EXPECT_HAS(r.out, "singulation");
  const core::Json j = core::read_json(dir() / "run.json");
  EXPECT_EQ(j["format"], "proprio.selfsupervise");
  EXPECT_EQ(j["classes"].size(), 2U);
  EXPECT_TRUE(j["ground_truth"].contains("mot_confusion"));
  EXPECT_FALSE(j["ground_truth"].contains("colour_accuracy"));  // only with --colour-words
  // A model of the vocabulary's words alone keeps SIFT words only (colour_words_from_model).
  EXPECT_FALSE(j["options"]["colour_words"].get<bool>());
  EXPECT_EQ(j["ground_truth"]["objects"].size(), 2U);
  EXPECT_TRUE(fs::exists(dir() / "run" / "decisions.jsonl"));
  EXPECT_TRUE(fs::exists(dir() / "run" / "selfsupervise.json"));
  std::ifstream log(dir() / "run" / "decisions.jsonl");
  std::string first;
  std::getline(log, first);
  EXPECT_EQ(core::Json::parse(first)["event"], "start");
  // The same directory again without --overwrite: exit 2.
  const auto again =
      run_cli("selfsupervise --objects book,bottle" + inputs() + " --out " + file("run"));
  EXPECT_EQ(again.code, 2);
  EXPECT_HAS(again.err, "already exists");
}

TEST_F(SelfSuperviseCli, ColourWordsScoreCByTheColourWordsBesideTheMixtureOfTopics) {
  // --colour-words: c also by the colour words alone, printed and in the JSON beside the MoT's;
  // --mot-classifier colour makes it the held-out figure (c) itself.
  const std::string run =
      "selfsupervise --objects book,bottle --pushes 1 --clear-pushes 1 --views blob --held-out 3 "
      "--width 160 --height 120 --step 4 --min-features 3 --seed 3 -q --colour-words" +
      inputs("colour.lda");
  const auto r = run_cli(run + " --out " + file("col") + " --json " + file("col.json"));
  ASSERT_EQ(r.code, 0) << r.err;
  const core::Json g = core::read_json(dir() / "col.json")["ground_truth"];
  ASSERT_TRUE(g.contains("colour_accuracy")) << g.dump();
  const double colour = g["colour_accuracy"].get<double>();
  EXPECT_HAS(r.out, core::printf_string("held-out accuracy: Mixture of Topics %.1f%%, argmax "
                                        "theta %.1f%%, colour %.1f%%",
                                        100 * g["mot_accuracy"].get<double>(),
                                        100 * g["argmax_accuracy"].get<double>(), 100 * colour));
  ASSERT_EQ(g["objects"].size(), 2U);
  EXPECT_TRUE(g["objects"][0].contains("colour_accuracy"));
  const auto c = run_cli(run + " --mot-classifier colour --out " + file("colc") + " --json " +
                         file("colc.json"));
  ASSERT_EQ(c.code, 0) << c.err;
  const core::Json h = core::read_json(dir() / "colc.json");
  EXPECT_EQ(h["options"]["mot_classifier"], "colour");
  EXPECT_EQ(h["ground_truth"]["mot_accuracy"].get<double>(), colour);
  EXPECT_EQ(h["ground_truth"]["colour_accuracy"].get<double>(), colour);
  EXPECT_EQ(h["ground_truth"]["argmax_accuracy"], g["argmax_accuracy"]);
  // A model made with colour words turns them on without the flag (colour_words_from_model): the
  // same run, the same figures, and the record says they were on.
  std::string plain = run;
  plain.erase(plain.find(" --colour-words"), std::string(" --colour-words").size());
  const auto a = run_cli(plain + " --out " + file("cola") + " --json " + file("cola.json"));
  ASSERT_EQ(a.code, 0) << a.err;
  const core::Json k = core::read_json(dir() / "cola.json");
  EXPECT_TRUE(k["options"]["colour_words"].get<bool>());
  EXPECT_EQ(k["ground_truth"]["colour_accuracy"].get<double>(), colour);
  EXPECT_EQ(k["ground_truth"]["mot_accuracy"], g["mot_accuracy"]);
}

TEST_F(SelfSuperviseCli, MotSmoothingReachesTheRunsMixtureOfTopics) {
  // --mot-smoothing s is the robot's Mixture of Topics' theta smoothing (MotOptions::smoothing,
  // which topics::fit_mot keeps in the model): the run's record says the s it used; the
  // default 0 keeps theta as it is. Out of [0, 0.5]: BadOptionsAreOneLineAndExit2.
  const std::string run =
      "selfsupervise --objects book,bottle --pushes 1 --clear-pushes 1 --views blob --held-out 3 "
      "--width 160 --height 120 --step 4 --min-features 3 --seed 3 -q" +
      inputs();
  for (const double s : {0.0, 0.05}) {
    const std::string name = s > 0 ? "smooth" : "plain";
    const std::string flag = s > 0 ? " --mot-smoothing 0.05" : "";
    const auto r = run_cli(run + flag + " --out " + file(name) + " --json " + file(name + ".json"));
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(core::read_json(dir() / (name + ".json"))["options"]["mot_smoothing"], s);
  }
}

TEST_F(SelfSuperviseCli, MoreRoundsThanObjectsAreMergedIntoTwoClasses) {
  // --rounds 3 for two objects, --same-object 10 (any two round classes judged one object): the
  // robot never judges both objects learned, runs all three rounds and merges them into two
  // classes; the JSON says which class each round became, the log has every merge.
  const auto r = run_cli(
      "selfsupervise --objects book,bottle --pushes 1 --clear-pushes 1 "
      "--views blob --held-out 3 --width 160 --height 120 --step 4 "
      "--min-features 3 --seed 3 -q --rounds 3 --same-object 10" +
      inputs() + " --out " + file("rounds") + " --json " + file("rounds.json"));
  ASSERT_EQ(r.code, 0) << r.err;
  const core::Json j = core::read_json(dir() / "rounds.json");
  ASSERT_EQ(j["classes"].size(), 2U);
  EXPECT_EQ(j["classes"][0], "object_1");
  EXPECT_EQ(j["classes"][1], "object_2");
  ASSERT_EQ(j["round_class"].size(), 3U);
  EXPECT_EQ(j["stop_reasons"].size(), 3U);
  for (const auto& c : j["round_class"]) {
    EXPECT_GE(c.get<int>(), -1);
    EXPECT_LE(c.get<int>(), 1);
  }
  EXPECT_EQ(j["options"]["rounds"], 3);
  std::ifstream log(dir() / "rounds" / "decisions.jsonl");
  int round_lines = 0;  // each round's class, one "merge" line a round run
  for (std::string line; std::getline(log, line);) {
    const core::Json e = core::Json::parse(line);
    if (e["event"] == "merge" && e.contains("round")) ++round_lines;
  }
  EXPECT_EQ(round_lines, 3);
}

TEST_F(SelfSuperviseCli, CeilingOnlyScoresTheRendersWithoutARobotRun) {
  // --ceiling-only: no push (no decision log, nothing learned), only the ladder's render rungs
  // (a0, a0_table) trained and scored, printed in the brief.
  const auto r = run_cli(
      "selfsupervise --objects book,bottle --ceiling-only --held-out 3 --width 160 --height 120 "
      "--step 4 --min-features 3 --seed 3 -q" +
      inputs() + " --out " + file("ceiling") + " --json " + file("ceiling.json"));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_HAS(r.out, "learned 0 of 0 classes from 0 views");
  EXPECT_HAS(r.out, "ladder a0 ");
  EXPECT_FALSE(fs::exists(dir() / "ceiling" / "decisions.jsonl"));
  const core::Json j = core::read_json(dir() / "ceiling.json");
  const core::Json& rungs = j["ground_truth"]["oracle_ladder"]["rungs"];
  ASSERT_GE(rungs.size(), 2U);
  EXPECT_EQ(rungs[0]["name"], "a0");
  EXPECT_EQ(rungs[0]["classes"], 2);
  EXPECT_EQ(rungs[0]["training_views"], 48);  // kLadderRenders per object
  EXPECT_EQ(rungs[2]["classes"], 0);          // (a): no pushes, nothing trained
}

TEST_F(SelfSuperviseCli, BadOptionsAreOneLineAndExit2) {
  const std::string out = " --out " + file("bad");
  const struct {
    std::string args;
    std::string message;
  } cases[] = {
      {"--objects book,unicorn" + inputs() + out, "unknown object 'unicorn'"},
      {"--objects book,cd,book" + inputs() + out, "named twice"},
      {"--objects book,,cd" + inputs() + out, "empty object name"},
      {"--objects book --pushes 0" + inputs() + out, "pushes"},
      {"--objects book,cd --free-space 0.5" + inputs() + out, "free-space"},
      {"--objects book,cd --free-space -0.1" + inputs() + out, "free-space"},
      {"--objects book,cd --split-colour 11" + inputs() + out, "split-colour"},
      {"--objects book,cd --split-colour -1" + inputs() + out, "split-colour"},
      {"--objects book,cd --singulate-tries 11" + inputs() + out, "singulate-tries"},
      {"--objects book,cd --singulate-tries -1" + inputs() + out, "singulate-tries"},
      {"--objects book,cd --switch-tries 6" + inputs() + out, "switch-tries"},
      {"--objects book,cd --switch-tries -1" + inputs() + out, "switch-tries"},
      {"--objects book,cd --repeat-tries 6" + inputs() + out, "repeat-tries"},
      {"--objects book,cd --repeat-share 0" + inputs() + out, "repeat-share"},
      {"--objects book,cd --recheck-tries 6" + inputs() + out, "recheck-tries"},
      {"--objects book,cd --recheck-tries 1 --choice dirichlet" + inputs() + out,
       "recheck_tries needs choice looks"},
      {"--objects book,cd --claims-by words" + inputs() + out, "claims-by"},
      {"--objects book,cd --claims-by none" + inputs() + out, "claims_by none is not a claim"},
      {"--objects book,cd --claims-by view-words --choice dirichlet" + inputs() + out,
       "claims_by view-words needs choice looks"},
      {"--objects book,cd --claims-by descriptors --choice dirichlet" + inputs() + out,
       "claims_by descriptors needs choice looks"},
      {"--objects book,cd --other-claims-by colour" + inputs() + out,
       "other_claims_by must be another signal"},
      {"--objects book,cd --descriptor-ratio 1.5" + inputs() + out, "descriptor-ratio"},
      {"--objects book,cd --mot-word-weight 1.5" + inputs() + out, "mot-word-weight"},
      {"--objects book,cd --mot-word-weight -0.1" + inputs() + out, "mot-word-weight"},
      {"--objects book,cd --mot-classifier words" + inputs() + out, "mot-classifier"},
      {"--objects book,cd --mot-smoothing 0.6" + inputs() + out, "mot-smoothing"},
      {"--objects book,cd --mot-smoothing -0.1" + inputs() + out, "mot-smoothing"},
      {"--objects book,cd --refind-colour 1.5" + inputs() + out, "refind-colour"},
      {"--objects book,cd --claims-by look-words --colour-first-look" + inputs() + out,
       "colour_first_look"},
      {"--objects book,cd --rounds 1" + inputs() + out, "fewer than the 2 objects"},
      {"--objects book,cd --rounds 65" + inputs() + out, "rounds"},
      {"--objects book,cd --same-object -1" + inputs() + out, "same-object"},
      {"--objects book,cd --same-object-by colour" + inputs() + out,
       "same_object_by colour judges the rounds of --rounds"},
      {"--objects book,cd --rounds 3 --same-object-by hue" + inputs() + out, "same-object-by"},
      {"--objects book,cd --rounds 3 --same-colour 1.5" + inputs() + out, "same-colour"},
      {"--objects book,cd --moved-colours --colour-first-look" + inputs() + out,
       "two sources of a round's colours"},
      {"--objects book,cd --colour-by-look --claims-by looks" + inputs() + out,
       "colour_by_look compares a blob with each look"},
      {"--objects book,cd --table-colours-out --claims-by looks" + inputs() + out,
       "table_colours_out leaves the table's colours out"},
      {"--objects book,cd --moved-colours --claims-by looks" + inputs() + out,
       "moved_colours chooses the pixels"},
      {"--objects book,cd --crowded-reclears 1" + inputs() + out,
       "crowded_reclears needs learn_clearance"},
      {"--objects book,cd --learn-clearance 0.05 --crowded-reclears 11" + inputs() + out,
       "crowded-reclears"},
      {"--objects book,cd --own-words 1" + inputs() + out, "own-words"},
      {"--objects book,cd --own-topics 1" + inputs() + out, "own-topics"},
      {"--objects book,mug,bottle,spirit-level,rabbit,cd,calculator,giraffe,bike" + inputs() + out,
       "do not fit on the table"},
      {"--objects book,cd" + inputs("other.lda") + out,
       "not the vocabulary the model was made with"},
      {"--objects book,cd --vocabulary " + file("v.vocab") + out, "--model"},
      // --colour-words needs a model of the vocabulary's words + 28 (recognize train
      // --colour-words); the error names the model file. Not with the oracle ladder.
      {"--objects book,cd --colour-words" + inputs() + out,
       file("m.lda") + ": 24 words, but --colour-words needs the vocabulary's 24 + 28"},
      {"--objects book,cd --colour-words --oracle-ladder" + inputs() + out,
       "colour words do not go with the oracle ladder"},
      // A model made with colour words turns them on (colour_words_from_model), so it is refused
      // where they are, naming the model; with the option off it is not the vocabulary's.
      {"--objects book,cd --oracle-ladder" + inputs("colour.lda") + out,
       file("colour.lda") + ": made with colour words (52 = the vocabulary's 24 + 28), but "
                            "selfsupervise: colour words do not go with the oracle ladder"},
      {"--objects book,cd --ceiling-only" + inputs("colour.lda") + out,
       "colour words do not go with the oracle ladder, its ceiling"},
      {"--objects book,cd --no-colour-words-from-model" + inputs("colour.lda") + out,
       "not the vocabulary the model was made with"},
      // c by the colour words alone needs them.
      {"--objects book,cd --mot-classifier colour" + inputs() + out,
       "mot_classifier colour scores by the colour words alone: it needs colour_words"},
  };
  for (const auto& c : cases) {
    const auto r = run_cli("selfsupervise " + c.args);
    EXPECT_EQ(r.code, 2) << c.args << "\n" << r.err;
    EXPECT_HAS(r.err, c.message);
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists(dir() / "bad")) << c.args;
  }
}

}  // namespace
}  // namespace proprio::app
