#pragma once
// `proprio vocab quantize` as a library call (thesis 6.1.3): a folder-per-class image set becomes
// a bag-of-words corpus, one document per image, for `proprio lda train`.

#include <filesystem>
#include <string>

#include "proprio/core/json_io.hpp"
#include "proprio/core/provenance.hpp"
#include "proprio/features/extraction.hpp"
#include "proprio/features/extraction_record.hpp"
#include "proprio/topics/corpus.hpp"

namespace proprio::recognition {

struct QuantizeImagesOptions {
  std::filesystem::path vocabulary;  ///< vocabulary file (required)
  std::filesystem::path images;      ///< folder-per-class image set (required)
  /// Directory to write (required): docword.txt and vocab.txt (UCI, words named v0, v1, ...),
  /// labels.csv (document from 1 as in docword.txt, class index, tokens) and classes.txt.
  std::filesystem::path corpus;
  /// Interest-point SIFT unless told otherwise, as `vocab build`.
  features::ExtractOptions features = sift_extraction();
  bool progress = false;  ///< a progress bar on stderr

  /// Throws Error naming the first bad option.
  void validate() const;

  static features::ExtractOptions sift_extraction() {
    features::ExtractOptions o;
    o.kind = features::FeatureKind::kSift;
    return o;
  }
};

// NOLINTNEXTLINE(bugprone-exception-escape)
struct QuantizeImagesResult {
  topics::Corpus corpus;  ///< a document per image, in the image set's order
  std::vector<std::string> classes;
  long tokens = 0;
  int images_without_features = 0;  ///< empty documents (kept, so that rows match images)
  QuantizeImagesOptions options;    ///< as given
  /// The record (format "proprio.vocab.quantize", vocab_quantize.schema.json): the fields
  /// described below.
  core::Json document;

  std::string message;  ///< one line: what happened (brief()'s first line)
  /// One line for a person (what the CLI prints).
  [[nodiscard]] std::string brief() const;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.options.vocabulary, {"vocabulary", "The vocabulary file"});
    v(self.options.images, {"images_dir", "The image set"});
    v(self.options.corpus, {"corpus", "The corpus directory written"});
    v(self.corpus.num_documents(), {"documents", "Documents, one per image"});
    v(self.tokens, {"tokens", "Tokens"});
    v(self.corpus.num_words(), {"words", "Words of the vocabulary"});
    v(self.images_without_features, {"images_without_features", "Empty documents"});
    v(self.classes, {"classes", "The image set's classes"});
    v(features::ExtractionRecord{self.options.features}, {"features", "The extraction options"});
  }
};

/// Reads the vocabulary and the images, quantises each image's features to their nearest words
/// and writes the corpus directory. Throws Error naming the vocabulary when its words' length is
/// not the descriptors', or naming an image that cannot be read.
QuantizeImagesResult run_quantize_images(const QuantizeImagesOptions& options,
                                         const core::Provenance& provenance);

}  // namespace proprio::recognition
