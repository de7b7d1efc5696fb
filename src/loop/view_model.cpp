// A vocabulary and an LDA model from training views' own descriptors (loop/view_model.hpp).
#include "proprio/loop/view_model.hpp"

#include <algorithm>
#include <numeric>
#include <vector>

#include "proprio/core/error.hpp"
#include "proprio/core/random.hpp"
#include "proprio/features/kmeans.hpp"
#include "proprio/topics/batch_lda.hpp"

namespace proprio::loop {

namespace {
// core::stream_seed key of the vocabulary's sample (the clutter experiment's since session 21).
constexpr std::uint64_t kVocabularyStream = 0x7c1c;
}  // namespace

features::Vocabulary views_vocabulary(std::span<const cv::Mat> views, int words, std::uint64_t seed,
                                      int sample, int threads) {
  if (words < 1) throw Error("views_vocabulary: words must be >= 1");
  if (sample < 0) throw Error("views_vocabulary: sample must be >= 0 (0 = every descriptor)");
  if (threads < 0) throw Error("views_vocabulary: threads must be >= 0 (0 = all cores)");
  std::vector<cv::Mat> nonempty;
  for (const cv::Mat& v : views) {
    if (v.rows > 0) nonempty.push_back(v);
  }
  if (nonempty.empty()) throw Error("views_vocabulary: the views hold no descriptor");
  cv::Mat stacked;
  cv::vconcat(nonempty, stacked);
  if (sample > 0 && stacked.rows > sample) {
    // k-means over a seeded sample of the descriptors (all of them cost minutes a run).
    std::vector<int> rows(static_cast<std::size_t>(stacked.rows));
    std::iota(rows.begin(), rows.end(), 0);
    core::Rng rng(core::stream_seed(seed, kVocabularyStream));
    for (std::size_t i = 0; i < static_cast<std::size_t>(sample); ++i) {
      const auto j =
          i + static_cast<std::size_t>(rng.uniform() * static_cast<double>(rows.size() - i));
      std::swap(rows[i], rows[std::min(j, rows.size() - 1)]);
    }
    cv::Mat drawn(sample, stacked.cols, CV_32F);
    for (int i = 0; i < sample; ++i)
      stacked.row(rows[static_cast<std::size_t>(i)]).copyTo(drawn.row(i));
    stacked = drawn;
  }
  features::KmeansOptions ko;
  ko.words = std::min(words, stacked.rows);
  ko.seed = seed;
  ko.threads = threads;
  return features::build_vocabulary(stacked, ko).vocabulary;
}

topics::LdaModel views_lda(const topics::Corpus& corpus, int topics, std::uint64_t seed) {
  topics::BatchLdaOptions bo;
  bo.num_topics = topics;
  bo.seed = seed;
  bo.max_iterations = kViewLdaIterations;
  return topics::train_batch_lda(corpus, bo).model;
}

}  // namespace proprio::loop
