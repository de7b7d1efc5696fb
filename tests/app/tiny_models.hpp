#pragma once
// Small real inputs for the commands that take a vocabulary and an LDA model (selfsupervise):
// built once per test suite from opencv-doc's fruits.jpg in well under a second.

#include <cstdint>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "proprio/core/provenance.hpp"
#include "proprio/features/kmeans.hpp"
#include "proprio/features/sift.hpp"
#include "proprio/features/vocabulary.hpp"
#include "proprio/topics/batch_lda.hpp"
#include "proprio/topics/corpus.hpp"
#include "proprio/topics/lda_model_io.hpp"

namespace proprio::test {

/// Writes dir/v.vocab, a 24-word vocabulary of fruits.jpg's dense SIFT, and dir/m.lda, a 3-topic
/// batch LDA model of documents of 50 of its words; returns the model. `tool` names the writer
/// in the vocabulary's provenance. PROPRIO_OPENCV_SAMPLES must be defined (opencv-doc's images).
inline topics::LdaModel write_tiny_vocabulary_and_model(const std::filesystem::path& dir,
                                                        const std::string& tool) {
  const cv::Mat img =
      cv::imread(std::string(PROPRIO_OPENCV_SAMPLES) + "/fruits.jpg", cv::IMREAD_COLOR);
  if (img.empty()) throw std::runtime_error("opencv-doc's fruits.jpg is missing");
  const features::Features f = features::dense_sift(img);
  features::KmeansOptions k;
  k.words = 24;
  k.threads = 1;
  const features::Vocabulary v = features::build_vocabulary(f.descriptors, k).vocabulary;
  features::write_vocabulary(dir / "v.vocab", v, core::Provenance::current({tool}, 1));
  const std::vector<std::int32_t> words = features::bag_of_words(v, f.descriptors);
  topics::Corpus corpus(v.size());
  for (std::size_t b = 0; b + 50 <= words.size(); b += 50) {
    corpus.add_tokens(std::vector<std::int32_t>(words.begin() + static_cast<long>(b),
                                                words.begin() + static_cast<long>(b + 50)));
  }
  topics::BatchLdaOptions lo;
  lo.num_topics = 3;
  lo.max_iterations = 10;
  topics::LdaModel m = topics::train_batch_lda(corpus, lo).model;
  topics::save_lda_model(m, dir / "m.lda");
  return m;
}

}  // namespace proprio::test
