// Golden outputs: representative results of the CLI pinned as they were before the library
// refactoring of issue 14 (one library call per command), and checked after every change.
//
// Pinned: a simulated push episode's Motion-Likelihood segmentation (segment.json), a trained
// online-LDA model with its train.json, and a k-means vocabulary with its build JSON. What may
// differ between two runs of the same code is left out: provenance (time, commit, command line
// with its temporary paths), timings (any key holding "seconds" or "per_s"), and paths.
// Everything else is compared exactly: numbers to the last bit, arrays element by element.
//
// The LDA E-step and the k-means assignment pick an instruction set at run time; the golden runs
// force the portable kernels (PROPRIO_TOPICS_KERNEL=generic, one thread) where proprio offers it,
// so that the pinned bits do not depend on the processor.
//
// When an output is meant to change, rerun with PROPRIO_GOLDEN_UPDATE=1 to rewrite the files in
// tests/golden/, and name the change in the commit.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "../support/named_corpus.hpp"
#include "../support/paths.hpp"
#include "../support/temp_dir.hpp"
#include "cli_run.hpp"
#include "proprio/core/files.hpp"
#include "proprio/core/json_io.hpp"
#include "proprio/features/vocabulary.hpp"
#include "proprio/topics/corpus_io.hpp"
#include "proprio/topics/lda_model_io.hpp"
#include "proprio/topics/synthetic.hpp"

namespace proprio {
namespace {
namespace fs = std::filesystem;
using test::run_cli;

fs::path golden_dir() { return test::source_dir() / "tests" / "golden"; }

bool updating() {
  const char* v = std::getenv("PROPRIO_GOLDEN_UPDATE");
  return v != nullptr && std::string(v) == "1";
}

// Whether a key's value may differ between two runs of the same code.
bool volatile_key(const std::string& key) {
  return key == "provenance" || key == "built_by" || key.find("seconds") != std::string::npos ||
         key.find("per_s") != std::string::npos;
}

// The document without what may differ between runs (see volatile_key), recursively; absolute
// paths (the test's temporary directory) reduced to their last component.
core::Json stable(const core::Json& j) {
  if (j.is_string()) {
    const std::string v = j.get<std::string>();
    if (!v.empty() && v.front() == '/') return fs::path(v).filename().string();
    return j;
  }
  if (j.is_object()) {
    core::Json out = core::Json::object();
    for (auto it = j.begin(); it != j.end(); ++it) {
      if (!volatile_key(it.key())) out[it.key()] = stable(it.value());
    }
    return out;
  }
  if (j.is_array()) {
    core::Json out = core::Json::array();
    for (const auto& v : j) out.push_back(stable(v));
    return out;
  }
  return j;
}

// Compares `produced` (a JSON result) with tests/golden/`name`, or rewrites the golden file.
void expect_golden_json(const fs::path& produced, const std::string& name) {
  const core::Json now = stable(core::read_json(produced));
  const fs::path golden = golden_dir() / name;
  if (updating()) {
    core::write_file_atomic(golden, now.dump(1) + "\n");
    GTEST_SKIP() << "rewrote " << golden;
  }
  ASSERT_TRUE(fs::is_regular_file(golden)) << golden;
  const core::Json pinned = core::read_json(golden);
  // The diff names the first differing values, as JSON Patch.
  EXPECT_EQ(now, pinned) << name << " differs from the golden output: "
                         << core::Json::diff(pinned, now).dump().substr(0, 2000);
}

// Copies a produced binary file to tests/golden/ when updating.
void update_golden_file(const fs::path& produced, const std::string& name) {
  if (updating())
    fs::copy_file(produced, golden_dir() / name, fs::copy_options::overwrite_existing);
}

class GoldenOutputs : public ::testing::Test {
 protected:
  void SetUp() override {
    ::setenv("PROPRIO_TOPICS_KERNEL", "generic", 1);
    if (updating()) fs::create_directories(golden_dir());
  }
  test::TempDir dir_{"proprio_golden_"};
  [[nodiscard]] std::string at(const std::string& name) const {
    return (dir_.path() / name).string();
  }
};

TEST_F(GoldenOutputs, MotionLikelihoodSegmentationOfASimulatedPush) {
  auto r = run_cli("sim record --scenario push --object mug --background moving --seed 7 --out " +
                   at("episode"));
  ASSERT_EQ(r.code, 0) << r.err;
  r = run_cli("segment " + at("episode") + " --method ml --out " + at("seg") + " --json " +
              at("segment.json"));
  ASSERT_EQ(r.code, 0) << r.err;
  expect_golden_json(at("segment.json"), "segment_ml_push_mug_moving_7.json");
}

TEST_F(GoldenOutputs, OnlineLdaModelOfASyntheticCorpus) {
  topics::SyntheticCorpusOptions o;
  o.num_topics = 4;
  o.num_words = 60;
  o.num_documents = 200;
  o.mean_length = 40;
  o.seed = 5;
  topics::write_corpus(test::named_synthetic_corpus(o), dir_.path() / "corpus",
                       topics::CorpusFormat::kUci);
  const auto r = run_cli("lda train --corpus " + at("corpus") +
                         " -k 4 --batch 40 --passes 2 --threads 1 --seed 2 --model " + at("m.lda") +
                         " --json " + at("train.json"));
  ASSERT_EQ(r.code, 0) << r.err;
  update_golden_file(at("m.lda"), "online_lda_k4.lda");
  expect_golden_json(at("train.json"), "online_lda_k4.train.json");
  if (updating()) return;
  // The model's numbers, bit for bit (the file's provenance holds the time and differs).
  const topics::LdaModel now = topics::load_lda_model(at("m.lda"));
  const topics::LdaModel pinned = topics::load_lda_model(golden_dir() / "online_lda_k4.lda");
  ASSERT_EQ(now.lambda.rows(), pinned.lambda.rows());
  ASSERT_EQ(now.lambda.cols(), pinned.lambda.cols());
  EXPECT_TRUE(now.lambda == pinned.lambda)
      << "lambda differs; max |difference| " << (now.lambda - pinned.lambda).cwiseAbs().maxCoeff();
  EXPECT_EQ(now.alpha, pinned.alpha);
  EXPECT_EQ(now.eta, pinned.eta);
}

TEST_F(GoldenOutputs, KmeansVocabularyOfOpencvSamples) {
  const fs::path samples = PROPRIO_OPENCV_SAMPLES;
  const std::vector<std::pair<std::string, std::vector<std::string>>> set{
      {"fruit", {"apple.jpg", "orange.jpg", "fruits.jpg"}},
      {"scene", {"box_in_scene.png", "graf1.png"}}};
  for (const auto& [cls, files] : set) {
    fs::create_directories(dir_.path() / "images" / cls);
    for (const auto& f : files) fs::copy_file(samples / f, dir_.path() / "images" / cls / f);
  }
  // --min-contrast 0: every grid patch, as vocab build took them before it shared recognize's
  // feature options (whose default, 2, drops flat patches); the words are pinned from then.
  const auto r = run_cli("vocab build --images " + at("images") +
                         " --words 16 --per-image 60 --dense --min-contrast 0 --seed 3 --threads 1 "
                         "--no-progress --out " +
                         at("v.vocab") + " --json " + at("build.json"));
  ASSERT_EQ(r.code, 0) << r.err;
  update_golden_file(at("v.vocab"), "vocabulary_16.vocab");
  expect_golden_json(at("build.json"), "vocabulary_16.build.json");
  if (updating()) return;
  const features::Vocabulary now = features::read_vocabulary(at("v.vocab"));
  const features::Vocabulary pinned =
      features::read_vocabulary(golden_dir() / "vocabulary_16.vocab");
  ASSERT_EQ(now.size(), pinned.size());
  ASSERT_EQ(now.dimension(), pinned.dimension());
  EXPECT_EQ(cv::norm(now.words(), pinned.words(), cv::NORM_INF), 0.0);
}

}  // namespace
}  // namespace proprio
