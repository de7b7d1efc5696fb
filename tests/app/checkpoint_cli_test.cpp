// Resumable learning through the CLI (issue 16): `proprio lda train` and `proprio vocab build`
// run as child processes, are killed with SIGKILL at a random moment after a checkpoint was
// written, are resumed from it, and end with the model of the uninterrupted run, bit for bit.
// Checkpoints of another corpus or other options are refused with exit 2 naming the file.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "../support/named_corpus.hpp"
#include "../support/temp_dir.hpp"
#include "cli_run.hpp"
#include "proprio/core/files.hpp"
#include "proprio/features/vocabulary.hpp"
#include "proprio/topics/corpus_io.hpp"
#include "proprio/topics/synthetic.hpp"

namespace proprio {
namespace {
namespace fs = std::filesystem;
using test::line_count;
using test::run_cli;

struct Killed {
  bool by_signal = false;  // false: the child had finished before the kill
  int delay_ms = 0;
};

// Starts `proprio args`, waits until `checkpoint` exists, waits a random 0..max_delay_ms more,
// then kills the child with SIGKILL and reaps it.
Killed run_and_kill(const std::string& args, const fs::path& checkpoint, int max_delay_ms) {
  std::random_device seed;
  Killed k;
  k.delay_ms = static_cast<int>(seed() % static_cast<unsigned>(max_delay_ms + 1));
  k.by_signal = test::run_cli_and_kill(
      args, [&] { return fs::exists(checkpoint); }, std::chrono::milliseconds(k.delay_ms),
      std::chrono::seconds(120));
  return k;
}

// True when `dir` holds only `allowed`: a killed writer's temporary checkpoint was removed by the
// resumed run's next write beside it (core::write_file_atomic).
bool only_files(const fs::path& dir, const std::vector<std::string>& allowed) {
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    bool ok = false;
    for (const auto& a : allowed) ok = ok || name == a;
    if (!ok) {
      ADD_FAILURE() << "left in " << dir << ": " << name;
      return false;
    }
  }
  return true;
}

TEST(CheckpointCli, LdaTrainKilledAndResumedGivesTheUninterruptedModel) {
  const test::TempDir dir("proprio_ckpt_cli_");
  topics::SyntheticCorpusOptions so;
  so.num_topics = 10;
  so.num_words = 400;
  so.num_documents = 1500;
  so.mean_length = 80;
  so.seed = 7;
  const fs::path corpus = dir.path() / "corpus";
  topics::write_corpus(test::named_synthetic_corpus(so), corpus, topics::CorpusFormat::kUci);
  const auto args = [&](int batch) {
    return "lda train --corpus " + corpus.string() + " --topics 10 --batch " +
           std::to_string(batch) +
           " --passes 12 --seed 11 --estep-max-iterations 200 --estep-tolerance 0.00001";
  };
  const std::string common = args(8);
  const fs::path whole = dir.path() / "whole.lda";
  auto r = run_cli(common + " --model " + whole.string());
  ASSERT_EQ(r.code, 0) << r.err;

  const fs::path ckpt = dir.path() / "run.ckpt";
  const fs::path model = dir.path() / "resumed.lda";
  Killed k;
  for (const int delay : {300, 30, 0}) {
    fs::remove(ckpt);
    k = run_and_kill(common + " --model " + model.string() + " --checkpoint " + ckpt.string() +
                         " --checkpoint-every 3",
                     ckpt, delay);
    if (k.by_signal) break;
  }
  ASSERT_TRUE(k.by_signal) << "the child finished before it could be killed";
  EXPECT_FALSE(fs::exists(model)) << "a killed run wrote its model";
  ASSERT_TRUE(fs::exists(ckpt));
  r = run_cli(common + " --model " + model.string() + " --checkpoint " + ckpt.string() +
              " --checkpoint-every 3 --resume " + ckpt.string() + " --threads 2");
  ASSERT_EQ(r.code, 0) << r.err << " (killed " << k.delay_ms << " ms after the first checkpoint)";
  EXPECT_TRUE(core::read_file(model) == core::read_file(whole))
      << "killed " << k.delay_ms << " ms after the first checkpoint";
  EXPECT_TRUE(only_files(dir.path(), {"corpus", "whole.lda", "run.ckpt", "resumed.lda"}));

  // Another corpus, other options: exit 2, one line naming the checkpoint.
  so.seed = 8;
  const fs::path other = dir.path() / "other";
  topics::write_corpus(test::named_synthetic_corpus(so), other, topics::CorpusFormat::kUci);
  std::string other_args = common;
  other_args.replace(other_args.find(corpus.string()), corpus.string().size(), other.string());
  r = run_cli(other_args + " --model " + (dir.path() / "o.lda").string() + " --resume " +
              ckpt.string());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_EQ(line_count(r.err), 1) << r.err;
  EXPECT_NE(r.err.find(ckpt.string()), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("another corpus"), std::string::npos) << r.err;
  r = run_cli(args(9) + " --model " + (dir.path() / "o.lda").string() + " --resume " +
              ckpt.string());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("batch = 8, this run has 9"), std::string::npos) << r.err;
  // The checkpoint may not be an input, nor the model.
  r = run_cli(common + " --model " + (dir.path() / "o.lda").string() + " --checkpoint " +
              (corpus / "docword.txt").string());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("--checkpoint"), std::string::npos) << r.err;
  r = run_cli(common + " --model " + ckpt.string() + " --resume " + ckpt.string());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("--model"), std::string::npos) << r.err;
  r = run_cli(common + " --method batch --model " + (dir.path() / "o.lda").string() +
              " --checkpoint " + (dir.path() / "b.ckpt").string());
  EXPECT_EQ(r.code, 2) << r.err;
}

TEST(CheckpointCli, VocabBuildKilledAndResumedGivesTheUninterruptedWords) {
  const test::TempDir dir("proprio_ckpt_cli_");
  const fs::path samples = PROPRIO_OPENCV_SAMPLES;
  for (const auto& [cls, file] : std::vector<std::pair<std::string, std::string>>{
           {"fruit", "apple.jpg"}, {"fruit", "orange.jpg"}, {"scene", "graf1.png"}}) {
    fs::create_directories(dir.path() / "images" / cls);
    fs::copy_file(samples / file, dir.path() / "images" / cls / file);
  }
  const auto args = [&](int words) {
    return "vocab build --images " + (dir.path() / "images").string() +
           " --dense --per-image 3000 --words " + std::to_string(words) +
           " --tolerance 0 --max-iterations 400 --seed 5 --threads 1 --no-progress";
  };
  const std::string common = args(300);
  const fs::path whole = dir.path() / "whole.vocab";
  auto r = run_cli(common + " --out " + whole.string());
  ASSERT_EQ(r.code, 0) << r.err;
  const fs::path ckpt = dir.path() / "k.ckpt";
  const fs::path out = dir.path() / "resumed.vocab";
  Killed k;
  for (const int delay : {100, 10, 0}) {
    fs::remove(ckpt);
    k = run_and_kill(common + " --out " + out.string() + " --checkpoint " + ckpt.string() +
                         " --checkpoint-every 2",
                     ckpt, delay);
    if (k.by_signal) break;
  }
  ASSERT_TRUE(k.by_signal) << "the child finished before it could be killed";
  EXPECT_FALSE(fs::exists(out));
  r = run_cli(common + " --out " + out.string() + " --resume " + ckpt.string());
  ASSERT_EQ(r.code, 0) << r.err;
  const cv::Mat a = features::read_vocabulary(whole).words();
  const cv::Mat b = features::read_vocabulary(out).words();
  ASSERT_EQ(a.size, b.size);
  EXPECT_EQ(std::memcmp(a.data, b.data, a.total() * a.elemSize()), 0)
      << "killed " << k.delay_ms << " ms after the first checkpoint";
  r = run_cli(args(299) + " --out " + (dir.path() / "o.vocab").string() + " --resume " +
              ckpt.string());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_EQ(line_count(r.err), 1) << r.err;
  EXPECT_NE(r.err.find(ckpt.string()), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("words = 300, this run has 299"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace proprio
