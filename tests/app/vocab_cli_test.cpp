// proprio vocab ...: build, info and quantize on a small image set made from opencv-doc photos,
// with JSON that matches its schema, files the library reads back, and bad input as one line.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <optional>

#include "../support/schema_check.hpp"
#include "../support/temp_dir.hpp"
#include "cli_run.hpp"
#include "proprio/core/json_io.hpp"
#include "proprio/features/vocabulary.hpp"
#include "proprio/topics/corpus_io.hpp"

namespace proprio {
namespace {
namespace fs = std::filesystem;
using test::expect_schema_valid;
using test::line_count;
using test::run_cli;

class VocabCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    temp_.emplace("proprio_vocab_cli");
    dir_ = temp_->path();
    const fs::path samples = PROPRIO_OPENCV_SAMPLES;
    const std::vector<std::pair<std::string, std::vector<std::string>>> set{
        {"fruit", {"apple.jpg", "orange.jpg", "fruits.jpg"}},
        {"scene", {"box_in_scene.png", "graf1.png"}}};
    for (const auto& [cls, files] : set) {
      fs::create_directories(dir_ / "images" / cls);
      for (const auto& f : files) fs::copy_file(samples / f, dir_ / "images" / cls / f);
    }
  }
  static void TearDownTestSuite() { temp_.reset(); }
  // NOLINTNEXTLINE(readability-identifier-naming)
  static std::optional<test::TempDir> temp_;
  // NOLINTNEXTLINE(readability-identifier-naming)
  static fs::path dir_;
};
std::optional<test::TempDir> VocabCli::temp_;
fs::path VocabCli::dir_;

TEST_F(VocabCli, BuildInfoQuantize) {
  const fs::path images = dir_ / "images";
  const fs::path v = dir_ / "v.vocab";
  const fs::path j = dir_ / "build.json";
  auto r = run_cli("vocab build --images " + images.string() +
                   " --words 20 --per-image 50 --dense --seed 3 --no-progress --out " + v.string() +
                   " --json " + j.string());
  ASSERT_EQ(r.code, 0) << r.err;
  expect_schema_valid("vocab_build.schema.json", j);
  const auto doc = core::read_json(j);
  EXPECT_EQ(doc["descriptors"].get<int>(), 5 * 50);
  EXPECT_EQ(doc["images"].get<int>(), 5);
  EXPECT_EQ(doc["classes"].get<int>(), 2);
  EXPECT_EQ(doc["words"].get<int>(), 20);
  EXPECT_GE(doc["iterations"].get<int>(), 1);
  EXPECT_GT(doc["cost"].get<double>(), 0);
  EXPECT_GT(doc["extract_seconds"].get<double>(), 0);
  const auto vocab = features::read_vocabulary(v);
  EXPECT_EQ(vocab.size(), 20);
  EXPECT_EQ(vocab.dimension(), 128);

  // The same seed gives the same words.
  const fs::path v2 = dir_ / "v2.vocab";
  r = run_cli("vocab build --images " + images.string() +
              " --words 20 --per-image 50 --dense --seed 3 --no-progress --out " + v2.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(cv::norm(features::read_vocabulary(v2).words(), vocab.words(), cv::NORM_INF), 0);

  const fs::path ij = dir_ / "info.json";
  r = run_cli("vocab info --vocab " + v.string() + " --json " + ij.string());
  ASSERT_EQ(r.code, 0) << r.err;
  expect_schema_valid("vocab_info.schema.json", ij);
  EXPECT_NE(core::read_json(ij)["built_by"]["command_line"].get<std::string>().find("--seed 3"),
            std::string::npos);

  const fs::path corpus = dir_ / "corpus";
  const fs::path qj = dir_ / "quantize.json";
  r = run_cli("vocab quantize --vocab " + v.string() + " --images " + images.string() +
              " --features dense --center-crop 0.9 --no-progress --corpus " + corpus.string() +
              " --json " + qj.string());
  ASSERT_EQ(r.code, 0) << r.err;
  expect_schema_valid("vocab_quantize.schema.json", qj);
  EXPECT_EQ(core::read_json(qj)["features"]["center_crop"].get<double>(), 0.9);
  const auto c = topics::read_corpus(corpus, topics::CorpusFormat::kUci);
  EXPECT_EQ(c.num_documents(), 5U);
  EXPECT_EQ(c.num_words(), 20);
  EXPECT_EQ(c.num_tokens(), core::read_json(qj)["tokens"].get<long>());
  std::ifstream labels(corpus / "labels.csv");
  std::string all((std::istreambuf_iterator<char>(labels)), std::istreambuf_iterator<char>());
  EXPECT_EQ(line_count(all), 6);
  EXPECT_NE(all.find("\n4,1,"), std::string::npos) << all;  // 4th image: the first "scene"
}

TEST_F(VocabCli, BadInput) {
  const fs::path images = dir_ / "images";
  const fs::path v = dir_ / "bad.vocab";
  auto r = run_cli("vocab build --images " + images.string() +
                   " --words 1000 --per-image 10 --dense --no-progress --out " + v.string());
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(line_count(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("fewer than 1000 words"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(v));

  fs::create_directories(dir_ / "empty" / "cls");
  r = run_cli("vocab build --images " + (dir_ / "empty").string() + " --out " + v.string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("no images"), std::string::npos) << r.err;

  fs::create_directories(dir_ / "broken" / "cls");
  std::ofstream(dir_ / "broken" / "cls" / "x.png") << "not a png";
  r = run_cli("vocab build --images " + (dir_ / "broken").string() + " --no-progress --out " +
              v.string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("x.png"), std::string::npos) << r.err;

  // The feature options are recognize's (one description): same names, same bounds.
  r = run_cli("vocab build --images " + images.string() + " --min-contrast 300 --out " +
              v.string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--min-contrast: must be in [0, 255] (it is 300)"), std::string::npos)
      << r.err;
  r = run_cli("vocab quantize --vocab x --images y --corpus z --features 1");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--features: must be dense or sift (it is 1)"), std::string::npos) << r.err;
  r = run_cli("vocab build --images " + images.string() + " --center-crop nan --out " + v.string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--center-crop: must be in (0, 1]"), std::string::npos) << r.err;

  // --alpha-mask reaches the image reader: pictures without alpha are named, nothing written.
  r = run_cli("vocab build --images " + images.string() + " --alpha-mask --no-progress --out " +
              v.string());
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(line_count(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("no alpha channel"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(v));

  std::ofstream(v, std::ios::binary) << "PRVOCAB1 truncated";
  r = run_cli("vocab info --vocab " + v.string());
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(line_count(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("truncated"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace proprio
