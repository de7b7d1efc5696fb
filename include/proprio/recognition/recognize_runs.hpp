#pragma once
// The library calls behind `proprio recognize train` and `proprio recognize classify` (thesis
// 6.1, 6.3, 7.3.1): an LDA model learned from the visual words of a folder-per-class image set or
// of episodes' frames, and documents classified by argmax theta, their topics named after classes
// from labelled images (never the test documents).

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "proprio/core/fields.hpp"
#include "proprio/core/json_io.hpp"
#include "proprio/core/provenance.hpp"
#include "proprio/features/colour_words.hpp"
#include "proprio/features/extraction.hpp"
#include "proprio/recognition/documents.hpp"
#include "proprio/recognition/image_corpus.hpp"
#include "proprio/topics/lda_model.hpp"
#include "proprio/topics/lda_runs.hpp"
#include "proprio/topics/online_lda.hpp"

namespace proprio::recognition {

inline constexpr core::ChoiceNames<FrameRegion, 6> kFrameRegionNames{
    {{"whole", FrameRegion::kWhole},
     {"target", FrameRegion::kTarget},
     {"objects", FrameRegion::kObjects},
     {"blobs", FrameRegion::kBlobs},
     {"masks", FrameRegion::kMasks},
     {"each-object", FrameRegion::kEachObject}}};

/// Where the documents come from: a folder-per-class image set (a document per image) or
/// episodes (each a directory holding episode.json, or a directory of them), every
/// frame_step-th frame made into documents by `frames`.
struct DocumentSource {
  std::filesystem::path images;
  std::vector<std::filesystem::path> episodes;
  FrameDocumentOptions frames;  ///< region, objects, masks and the feature options
  int frame_step = 1;

  /// Throws Error unless exactly one of images and episodes is given, or on a bad option.
  void validate() const;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v.choice(self.frames.region,
             {"region",
              "Episodes: whole frame, target, objects, blobs, masks or each-object (ground truth)"},
             kFrameRegionNames);
    v(self.frame_step, {"frame_step", "Episodes: every n-th frame", core::at_least(1)});
  }
};

struct RecognizeTrainOptions {
  DocumentSource source;
  std::filesystem::path vocabulary;  ///< vocabulary file (proprio vocab build; required)
  std::filesystem::path model;       ///< model file to write (required)
  topics::LdaMethod method = topics::LdaMethod::kOnline;
  topics::OnlineLdaOptions online;  ///< K, seed and the online method's options
  int max_iterations = 100;         ///< batch: EM iterations at most
  /// Each document is its features' vocabulary words, then their colour words numbered after
  /// the vocabulary's (features::document_words on `colour`: the patch's mean colour on a fixed
  /// HSV grid, 28 words), so the model has the vocabulary's words + 28: the model `proprio
  /// selfsupervise --colour-words` needs. Off (the default): SIFT words only. Episodes only.
  bool colour_words = false;
  /// colour_words: each colour word counts this many times in the documents the model learns
  /// from (topics::weighted_from), so that the topics follow the objects' colours more than their
  /// SIFT words. The model records the weights (topics::LdaModel::word_weights, lda-model format
  /// version 2) and weighs every document it reads alike (`selfsupervise`, `recognize classify`,
  /// `learn --model`). No effect without colour_words. 1: each once (format version 1). 128, the
  /// default since session 47 (docs/results/selfsupervision/rule-s47-colour-weight.md; learn's
  /// since session 46): on fresh seeds 123-142 selfsupervise's c (its Mixture of Topics) rose
  /// 43.2 -> 59.5 % (+16.3 +- 7.8) on the same pushes, and K = 32 did nothing (tuning seeds).
  int colour_weight = 128;
  features::ColourWordOptions colour;  ///< colour_words: the grid (not a flag)
  bool progress = false;               ///< a progress bar on stderr

  void validate() const;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v.choice(self.method, {"method", "online or batch"}, topics::kLdaMethodNames);
    v(self.max_iterations, {"max_iterations", "EM iterations (batch)", core::at_least(1)});
    v(self.colour_words,
      {"colour_words",
       "Episodes: documents carry a colour word a feature (its patch's mean colour, 28 HSV "
       "words) after its SIFT word; the model has the vocabulary's words + 28"});
    v(self.colour_weight,
      {"colour_weight",
       "colour_words: each colour word counts this many times in the documents learned from "
       "(the model records it and weighs what it reads alike)",
       core::between(1, 1000)});
  }
};

// NOLINTNEXTLINE(bugprone-exception-escape)
struct RecognizeTrainResult {
  topics::LdaModel model;
  std::filesystem::path model_file;  ///< where the model was written
  std::filesystem::path vocabulary;
  std::string source;  ///< "episodes" or "images"
  topics::LdaMethod method = topics::LdaMethod::kOnline;
  std::size_t documents = 0;
  long long tokens = 0;
  int frames = 0;             ///< frames read (episodes)
  bool colour_words = false;  ///< the documents carried colour words
  int colour_weight = 1;      ///< each colour word counted this many times
  std::string summary;        ///< the training summary's line
  std::string report;         ///< brief()'s text: what the CLI prints, lines ending in '\n'
  core::Json document;        ///< format "proprio.recognize.train": the fields described below
  std::string message;        ///< one line: brief()'s first (the Summary convention, core::Summary)
  [[nodiscard]] std::string brief() const { return report; }

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.model_file, {"model", "The model file written"});
    v(self.vocabulary, {"vocabulary", "The vocabulary file"});
    v(self.source, {"source", "episodes or images"});
    v.choice(self.method, {"method", "online or batch"}, topics::kLdaMethodNames);
    v(self.model.num_topics(), {"topics", "Topics K"});
    v(self.model.num_words(), {"words", "Words W"});
    v(self.documents, {"documents", "Documents learned from"});
    v(self.tokens, {"tokens", "Their tokens"});
    v(self.frames, {"frames", "Frames read (episodes)"});
    v(self.colour_words, {"colour_words", "The documents carried colour words"});
    v(self.colour_weight, {"colour_weight", "Each colour word counted this many times"});
    v(self.summary, {"summary", "The training summary's line"});
  }
};

/// Reads the vocabulary and the documents, trains, writes the model. Throws Error when every
/// document is empty.
RecognizeTrainResult run_recognize_train(const RecognizeTrainOptions& options,
                                         const core::Provenance& provenance);

struct RecognizeClassifyOptions {
  std::filesystem::path model;       ///< LDA model file (required)
  std::filesystem::path vocabulary;  ///< the model's vocabulary file (required)
  DocumentSource source;
  /// Labelled folder-per-class images that name the topics (7.3.1); none: topics only. With
  /// `source.images` its class folders must be the same.
  std::filesystem::path map_with;
  /// CSV to write, a row per document: its image or episode and frame, truth, topic, class and
  /// theta; none: not written.
  std::filesystem::path out;
  bool progress = false;

  void validate() const;
};

// NOLINTNEXTLINE(bugprone-exception-escape)
struct RecognizeClassifyResult {
  std::string report;  ///< brief()'s text: the confusion matrices and accuracies, as printed
  std::filesystem::path model;
  // Episodes: the episodes, their region, frame step and frames.
  std::optional<std::vector<std::string>> episodes;
  std::optional<std::string> region;
  std::optional<int> frame_step;
  std::optional<std::int64_t> frames;
  // Images: the image set.
  std::optional<std::filesystem::path> images;
  std::int64_t documents = 0;
  std::int64_t empty_documents = 0;
  std::optional<ConfusionMatrix> topics;   ///< by topic
  std::optional<TopicMapping> mapping;     ///< episodes with map_with: the topic -> class mapping
  std::optional<ConfusionMatrix> classes;  ///< episodes with map_with: topics merged into classes
  std::optional<Evaluation> mapped;        ///< images with map_with
  std::optional<std::filesystem::path> out;
  core::Json document;  ///< format "proprio.recognize.classify": the fields described below
  std::string message;  ///< one line: brief()'s first (the Summary convention, core::Summary)
  [[nodiscard]] std::string brief() const { return report; }

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.model, {"model", "The model file"});
    v(self.episodes, {"episodes", "The episodes classified"});
    v(self.region, {"region", "What of a frame is a document"});
    v(self.frame_step, {"frame_step", "Every n-th frame"});
    v(self.frames, {"frames", "Frames read"});
    v(self.images, {"images", "The images classified"});
    v(self.documents, {"documents", "Documents"});
    v(self.empty_documents, {"empty_documents", "Documents without features"});
    v(self.topics, {"topics", "Truth x topic (argmax theta)"});
    v(self.mapping, {"mapping", "The topic -> class mapping"});
    v(self.classes, {"classes", "Truth x class, topics merged"});
    v(self.mapped, {"mapped", "The classification by the mapping"});
    v(self.out, {"out", "The CSV written"});
  }
};

/// Classifies the documents, names the topics when `map_with` is given, writes `out`. Throws
/// Error naming the model when its number of words is not the vocabulary's.
RecognizeClassifyResult run_recognize_classify(const RecognizeClassifyOptions& options,
                                               const core::Provenance& provenance);

/// An evaluation as `recognize classify` and `experiment` print it: the topic confusion matrix,
/// the topic -> class mapping, the merged class matrix and the accuracies, under `title`.
std::string evaluation_report(const std::string& title, const Evaluation& e);

}  // namespace proprio::recognition
