// proprio lda ...: train, infer, perplexity, topics and export on a synthetic corpus, with
// results that match the library's, JSON that matches its schema, and bad input as one line.
#include <gtest/gtest.h>

#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <optional>

#include "../support/named_corpus.hpp"
#include "../support/schema_check.hpp"
#include "../support/temp_dir.hpp"
#include "cli_run.hpp"
#include "proprio/core/csv.hpp"
#include "proprio/core/json_io.hpp"
#include "proprio/topics/corpus_io.hpp"
#include "proprio/topics/lda_model_io.hpp"
#include "proprio/topics/perplexity.hpp"
#include "proprio/topics/synthetic.hpp"

namespace proprio {
namespace {
namespace fs = std::filesystem;
using test::line_count;
using test::run_cli;

using test::expect_schema_valid;

class LdaCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    temp_.emplace("proprio_lda_cli");
    dir_ = temp_->path();
    topics::SyntheticCorpusOptions o;
    o.num_topics = 5;
    o.num_words = 120;
    o.num_documents = 400;
    o.mean_length = 60;
    o.seed = 3;
    const topics::Corpus named = test::named_synthetic_corpus(o);
    const auto split = topics::hold_out(named, 0.1, 1);
    topics::write_corpus(split.train, dir_ / "train", topics::CorpusFormat::kUci);
    topics::write_corpus(split.heldout, dir_ / "heldout", topics::CorpusFormat::kUci);
    topics::write_corpus(split.heldout, dir_ / "heldout_mm", topics::CorpusFormat::kMatrixMarket);
    const auto r = run_cli("lda train --corpus " + (dir_ / "train").string() +
                           " -k 5 --batch 50 --passes 3 --seed 2 --heldout " +
                           (dir_ / "heldout").string() + " --evaluate-every 4 --model " +
                           (dir_ / "m.lda").string() + " --json " + (dir_ / "train.json").string());
    ASSERT_EQ(r.code, 0) << r.err;
  }
  static void TearDownTestSuite() { temp_.reset(); }

  static std::string d(const std::string& name) { return (dir_ / name).string(); }
  // NOLINTNEXTLINE(readability-identifier-naming)
  static std::optional<test::TempDir> temp_;
  // NOLINTNEXTLINE(readability-identifier-naming)
  static fs::path dir_;
};
std::optional<test::TempDir> LdaCli::temp_;
fs::path LdaCli::dir_;

TEST_F(LdaCli, TrainWritesAModelAndTimings) {
  const core::Json j = core::read_json(d("train.json"));
  EXPECT_EQ(j["format"], "proprio.lda.train");
  EXPECT_GT(j["seconds"].get<double>(), 0.0);
  EXPECT_GT(j["docs_per_s"].get<double>(), 0.0);
  EXPECT_GT(j["tokens_per_s"].get<double>(), 0.0);
  EXPECT_EQ(j["documents"].get<int>(), 360 * 3);
  const auto& trace = j["perplexity_trace"];
  ASSERT_GE(trace.size(), 3u);
  EXPECT_LT(trace.back()["perplexity"].get<double>(), trace.front()["perplexity"].get<double>());
  expect_schema_valid("lda_train.schema.json", d("train.json"));
  const topics::LdaModel m = topics::load_lda_model(d("m.lda"));
  EXPECT_EQ(m.num_topics(), 5);
  EXPECT_EQ(m.num_words(), 120);
  EXPECT_EQ(m.vocabulary[7], "word7");
  EXPECT_EQ(m.updates, 8 * 3);
}

TEST_F(LdaCli, PerplexityOfTheModelAndOfItsExportedLambdaAgree) {
  auto r = run_cli("lda perplexity --model " + d("m.lda") + " --corpus " + d("heldout") +
                   " --json " + d("p1.json"));
  ASSERT_EQ(r.code, 0) << r.err;
  const double p1 = core::read_json(d("p1.json"))["perplexity"].get<double>();
  expect_schema_valid("lda_perplexity.schema.json", d("p1.json"));
  // The held-out perplexity after training equals the trace's last point.
  const auto trace = core::read_json(d("train.json"))["perplexity_trace"];
  EXPECT_NEAR(trace.back()["perplexity"].get<double>(), p1, 1e-9 * p1);
  r = run_cli("lda export --model " + d("m.lda") + " --out " + d("lambda.csv"));
  ASSERT_EQ(r.code, 0) << r.err;
  const topics::LdaModel m = topics::load_lda_model(d("m.lda"));
  r = run_cli("lda perplexity --lambda " + d("lambda.csv") + " --alpha " + std::to_string(m.alpha) +
              " --corpus " + d("heldout_mm") + " --format mm --json " + d("p2.json"));
  ASSERT_EQ(r.code, 0) << r.err;
  const double p2 = core::read_json(d("p2.json"))["perplexity"].get<double>();
  EXPECT_NEAR(p1, p2, 1e-6 * p1);
  r = run_cli("lda perplexity --model " + d("m.lda") + " --corpus " + d("heldout") +
              " --method bound --json " + d("p3.json"));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(core::read_json(d("p3.json"))["method"], "variational_bound");
}

TEST_F(LdaCli, ExportWritesKRowsOfW) {
  ASSERT_EQ(
      run_cli("lda export --model " + d("m.lda") + " --out " + d("beta.csv") + " --normalize").code,
      0);
  const core::CsvTable t = core::read_csv(d("beta.csv"));
  ASSERT_EQ(t.rows.size(), 5u);
  ASSERT_EQ(t.header.size(), 120u);
  EXPECT_EQ(t.header[3], "word3");
  for (std::size_t k = 0; k < 5; ++k) {
    double s = 0;
    for (std::size_t w = 0; w < 120; ++w) s += t.at(k, w);
    EXPECT_NEAR(s, 1.0, 1e-12);
  }
}

TEST_F(LdaCli, InferWritesThetaAndClasses) {
  const auto r = run_cli("lda infer --model " + d("m.lda") + " --corpus " + d("heldout") +
                         " --out " + d("theta.csv") + " --json " + d("infer.json"));
  ASSERT_EQ(r.code, 0) << r.err;
  expect_schema_valid("lda_infer.schema.json", d("infer.json"));
  const core::CsvTable t = core::read_csv(d("theta.csv"));
  ASSERT_EQ(t.rows.size(), 40u);
  ASSERT_EQ(t.header.size(), 7u);
  for (std::size_t i = 0; i < t.rows.size(); ++i) {
    double s = 0;
    std::size_t best = 0;
    for (std::size_t k = 0; k < 5; ++k) {
      s += t.at(i, 2 + k);
      if (t.at(i, 2 + k) > t.at(i, 2 + best)) best = k;
    }
    EXPECT_NEAR(s, 1.0, 1e-9);
    EXPECT_EQ(t.at(i, 1), static_cast<double>(best));
  }
}

TEST_F(LdaCli, TopicsPrintsTheTopWords) {
  const auto r = run_cli("lda topics --model " + d("m.lda") + " --top 4 --json " + d("t.json"));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(line_count(r.out), 5);
  EXPECT_EQ(r.out.rfind("topic 0: word", 0), 0u) << r.out;
  expect_schema_valid("lda_topics.schema.json", d("t.json"));
}

TEST_F(LdaCli, BatchTrainingWorksToo) {
  const auto r = run_cli("lda train --method batch --corpus " + d("train") +
                         " -k 5 --max-iterations 20 --heldout " + d("heldout") + " --model " +
                         d("b.lda") + " --json " + d("b.json"));
  ASSERT_EQ(r.code, 0) << r.err;
  expect_schema_valid("lda_train.schema.json", d("b.json"));
  const core::Json j = core::read_json(d("b.json"));
  EXPECT_EQ(j["method"], "batch");
  EXPECT_GT(j["heldout_perplexity"].get<double>(), 1.0);
}

TEST_F(LdaCli, HelpEverywhere) {
  for (const char* sub : {"", " train", " infer", " perplexity", " topics", " export"}) {
    const auto r = run_cli(std::string("lda") + sub + " --help");
    EXPECT_EQ(r.code, 0) << sub;
    EXPECT_NE(r.out.find("Usage"), std::string::npos) << sub;
  }
}

TEST_F(LdaCli, BadInputIsOneLineNamingTheFileAndExitTwo) {
  const fs::path bad = dir_ / "bad";
  fs::create_directories(bad);
  std::ofstream(bad / "docword.txt") << "2\n3\n2\n1 1 1\n1 9 1\n";
  std::ofstream(bad / "vocab.txt") << "a\nb\nc\n";
  std::ofstream(dir_ / "garbage.lda") << "not a model at all, clearly";
  const std::string m = d("m.lda");
  const std::vector<std::pair<std::string, std::string>> cases{
      {"lda train --corpus " + bad.string() + " --model " + d("x.lda"), "docword.txt:5:"},
      {"lda train --corpus " + d("train") + " -k 0 --model " + d("x.lda"), "topics"},
      {"lda train --corpus " + d("train") + " --kappa 0.3 --model " + d("x.lda"), "kappa"},
      {"lda train --corpus " + d("nowhere") + " --model " + d("x.lda"), "nowhere"},
      {"lda perplexity --model " + d("garbage.lda") + " --corpus " + d("heldout"), "garbage.lda"},
      {"lda perplexity --model " + m + " --corpus " + bad.string(), "docword.txt:5:"},
      {"lda perplexity --corpus " + d("heldout"), "exactly one of --model and --lambda"},
      {"lda perplexity --lambda " + d("train.json") + " --alpha 0.1 --corpus " + d("heldout"),
       "train.json"},
      {"lda infer --model " + m + " --corpus " + d("heldout") + " --format ldac --out " +
           d("x.csv"),
       "heldout"},
      {"lda topics --model " + d("missing.lda"), "missing.lda"},
      {"lda train --corpus " + d("train") + " --format xml --model " + d("x.lda"), "format"},
  };
  for (const auto& [args, expect] : cases) {
    const auto r = run_cli(args);
    EXPECT_EQ(r.code, 2) << args << "\n" << r.err;
    EXPECT_EQ(line_count(r.err), 1) << args << "\n" << r.err;
    EXPECT_NE(r.err.find(expect), std::string::npos) << args << "\n" << r.err;
  }
  EXPECT_FALSE(fs::exists(d("x.lda")));
}

// Issue 16: outputs equal to inputs, absurd priors written as NaN with exit 0, a FIFO given as a
// model (a hang), a corpus naming word 9,999,999 (an 800 MB model).
TEST_F(LdaCli, HostileArgumentsAreRefusedWithExitTwo) {
  const fs::path fifo = dir_ / "pipe.lda";
  fs::remove(fifo);
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::ofstream(dir_ / "huge_id.ldac") << "1 9999999:1\n";
  // A model whose alpha makes the E-step overflow (written past save's checks).
  topics::LdaModel nan_model = topics::load_lda_model(d("m.lda"));
  nan_model.alpha = 1e300;
  std::ofstream(dir_ / "nan.lda", std::ios::binary) << topics::serialize_lda_model(nan_model);
  const std::string train = "lda train --corpus " + d("train") + " -k 3 ";
  const std::vector<std::pair<std::string, std::string>> cases{
      {train + "--model " + d("same.lda") + " --json " + d("same.lda"),
       "--json is the same file as"},
      {train + "--model " + d("train/docword.txt"), "--model is the same file as"},
      {train + "--alpha 1e300 --model " + d("x.lda"), "alpha"},
      {train + "--eta 1e300 --model " + d("x.lda"), "eta"},
      {train + "--mpi-exchange four --model " + d("x.lda"), "(it is four)"},
      {"lda infer --model " + d("m.lda") + " --corpus " + d("heldout") + " --out " + d("m.lda"),
       "--out is the same file as"},
      {"lda infer --model " + d("nan.lda") + " --corpus " + d("heldout") + " --out " + d("x.csv"),
       "nan.lda: LDA model: alpha = "},
      {"lda infer --model " + fifo.string() + " --corpus " + d("heldout") + " --out " + d("x.csv"),
       "pipe.lda: is not a regular file"},
      {"lda topics --model /dev/zero", "/dev/zero: is not a regular file"},
      {"lda train --format ldac --corpus " + d("huge_id.ldac") + " -k 2 --model " + d("x.lda"),
       "huge_id.ldac:1: word id 9999999 outside [0, 1000000)"},
  };
  for (const auto& [args, expect] : cases) {
    const auto r = run_cli(args);
    EXPECT_EQ(r.code, 2) << args << "\n" << r.err;
    EXPECT_EQ(line_count(r.err), 1) << args << "\n" << r.err;
    EXPECT_NE(r.err.find(expect), std::string::npos) << args << "\n" << r.err;
  }
  EXPECT_FALSE(fs::exists(d("x.lda")));
  EXPECT_FALSE(fs::exists(d("x.csv")));
  EXPECT_FALSE(fs::exists(d("same.lda")));
  EXPECT_NO_THROW((void)topics::load_lda_model(d("m.lda"))) << "an input was overwritten";
  EXPECT_NO_THROW((void)topics::read_corpus(d("train"), topics::CorpusFormat::kUci));
  fs::remove(fifo);
}

}  // namespace
}  // namespace proprio
