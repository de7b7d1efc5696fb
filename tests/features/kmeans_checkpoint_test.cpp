// Checkpoints of k-means (issue 16): resumed from any checkpoint, Lloyd's iterations end with the
// uninterrupted run's words, bit for bit; other descriptors, other options or a damaged file are
// refused naming it.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <functional>
#include <opencv2/core.hpp>
#include <string>

#include "../support/temp_dir.hpp"
#include "proprio/core/checkpoint.hpp"
#include "proprio/core/error.hpp"
#include "proprio/core/files.hpp"
#include "proprio/features/kmeans.hpp"

namespace proprio::features {
namespace {

cv::Mat blobs(int n, int dim, std::uint64_t seed) {
  cv::RNG rng(seed);
  cv::Mat x(n, dim, CV_32F);
  rng.fill(x, cv::RNG::NORMAL, 0, 1);
  for (int i = 0; i < n; ++i) x.row(i) += static_cast<float>(i % 7) * 3.0F;
  return x;
}

bool same_words(const Vocabulary& a, const Vocabulary& b) {
  const cv::Mat& x = a.words();
  const cv::Mat& y = b.words();
  return x.size == y.size && std::memcmp(x.data, y.data, x.total() * x.elemSize()) == 0;
}

std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

KmeansOptions options() {
  KmeansOptions o;
  o.words = 12;
  o.max_iterations = 30;
  o.tolerance = 0;
  o.seed = 4;
  o.threads = 1;
  return o;
}

TEST(KmeansCheckpoint, ResumingFromACheckpointGivesTheUninterruptedWords) {
  const test::TempDir dir("proprio_kmeans_ckpt_");
  const cv::Mat x = blobs(600, 8, 1);
  const KmeansOptions o = options();
  const VocabularyResult whole = build_vocabulary(x, o);
  ASSERT_GE(whole.summary.iterations, 3);
  for (const int every : {1, 2, whole.summary.iterations - 1}) {
    core::CheckpointOptions c;
    c.checkpoint = dir.path() / ("every" + std::to_string(every) + ".ckpt");
    c.every = every;
    const VocabularyResult saved = build_vocabulary(x, o, c);
    EXPECT_TRUE(same_words(saved.vocabulary, whole.vocabulary));
    core::CheckpointOptions resume;
    resume.resume = c.checkpoint;
    KmeansOptions two = o;
    two.threads = 2;  // the words do not depend on it
    const VocabularyResult resumed = build_vocabulary(x, two, resume);
    EXPECT_TRUE(same_words(resumed.vocabulary, whole.vocabulary)) << "every " << every;
    EXPECT_EQ(resumed.summary.iterations, whole.summary.iterations);
    EXPECT_EQ(resumed.summary.cost, whole.summary.cost);
    EXPECT_EQ(resumed.summary.termination, whole.summary.termination);
  }
}

TEST(KmeansCheckpoint, OtherDescriptorsOtherOptionsAndDamageAreRefused) {
  const test::TempDir dir("proprio_kmeans_ckpt_");
  const cv::Mat x = blobs(300, 8, 1);
  const KmeansOptions o = options();
  core::CheckpointOptions c;
  c.checkpoint = dir.path() / "k.ckpt";
  (void)build_vocabulary(x, o, c);
  core::CheckpointOptions resume;
  resume.resume = c.checkpoint;
  const std::string other =
      message_of([&] { (void)build_vocabulary(blobs(300, 8, 2), o, resume); });
  EXPECT_NE(other.find(c.checkpoint.string()), std::string::npos) << other;
  EXPECT_NE(other.find("another descriptor set"), std::string::npos) << other;
  KmeansOptions more = o;
  more.words = 13;
  EXPECT_NE(message_of([&] { (void)build_vocabulary(x, more, resume); }).find("words = 12"),
            std::string::npos);
  // A state whose centres are cut short, and one with NaN centres.
  core::Checkpoint k = core::load_checkpoint(c.checkpoint);
  const std::string good_state = k.state;
  k.state = good_state.substr(0, good_state.size() - 4);
  const std::filesystem::path bad = dir.path() / "bad.ckpt";
  core::save_checkpoint(k, bad);
  resume.resume = bad;
  const std::string cut = message_of([&] { (void)build_vocabulary(x, o, resume); });
  EXPECT_NE(cut.find(bad.string()), std::string::npos) << cut;
  EXPECT_NE(cut.find("runs past the end"), std::string::npos) << cut;
  k.state = good_state;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(k.state.data() + k.state.size() - 4, &nan, sizeof nan);
  core::save_checkpoint(k, bad);
  EXPECT_NE(message_of([&] { (void)build_vocabulary(x, o, resume); }).find("not finite"),
            std::string::npos);
}

}  // namespace
}  // namespace proprio::features
