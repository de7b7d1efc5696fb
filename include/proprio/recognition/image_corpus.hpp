#pragma once
// Labelled bag-of-words corpora of folder-per-class image sets (thesis 6.3.1-6.3.2) and the
// evaluation of an LDA model on them: theta by the E-step, class = argmax (6.1.4), topics named
// after classes from labelled documents only (topic_mapping.hpp).
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "proprio/features/image_set.hpp"
#include "proprio/features/vocabulary.hpp"
#include "proprio/recognition/confusion.hpp"
#include "proprio/recognition/documents.hpp"
#include "proprio/recognition/topic_mapping.hpp"
#include "proprio/topics/corpus.hpp"
#include "proprio/topics/inference.hpp"
#include "proprio/topics/lda_model.hpp"

namespace proprio::recognition {

/// Documents with the class of each (-1: unknown) and the classes' names.
struct LabelledCorpus {
  topics::Corpus corpus;
  std::vector<int> labels;
  std::vector<std::string> classes;
};

/// Called after each image or frame: (done, total).
using ProgressFn = std::function<void(std::size_t, std::size_t)>;

/// The images `indices` of `set` as whole-image documents (labels: their classes). Throws Error
/// naming an image that cannot be read.
LabelledCorpus image_corpus(const features::ImageSet& set, std::span<const std::size_t> indices,
                            const features::Vocabulary& vocabulary,
                            const features::ExtractOptions& options,
                            const ProgressFn& progress = {});

/// A per-class split of an image set into training and test images.
struct SetSplit {
  std::vector<std::size_t> train;
  std::vector<std::size_t> test;
};

/// In each class, `test_per_class` images drawn at random (seeded) are the test set and the rest
/// train. Throws Error naming a class with fewer than test_per_class + 1 images.
SetSplit split_per_class(const features::ImageSet& set, int test_per_class, std::uint64_t seed);

/// The images of `indices` whose class is one of `classes` (names), in order.
std::vector<std::size_t> images_of(const features::ImageSet& set,
                                   std::span<const std::size_t> indices,
                                   const std::vector<std::string>& classes);

/// Descriptors for a dictionary (thesis 6.3.1): from `images_per_class` images of each class
/// among `indices` (drawn at random), `per_image` descriptors each, drawn at random from the
/// image's features (all of them when it has fewer). N x 128 CV_32F.
cv::Mat sample_descriptors(const features::ImageSet& set, std::span<const std::size_t> indices,
                           int images_per_class, int per_image,
                           const features::ExtractOptions& options, std::uint64_t seed,
                           const ProgressFn& progress = {});

/// How a model classifies a test set.
struct Evaluation {
  TopicMapping mapping;     ///< from the labelled mapping documents only
  ConfusionMatrix topics;   ///< classes x topics z_1..z_K (argmax theta)
  ConfusionMatrix classes;  ///< classes x classes, topics merged by the mapping (7.3.1)

  /// Output only: {"mapping": {"topic_class", "mean_theta"}, "topics", "classes"}.
  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.mapping, {"mapping", "Topics named after classes by the labelled views"});
    v(self.topics, {"topics", "Classes x topics (argmax theta)"});
    v(self.classes, {"classes", "Classes x classes, topics merged by the mapping"});
  }
};

/// Infers theta of the mapping documents (labelled: training views) and maps the topics to their
/// classes, then classifies `test` by argmax theta and the mapping. The test labels are used for
/// the confusion matrices only.
Evaluation evaluate_model(const topics::LdaModel& model, const LabelledCorpus& mapping_documents,
                          const LabelledCorpus& test, const topics::InferenceOptions& options = {});

/// Evaluation as JSON (its description's): {"mapping": {"topic_class", "mean_theta"}, "topics",
/// "classes"}.
inline core::Json evaluation_to_json(const Evaluation& e) { return core::fields_to_json(e); }

}  // namespace proprio::recognition
