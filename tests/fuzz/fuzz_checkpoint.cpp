// Fuzz target: checkpoints of resumable learning (core/checkpoint.hpp; online LDA's and k-means'
// states). The first byte picks what the rest is:
//   even            a whole checkpoint file, through core::load_checkpoint;
//   1 mod 4         a checkpoint's payload, framed with a valid header and checksum;
//   3 mod 8         the state of an online-LDA checkpoint whose identity (corpus checksum, options)
//                   is valid for a tiny corpus: training resumes from it;
//   7 mod 8         the same for k-means over a tiny descriptor set.
// So that mutations reach the learners' state parsers instead of all stopping at a checksum.
#include <unistd.h>

#include <opencv2/core.hpp>

#include "fuzz_input.hpp"
#include "proprio/core/binary_file.hpp"
#include "proprio/core/checkpoint.hpp"
#include "proprio/features/kmeans.hpp"
#include "proprio/topics/online_lda.hpp"

namespace {
using namespace proprio;
namespace fs = std::filesystem;

const topics::Corpus& tiny_corpus() {
  static const topics::Corpus kCorpus = [] {
    topics::Corpus c(6);
    const std::int32_t w[3][3] = {{0, 1, 2}, {2, 3, 4}, {1, 4, 5}};
    const std::int32_t n[3] = {1, 2, 3};
    for (const auto& doc : w) c.add_document(doc, n);
    return c;
  }();
  return kCorpus;
}

topics::OnlineLdaOptions tiny_lda_options() {
  topics::OnlineLdaOptions o;
  o.num_topics = 2;
  o.batch_size = 1;
  o.passes = 2;
  o.estep.max_iterations = 5;
  return o;
}

const cv::Mat& tiny_descriptors() {
  static const cv::Mat kDescriptors = [] {
    cv::Mat m(24, 3, CV_32F);
    for (int i = 0; i < m.rows; ++i) {
      for (int d = 0; d < m.cols; ++d) m.at<float>(i, d) = static_cast<float>((i * 7 + d * 3) % 11);
    }
    return m;
  }();
  return kDescriptors;
}

features::KmeansOptions tiny_kmeans_options() {
  features::KmeansOptions o;
  o.words = 3;
  o.max_iterations = 4;
  o.tolerance = 0;
  o.threads = 1;
  return o;
}

fs::path scratch(const char* name) {
  return fs::temp_directory_path() / ("proprio_fuzz_ckpt_" + std::to_string(::getpid()) + name);
}

// A valid checkpoint of each learner, written once: its identity is reused with fuzzed states.
const core::Checkpoint& valid(bool lda) {
  static const core::Checkpoint kLda = [] {
    core::CheckpointOptions c;
    c.checkpoint = scratch("_lda_seed");
    (void)topics::train_online_lda(tiny_corpus(), nullptr, tiny_lda_options(), c);
    core::Checkpoint k = core::load_checkpoint(c.checkpoint);
    fs::remove(c.checkpoint);
    return k;
  }();
  static const core::Checkpoint kKmeans = [] {
    core::CheckpointOptions c;
    c.checkpoint = scratch("_kmeans_seed");
    (void)features::build_vocabulary(tiny_descriptors(), tiny_kmeans_options(), c);
    core::Checkpoint k = core::load_checkpoint(c.checkpoint);
    fs::remove(c.checkpoint);
    return k;
  }();
  return lda ? kLda : kKmeans;
}

}  // namespace

// NOLINTNEXTLINE(readability-identifier-naming): the name libFuzzer calls
extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::string_view rest = fuzz::as_text(data + 1, size - 1);
  const int mode = data[0];
  if ((mode & 1) == 0) {
    const auto path = fuzz::as_file(rest, ".ckpt");
    fuzz::expect_error_or_success([&] { (void)core::load_checkpoint(path); });
    return 0;
  }
  if ((mode & 3) == 1) {
    const std::string bytes = core::frame_binary(core::kCheckpointFormat, rest);
    fuzz::expect_error_or_success([&] { (void)core::parse_checkpoint(bytes, "fuzz.ckpt"); });
    return 0;
  }
  const bool lda = (mode & 7) == 3;
  core::Checkpoint c = valid(lda);
  c.state = std::string(rest);
  core::CheckpointOptions resume;
  resume.resume = fuzz::as_file(core::serialize_checkpoint(c), ".ckpt");
  fuzz::expect_error_or_success([&] {
    if (lda) {
      (void)topics::train_online_lda(tiny_corpus(), nullptr, tiny_lda_options(), resume);
    } else {
      (void)features::build_vocabulary(tiny_descriptors(), tiny_kmeans_options(), resume);
    }
  });
  return 0;
}
