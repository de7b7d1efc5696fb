#pragma once
// A visual vocabulary (thesis 6.1.2): K cluster centres ("words") in descriptor space; a
// descriptor is quantised to its nearest word (Euclidean), which makes an image a bag of words.

#include <cstdint>
#include <filesystem>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "proprio/core/fields.hpp"
#include "proprio/core/json_io.hpp"
#include "proprio/core/provenance.hpp"

namespace proprio::features {

class Vocabulary {
 public:
  /// Takes K x D CV_32F words (D = 128 for SIFT), K >= 1, all finite; throws Error otherwise.
  explicit Vocabulary(cv::Mat words);

  [[nodiscard]] int size() const { return words_.rows; }
  [[nodiscard]] int dimension() const { return words_.cols; }
  [[nodiscard]] const cv::Mat& words() const { return words_; }

  /// Index of the word nearest to one descriptor of dimension() floats (ties: lowest index).
  [[nodiscard]] int quantize(const float* descriptor) const;
  /// Nearest word of every row of an N x D CV_32F matrix. Exact: squared distances
  /// ||x||^2 - 2 x.c + ||c||^2 by a blocked matrix product fused with the arg-min (AVX2 /
  /// AVX-512 when the processor has them), split over `threads` (0 = all cores): ~244 million
  /// descriptor-word pairs/s on 2 busy cores, faster than FLANN's kd-trees and exact (see
  /// docs/results/features.md). Throws Error on a wrong shape or type, or non-finite values.
  [[nodiscard]] std::vector<int> quantize(const cv::Mat& descriptors, int threads = 0) const;
  /// quantize() with the squared distance to the chosen word of each row.
  [[nodiscard]] std::vector<int> quantize(const cv::Mat& descriptors, std::vector<float>& sq_dist,
                                          int threads = 0) const;

 private:
  cv::Mat words_;
  std::vector<float> norms_;  // ||c||^2 of every word
};

/// Word ids of every descriptor row (the tokens of one document, for topics::Corpus::add_tokens).
/// An empty descriptor matrix gives no tokens.
std::vector<std::int32_t> bag_of_words(const Vocabulary& vocabulary, const cv::Mat& descriptors);

/// The version of the vocabulary file format this build writes (and the only one it reads).
inline constexpr std::uint32_t kVocabularyFormatVersion = 1;

/// Writes the vocabulary atomically: magic, version, CRC-32, sizes, the words as float32 and
/// the provenance as JSON (docs/formats/vocabulary.md).
void write_vocabulary(const std::filesystem::path& path, const Vocabulary& vocabulary,
                      const core::Provenance& provenance);
/// Reads a vocabulary file. Throws Error naming the file when it is missing, truncated, corrupt
/// (checksum), of another version, or holds non-finite values.
Vocabulary read_vocabulary(const std::filesystem::path& path);
/// The provenance stored in a vocabulary file (same checks as read_vocabulary).
core::Provenance read_vocabulary_provenance(const std::filesystem::path& path);

/// What a vocabulary file holds (`proprio vocab info`).
// NOLINTNEXTLINE(bugprone-exception-escape)
struct VocabularyInfo {
  std::filesystem::path vocabulary;  ///< the file
  int words = 0;                     ///< K
  int dimension = 0;                 ///< D, values per word
  core::Provenance built_by;         ///< the provenance stored in the file
  /// The record (format "proprio.vocab.info"): the fields described below.
  core::Json document;

  std::string message;  ///< one line: what happened (brief()'s first line)
  /// "FILE: K words of D values, written WHEN by proprio VERSION\n  COMMAND LINE".
  [[nodiscard]] std::string brief() const;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.vocabulary, {"vocabulary", "The vocabulary file"});
    v(self.words, {"words", "Number of words"});
    v(self.dimension, {"dimension", "Values per word"});
    v(core::to_json(self.built_by), {"built_by", "The provenance stored in the file"});
  }
};

/// Reads `path` (same checks as read_vocabulary) and returns what it holds, with its record.
VocabularyInfo run_vocabulary_info(const std::filesystem::path& path,
                                   const core::Provenance& provenance);

}  // namespace proprio::features
