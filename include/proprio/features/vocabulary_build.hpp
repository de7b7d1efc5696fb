#pragma once
// `proprio vocab build` as a library call (thesis 6.1.2, 6.3.1): the local features of every image
// of a folder-per-class set, a uniform sample of each image's descriptors, k-means into words.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include "proprio/core/communicator.hpp"
#include "proprio/core/fields.hpp"
#include "proprio/core/json_io.hpp"
#include "proprio/core/provenance.hpp"
#include "proprio/features/extraction.hpp"
#include "proprio/features/extraction_record.hpp"
#include "proprio/features/kmeans.hpp"
#include "proprio/features/vocabulary.hpp"

namespace proprio::features {

struct VocabularyBuildOptions {
  std::filesystem::path images;  ///< folder-per-class image set, DIR/<class>/<image> (required)
  /// The vocabulary file to write (docs/formats/vocabulary.md); empty: not written.
  std::filesystem::path out;
  /// Interest-point SIFT unless told otherwise (6.3.1 built its dictionaries so); the other
  /// options as in every command that extracts features.
  ExtractOptions features = sift_extraction();
  int per_image = 100;  ///< descriptors sampled per image, uniformly without replacement; 0 = all
  KmeansOptions kmeans;
  /// k-means checkpoints every N iterations and resume (issue 16; build_vocabulary). On resume
  /// the features are extracted and sampled again (the same, for the same options), then Lloyd's
  /// iterations continue from the checkpoint's centres. One process only (not under mpirun).
  core::CheckpointOptions checkpointing;
  bool progress = false;  ///< a progress bar on stderr

  /// Throws Error naming the first bad option.
  void validate() const;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.per_image, {"per_image", "Descriptors sampled per image (0 = all)", core::at_least(0)});
  }

  static ExtractOptions sift_extraction() {
    ExtractOptions o;
    o.kind = FeatureKind::kSift;
    return o;
  }
};

// NOLINTNEXTLINE(bugprone-exception-escape)
struct VocabularyBuildResult {
  Vocabulary vocabulary;
  KmeansSummary kmeans;
  std::size_t classes = 0;
  std::size_t images = 0;
  int images_without_features = 0;
  int descriptors = 0;             ///< descriptors clustered
  double extract_seconds = 0.0;    ///< reading images and computing descriptors, wall clock
  VocabularyBuildOptions options;  ///< as given
  std::optional<int> ranks;        ///< MPI ranks, when more than one
  /// The record (format "proprio.vocab.build", docs/formats/schemas/vocab_build.schema.json):
  /// the fields described below.
  core::Json document;

  std::string message;  ///< one line: what happened (brief()'s first line)
  /// One line for a person (what the CLI prints).
  [[nodiscard]] std::string brief() const;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    const VocabularyBuildOptions& o = self.options;
    v(o.images, {"images_dir", "The image set"});
    v(o.out, {"vocabulary", "The vocabulary written"});
    v(self.classes, {"classes", "Classes of the image set"});
    v(self.images, {"images", "Images read"});
    v(self.images_without_features, {"images_without_features", "Images without features"});
    v(ExtractionRecord{o.features}, {"features", "The extraction options"});
    v(o.per_image, {"per_image", "Descriptors sampled per image (0 = all)"});
    v(self.vocabulary.size(), {"words", "Words of the vocabulary"});
    v(self.descriptors, {"descriptors", "Descriptors clustered"});
    v(self.extract_seconds, {"extract_seconds", "Reading and extraction, wall clock"});
    v(self.kmeans.seconds, {"kmeans_seconds", "k-means, wall clock"});
    v(self.kmeans.iterations, {"iterations", "Lloyd iterations"});
    v(self.kmeans.termination, {"termination", "converged or max_iterations"});
    v(self.kmeans.cost, {"cost", "Sum of squared distances to the words"});
    v(self.kmeans.empty_clusters_reseeded, {"empty_clusters_reseeded", "Empty clusters reseeded"});
    v(o.kmeans.tolerance, {"tolerance", "k-means tolerance"});
    v(o.kmeans.seed, {"seed", "k-means seed"});
    v(o.kmeans.threads, {"threads", "k-means threads"});
    v(self.ranks, {"ranks", "MPI ranks (with more than one)"});
  }
};

/// Reads the image set, extracts and samples descriptors (the sample draws from one stream seeded
/// by kmeans.seed, image after image), builds the vocabulary and writes it to `out` (when given)
/// with `provenance`. Throws Error naming the image set when it yields no features or fewer
/// descriptors than words, or naming an image that cannot be read.
VocabularyBuildResult run_vocabulary_build(const VocabularyBuildOptions& options,
                                           const core::Provenance& provenance);

/// The same as one rank of a data-parallel job (issue 23), collective over `comm` (with one rank,
/// the call above): rank r extracts the features of images i with i mod ranks = r; the sample of
/// each image is the one-process sample (the ranks share every image's descriptor count and replay
/// the one random stream); the sampled rows go to the ranks that hold their chunks of k-means
/// (kmeans_rows_of_rank) and k-means runs over the ranks. Every rank ends with the one-process
/// vocabulary, bit for bit; rank 0 alone writes it, after the last collective step. Bad input on
/// any rank: core::CollectiveError on every rank. The record adds "ranks" (with more than one).
VocabularyBuildResult run_vocabulary_build(const VocabularyBuildOptions& options,
                                           const core::Provenance& provenance,
                                           core::Communicator& comm);

}  // namespace proprio::features
