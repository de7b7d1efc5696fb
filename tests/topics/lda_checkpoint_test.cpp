// Checkpoints of online LDA (issue 16): a run stopped after any checkpoint and resumed gives the
// uninterrupted run's model bit for bit; a checkpoint of another corpus or other options, or a
// damaged one, is refused naming the file.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <functional>
#include <string>

#include "../support/temp_dir.hpp"
#include "proprio/core/checkpoint.hpp"
#include "proprio/core/error.hpp"
#include "proprio/core/files.hpp"
#include "proprio/topics/lda_model_io.hpp"
#include "proprio/topics/online_lda.hpp"
#include "proprio/topics/synthetic.hpp"

namespace proprio::topics {
namespace {
namespace fs = std::filesystem;

Corpus small_corpus(std::uint64_t seed) {
  SyntheticCorpusOptions o;
  o.num_topics = 4;
  o.num_words = 60;
  o.num_documents = 90;
  o.mean_length = 30;
  o.seed = seed;
  return make_synthetic_corpus(o).corpus;
}

OnlineLdaOptions small_options() {
  OnlineLdaOptions o;
  o.num_topics = 4;
  o.batch_size = 16;
  o.passes = 3;
  o.seed = 5;
  o.evaluate_every = 2;
  return o;
}

std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(LdaCheckpoint, ResumingFromEveryCheckpointGivesTheUninterruptedModel) {
  const test::TempDir dir("proprio_lda_ckpt_");
  const Corpus corpus = small_corpus(2);
  const Corpus heldout = small_corpus(9);
  const OnlineLdaOptions o = small_options();
  const OnlineLdaResult whole = train_online_lda(corpus, heldout, o);
  const std::string whole_bytes = serialize_lda_model(whole.model);
  // 6 mini-batches a pass, 3 passes: 18 updates. Checkpoints every 5 (the last at 15), each kept.
  core::CheckpointOptions c;
  c.checkpoint = dir.path() / "run.ckpt";
  c.every = 5;
  const OnlineLdaResult saved = train_online_lda(corpus, &heldout, o, c);
  EXPECT_EQ(serialize_lda_model(saved.model), whole_bytes);
  // The last checkpoint of a run with every = N is the one after update 18 - 18 mod N: 18 (the
  // end), 16, 14, 12 (a pass's end) and 17 (its last batch, mid-pass).
  for (const int every : {1, 4, 7, 12, 17}) {
    core::CheckpointOptions each;
    each.checkpoint = dir.path() / ("every" + std::to_string(every) + ".ckpt");
    each.every = every;
    (void)train_online_lda(corpus, &heldout, o, each);
    core::CheckpointOptions resume;
    resume.resume = each.checkpoint;
    OnlineLdaOptions more_threads = o;
    more_threads.threads = 2;  // the model does not depend on it, nor does the checkpoint
    const OnlineLdaResult resumed = train_online_lda(corpus, &heldout, more_threads, resume);
    EXPECT_EQ(serialize_lda_model(resumed.model), whole_bytes) << "every " << every;
    EXPECT_EQ(resumed.summary.updates, whole.summary.updates);
    EXPECT_EQ(resumed.summary.documents, whole.summary.documents);
    ASSERT_EQ(resumed.summary.trace.size(), whole.summary.trace.size());
    for (std::size_t i = 0; i < whole.summary.trace.size(); ++i) {
      EXPECT_EQ(resumed.summary.trace[i].perplexity, whole.summary.trace[i].perplexity);
    }
    EXPECT_EQ(resumed.summary.mean_estep_iterations, whole.summary.mean_estep_iterations);
  }
}

TEST(LdaCheckpoint, ACheckpointOfAnotherCorpusOrOtherOptionsIsRefused) {
  const test::TempDir dir("proprio_lda_ckpt_");
  const Corpus corpus = small_corpus(2);
  const OnlineLdaOptions o = small_options();
  core::CheckpointOptions c;
  c.checkpoint = dir.path() / "run.ckpt";
  (void)train_online_lda(corpus, nullptr, o, c);
  core::CheckpointOptions resume;
  resume.resume = c.checkpoint;

  const std::string other_corpus =
      message_of([&] { (void)train_online_lda(small_corpus(3), nullptr, o, resume); });
  EXPECT_NE(other_corpus.find(c.checkpoint.string()), std::string::npos) << other_corpus;
  EXPECT_NE(other_corpus.find("another corpus"), std::string::npos) << other_corpus;

  OnlineLdaOptions other = o;
  other.kappa = 0.8;
  const std::string other_kappa =
      message_of([&] { (void)train_online_lda(corpus, nullptr, other, resume); });
  EXPECT_NE(other_kappa.find("kappa"), std::string::npos) << other_kappa;
  other = o;
  other.seed = 6;
  EXPECT_NE(
      message_of([&] { (void)train_online_lda(corpus, nullptr, other, resume); }).find("seed"),
      std::string::npos);
  const Corpus heldout = small_corpus(9);
  EXPECT_NE(
      message_of([&] { (void)train_online_lda(corpus, &heldout, o, resume); }).find("heldout"),
      std::string::npos);
  // A k-means checkpoint is not an LDA one.
  core::Checkpoint k;
  k.kind = "kmeans";
  core::save_checkpoint(k, dir.path() / "k.ckpt");
  resume.resume = dir.path() / "k.ckpt";
  EXPECT_NE(message_of([&] {
              (void)train_online_lda(corpus, nullptr, o, resume);
            }).find("a checkpoint of kmeans, not of online_lda"),
            std::string::npos);
}

TEST(LdaCheckpoint, DamagedCheckpointsAreRefusedNamingTheFile) {
  const test::TempDir dir("proprio_lda_ckpt_");
  const Corpus corpus = small_corpus(2);
  const OnlineLdaOptions o = small_options();
  core::CheckpointOptions c;
  c.checkpoint = dir.path() / "run.ckpt";
  (void)train_online_lda(corpus, nullptr, o, c);
  const std::string good = core::read_file(c.checkpoint);
  const fs::path bad = dir.path() / "bad.ckpt";
  core::CheckpointOptions resume;
  resume.resume = bad;
  auto refused = [&](const std::string& bytes, const std::string& expect) {
    core::write_file_atomic(bad, bytes);
    const std::string m = message_of([&] { (void)train_online_lda(corpus, nullptr, o, resume); });
    EXPECT_NE(m.find(bad.string()), std::string::npos) << m;
    EXPECT_NE(m.find(expect), std::string::npos) << m;
  };
  refused(good.substr(0, good.size() - 1), "truncated");
  refused("PRLDAMDL" + good.substr(8), "wrong magic number");
  std::string flipped = good;
  flipped[good.size() / 2] = static_cast<char>(flipped[good.size() / 2] ^ 1);
  refused(flipped, "checksum mismatch");
  // A state whose trace claims 2^60 points: refused before anything is allocated.
  core::Checkpoint k = core::load_checkpoint(c.checkpoint);
  std::string state = k.state;
  const std::uint64_t huge = std::uint64_t{1} << 60;
  std::memcpy(state.data() + 4 + 8 + 8 + 8 + 4 + 8 + 8 + 8 + 8 + 8 + 8, &huge, sizeof huge);
  k.state = state;
  refused(core::serialize_checkpoint(k), "runs past the end");
  // A count of options beyond the file.
  k = core::load_checkpoint(c.checkpoint);
  std::string raw = core::serialize_checkpoint(k);
  const std::size_t at = core::kBinaryHeaderBytes + 4 + k.kind.size() + 8;
  const std::uint32_t many = 4000;
  std::memcpy(raw.data() + at, &many, sizeof many);
  const std::string payload = raw.substr(core::kBinaryHeaderBytes);
  refused(core::frame_binary(core::kCheckpointFormat, payload), "options");
}

}  // namespace
}  // namespace proprio::topics
