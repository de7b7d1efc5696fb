#pragma once
// Classifying the frames of episodes with a learned LDA model (thesis 6.1.4, 6.3.3): each frame
// (or each blob of it) becomes a document as in training (FrameDocumentOptions), its topic
// proportions theta come from the E-step, its topic is argmax theta. Where the episode has
// ground-truth object masks, each document's true object is known, which gives the confusion
// matrices; and the ground-truth masks cut the frames into labelled views of single objects
// (object_view_corpus), the simulator's counterpart of the thesis's segmented ground-truth
// images.
#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "proprio/episode/episode.hpp"
#include "proprio/features/features.hpp"
#include "proprio/features/vocabulary.hpp"
#include "proprio/recognition/confusion.hpp"
#include "proprio/recognition/documents.hpp"
#include "proprio/recognition/image_corpus.hpp"
#include "proprio/recognition/topic_mapping.hpp"
#include "proprio/topics/inference.hpp"
#include "proprio/topics/lda_model.hpp"

namespace proprio::recognition {

struct EpisodeClassifyOptions {
  /// How a frame becomes documents: the same options as training (recognize train --region).
  FrameDocumentOptions frames;
  int frame_step = 1;  ///< classify every n-th frame (>= 1)
  topics::InferenceOptions inference;
  void validate() const;
};

/// One classified document of one frame.
struct ClassifiedDocument {
  int episode = 0;   ///< index into the episodes given
  int frame = 0;     ///< frame index in that episode
  int document = 0;  ///< within the frame (several only for the blobs region)
  std::int64_t tokens = 0;
  /// The true object: index into EpisodeClassification::classes of the object whose
  /// ground-truth mask holds most of the document's features (the arm and the background do not
  /// count); -1 when the episode has no masks or no feature lies on an object.
  int truth = -1;
  int topic = -1;   ///< argmax theta (6.1.4); -1 for an empty document
  int mapped = -1;  ///< the class by a topic mapping (apply_mapping); -1 without one
};

struct EpisodeClassification {
  std::vector<ClassifiedDocument> documents;
  Eigen::MatrixXd theta;  ///< documents x K, rows E[theta_d]
  /// The true objects' names, sorted: catalogue names (the simulator's role prefixes
  /// "scatter-", "distractor-", "neighbour-" dropped, or the FrameDocumentOptions::objects name
  /// an object matched). Empty when no episode has ground-truth masks.
  std::vector<std::string> classes;
  /// classes x topics (argmax theta), documents with a truth only; none without ground truth.
  std::optional<ConfusionMatrix> by_topic;
  struct Summary {
    int episodes = 0, frames = 0, documents = 0;
    std::int64_t empty_documents = 0;  ///< no features in the region: no topic
    std::int64_t tokens = 0;
    double seconds = 0;
    std::string message;
  } summary;
};

/// Classifies every frame_step-th frame of `episodes` with `model` over `vocabulary`. Throws
/// Error when the model and the vocabulary disagree on the number of words, the vocabulary is
/// not of SIFT descriptors, an episode has no frames (naming it), or a region needs what an
/// episode lacks (masks, target, mask files).
EpisodeClassification classify_episodes(const std::vector<episode::Episode>& episodes,
                                        const topics::LdaModel& model,
                                        const features::Vocabulary& vocabulary,
                                        const EpisodeClassifyOptions& options,
                                        const ProgressFn& progress = {});

/// Names the documents' classes by a topic mapping over `mapping_classes` (from labelled views,
/// never the documents' truth) and returns the confusion matrix mapping_classes x
/// mapping_classes of the documents whose truth is one of them (the merged matrix of 7.3.1).
ConfusionMatrix apply_mapping(EpisodeClassification& result, const TopicMapping& mapping,
                              const std::vector<std::string>& mapping_classes);

/// The class name of an episode object (see EpisodeClassification::classes).
std::string object_class_name(const std::string& object_name,
                              const std::vector<std::string>& objects = {});

/// Labelled views of single objects cut from frames by the ground-truth masks: for each of the
/// frames `frames[e]` of episode e and each object whose class is one of `classes`, a document
/// of the features inside that object's mask (grown by `dilate` pixels so that the SIFT patches
/// on its outline count, or shrunk by `erode` pixels so that those mostly off the object do not;
/// object_mask), kept when it has at least `min_features` features (ViewSelection::kMask) or
/// when its bare mask (neither grown nor shrunk) has (kBareMask: the same views whatever the
/// growth or shrinking, a view then possibly with fewer than min_features, even none). Labels
/// index `classes`. erode_min_features > 0 (with erode > 0): the adaptive shrink, each view's
/// mask shrunk by adaptive_erosion (by at most erode pixels, only as far as it keeps that many of
/// its bare mask's features); 0: by erode. Throws Error when an episode has no masks or dilate
/// and erode are out of range or both > 0, or erode_min_features is not in [0, 10000].
LabelledCorpus object_view_corpus(
    const std::vector<episode::Episode>& episodes, const std::vector<std::vector<int>>& frames,
    const std::vector<std::string>& classes, const features::Vocabulary& vocabulary,
    const features::ExtractOptions& options, int min_features = 20, int dilate = 4, int erode = 0,
    ViewSelection selection = ViewSelection::kMask, int erode_min_features = 0);

/// The views of object_view_corpus before quantization (the same views, in the same order): so
/// that several vocabularies can quantize one extraction (views_corpus).
struct LabelledFeatures {
  std::vector<features::Features> views;
  std::vector<int> labels;
  std::vector<std::string> classes;
  /// Where each view comes from (object_view_features fills it; empty otherwise).
  std::vector<ViewOrigin> origins;
};
LabelledFeatures object_view_features(const std::vector<episode::Episode>& episodes,
                                      const std::vector<std::vector<int>>& frames,
                                      const std::vector<std::string>& classes,
                                      const features::ExtractOptions& options,
                                      int min_features = 20, int dilate = 4, int erode = 0,
                                      ViewSelection selection = ViewSelection::kMask,
                                      int erode_min_features = 0);

/// The documents of `views` over `vocabulary` (each view's bag of words), with their labels.
LabelledCorpus views_corpus(const LabelledFeatures& views, const features::Vocabulary& vocabulary);

}  // namespace proprio::recognition
