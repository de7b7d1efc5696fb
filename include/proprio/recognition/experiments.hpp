#pragma once
// The object-modelling experiments of thesis 6.3 and 7.3.1, rerun on any folder-per-class image
// set and on simulated videos:
//  - set experiments (6.3.1 specific vs wide dictionary, Tables 6.1-6.2; 6.3.2 batch vs online
//    LDA, Table 6.3): two sets of classes A and B, a specific dictionary from A's training images
//    and a wide one from many classes, LDA with K = classes per set on each set's training
//    images, classification of its test images;
//  - the scatter experiment (6.3.3, Tables 6.4-6.5; 7.3.1, Tables 7.1-7.2): online LDA with
//    mini-batches of 50 frames on videos of objects moved about, classification of held-out views
//    of each object, with K = number of objects and with more topics, merged.
// In every case topics are named after classes from labelled training images only.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "proprio/episode/episode.hpp"
#include "proprio/features/image_set.hpp"
#include "proprio/features/kmeans.hpp"
#include "proprio/features/vocabulary.hpp"
#include "proprio/recognition/documents.hpp"
#include "proprio/recognition/image_corpus.hpp"
#include "proprio/recognition/mot.hpp"
#include "proprio/topics/batch_lda.hpp"
#include "proprio/topics/online_lda.hpp"

namespace proprio::recognition {

/// Which LDA learner.
enum class LdaMethod { kBatch, kOnline };
std::string to_string(LdaMethod m);

struct SetExperimentOptions {
  std::vector<std::string> set_a;  ///< classes of set A; empty: the first half of the classes
  std::vector<std::string> set_b;  ///< classes of set B; empty: the other half
  /// Classes of the wide dictionary; empty: every class of the image set.
  std::vector<std::string> wide;
  int dictionary_images = 30;       ///< images per class for a dictionary (thesis: 30)
  int descriptors_per_image = 100;  ///< dense SIFT drawn per image (thesis: 100)
  features::KmeansOptions kmeans;   ///< 400 words, stop below 0.1% change
  int test_per_class = 20;          ///< test images per class (thesis: 20); the rest train
  features::ExtractOptions features;
  topics::BatchLdaOptions batch;    ///< num_topics is set to the classes of the set
  topics::OnlineLdaOptions online;  ///< num_topics is set to the classes of the set
  std::uint64_t seed = 1;           ///< split, descriptor samples, k-means and LDA
  /// Which models (name, set "A"/"B", dictionary "specific"/"wide", method): see
  /// dictionary_runs() and batch_online_runs().
  struct Run {
    std::string name;
    std::string set;
    std::string dictionary;
    LdaMethod method = LdaMethod::kBatch;
  };
  std::vector<Run> runs;
  void validate() const;
};

/// Thesis 6.3.1: C_AS, C_BS, C_AW, C_BW with batch LDA.
std::vector<SetExperimentOptions::Run> dictionary_runs();
/// Thesis 6.3.2: C_AW, C_BW with batch LDA and C_AO, C_BO with online LDA (wide dictionary).
std::vector<SetExperimentOptions::Run> batch_online_runs();

struct SetRunResult {
  SetExperimentOptions::Run run;
  Evaluation evaluation;
  int train_documents = 0;
  int test_documents = 0;
  double train_seconds = 0;
  std::string lda_summary;  ///< the learner's brief summary
};

struct SetExperimentResult {
  std::vector<std::string> set_a, set_b, wide;
  std::optional<features::KmeansSummary> specific_kmeans, wide_kmeans;
  int specific_descriptors = 0, wide_descriptors = 0;
  std::vector<SetRunResult> runs;
  double seconds = 0;
};

/// Runs the set experiment on `set`. Throws Error on bad options, unknown or overlapping class
/// names, or classes with too few images.
SetExperimentResult run_set_experiment(const features::ImageSet& set,
                                       const SetExperimentOptions& options,
                                       const ProgressFn& progress = {});

struct ScatterExperimentOptions {
  /// Numbers of topics to try; 0 stands for the number of objects (thesis: K = objects, and 8).
  std::vector<int> topics{0, 8};
  /// How frames become documents: by default the features on the named objects (the view
  /// folders' classes) by the ground-truth masks.
  FrameDocumentOptions frames{FrameRegion::kObjects, {}, {}, {}, {}};
  int frame_step = 1;  ///< use every n-th frame
  /// Dictionary from the training frames: descriptors_per_frame from dictionary_frames frames.
  int dictionary_frames = 200;
  int descriptors_per_frame = 100;
  features::KmeansOptions kmeans;  ///< 400 words
  /// Online LDA: mini-batches of 50 frames (6.3.3): batch_size counts frames; with several
  /// documents a frame, a mini-batch holds batch_size * documents / frames documents.
  topics::OnlineLdaOptions online = [] {
    topics::OnlineLdaOptions o;
    o.batch_size = 50;
    return o;
  }();
  /// Views of each object used (with their labels) to name the topics; the rest are the test.
  double mapping_fraction = 0.5;
  /// How a view becomes a document: the whole image (the object over its backdrop).
  features::ExtractOptions view_features;
  /// Views cut from the frames of held-out episodes (run_scatter_experiment with view
  /// episodes): every view_step-th frame, each object's features inside its ground-truth mask,
  /// kept when there are at least view_min_features of them.
  int view_step = 5;
  int view_min_features = 20;
  /// Each view's mask is grown by this many pixels before its features are taken
  /// (object_view_features' dilate; 0: the grid points on the object only). The CLI's --dilate
  /// sets it and frames.dilate together, so that LDA's documents and the views are cut alike.
  int view_dilate = 4;
  /// Each view's mask is shrunk by this many pixels instead (object_mask; 0 unless view_dilate
  /// is 0). The CLI's --erode sets it and frames.erode together.
  int view_erode = 0;
  /// The adaptive shrink (object_view_features' erode_min_features; 0, the default: off): each
  /// view's mask shrunk by at most view_erode pixels, only as far as it keeps this many of its
  /// bare mask's features. The CLI's --erode-min-features sets it and
  /// frames.erode_min_features together. In [0, 10000].
  int view_erode_min_features = 0;
  /// Views kept by the features of their bare masks (ViewSelection::kBareMask), so that grown
  /// or shrunk masks are scored on the same views as the bare ones; kMask (the default): by the
  /// features of the mask they are cut by.
  ViewSelection view_selection = ViewSelection::kMask;
  /// View episodes are cut into blocks of view_block frames; a mapping_fraction of the blocks
  /// (spread evenly: alternate ones for 0.5) name the topics, the others are the test.
  int view_block = 25;
  /// View episodes split by episode instead of by blocks: the first round(mapping_fraction * n)
  /// view episodes (in the order given) give the labelled views, the others the test views, so
  /// that no test frame has a near-copy among the labelled ones.
  bool split_by_episode = false;
  /// Also fit a supervised Mixture of Topics (thesis 7.1) to the theta of the labelled views and
  /// classify the test views by it (ScatterRunResult::mot): the same LDA model and views as the
  /// argmax-theta evaluation.
  bool mot = false;
  topics::MotOptions mot_options;
  /// With mot: also evaluate the supervised MoT at each of these theta smoothings
  /// (MotOptions::smoothing), with either prior and each object model (one Dirichlet, a shared
  /// precision, a mixture of at most 10 Dirichlets per object; ScatterRunResult::mot_grid): the
  /// tuning grid of docs/results/mot.md. Empty: none.
  std::vector<double> mot_smoothing_grid;
  /// With mot_smoothing_grid: the grid's mixture model is fitted once per value here, the most
  /// components an object may have (MotOptions::components; each >= 2), so that the cap is tuned
  /// on the same LDA model and views. Default: 10 alone (the grid before 2026-12-03).
  std::vector<int> mot_grid_components{10};
  /// With mot_smoothing_grid: also pool each object model's classification by words with the
  /// objects' word multinomials fitted to the labelled views (topics::fit_word_multinomials,
  /// topics::pool_word_multinomials), once per weight here, each in [0, 1] (model
  /// "<model>-words-multinomial"). Default: none (the grid before session 22).
  std::vector<double> mot_grid_word_weights;
  std::uint64_t seed = 1;
  void validate() const;
};

/// One point of ScatterExperimentOptions::mot_smoothing_grid.
struct MotGridPoint {
  ThetaSource source = ThetaSource::kEStep;
  double smoothing = 0;
  topics::MotPrior prior = topics::MotPrior::kViews;
  /// The object model: "dirichlet" (one per object), "shared-precision" (one precision shared
  /// by the objects) or "mixture" (MotOptions::components = 10); with "-words" appended, the same
  /// fit classifying the test views by their words (topics::classify_mot_words; smoothing 0);
  /// with "-words-multinomial", that pooled with the objects' word multinomials at word_weight.
  std::string model = "dirichlet";
  /// The mixture's most components per object (ScatterExperimentOptions::mot_grid_components);
  /// 1 for the other models.
  int components = 1;
  /// "-words-multinomial" models: the multinomials' weight (ScatterExperimentOptions::
  /// mot_grid_word_weights).
  std::optional<double> word_weight;
  ConfusionMatrix classes;
};

struct ScatterRunResult {
  int topics = 0;
  Evaluation evaluation;
  topics::OnlineLdaSummary summary;
  std::optional<MotEvaluation> mot;  ///< with ScatterExperimentOptions::mot
  /// With ScatterExperimentOptions::mot: the unsupervised MoT on the same views (labels only
  /// name its objects).
  std::optional<MotUnsupervisedEvaluation> mot_unsupervised;
  std::vector<MotGridPoint> mot_grid;  ///< with ScatterExperimentOptions::mot_smoothing_grid
  /// With ScatterExperimentOptions::mot_smoothing_grid: what the views' theta and words allow
  /// (representation_ceilings) on the same LDA model and views.
  std::vector<RepresentationCeiling> ceilings;
  /// With mot_smoothing_grid and view episodes: each test view's object by the mixture of at
  /// most mot_grid_components.front() Dirichlets per object (fitted on the E-step theta, prior
  /// from the views) classifying by its words (-1: an empty view), in test_origins' order.
  std::vector<int> mixture_words_predicted;
};

struct ScatterExperimentResult {
  std::vector<std::string> objects;  ///< the view folders' classes
  int frames = 0;                    ///< frames used
  int documents = 0;                 ///< training documents (empty ones dropped)
  std::int64_t tokens = 0;
  int mapping_views = 0, test_views = 0;
  /// With view episodes: where each test view comes from, and its object (test_labels).
  std::vector<ViewOrigin> test_origins;
  std::vector<int> test_labels;
  std::vector<int> test_features;                 ///< each test view's features
  std::optional<features::KmeansSummary> kmeans;  ///< when the dictionary was built here
  int dictionary_descriptors = 0;                 ///< descriptors it was built from
  int words = 0;
  int batch_documents = 0;  ///< documents per mini-batch (the frames' documents, see online)
  std::vector<ScatterRunResult> runs;
  double seconds = 0;
};

/// Runs the scatter experiment: documents from every frame_step-th frame of the episodes, in
/// order; a dictionary from them unless `vocabulary` is given; online LDA for each K; views of
/// `views`' classes split per class into mapping and test views (seeded).
ScatterExperimentResult run_scatter_experiment(const std::vector<episode::Episode>& episodes,
                                               const features::ImageSet& views,
                                               const ScatterExperimentOptions& options,
                                               const features::Vocabulary* vocabulary = nullptr,
                                               const ProgressFn& progress = {});

/// The same with views cut from the frames of `view_episodes` (never used for the dictionary or
/// LDA) by the ground-truth masks (object_view_corpus): the segmented views of each of `objects`
/// that the thesis's ground-truth images were. Each view episode is cut into blocks of
/// view_block frames; the views of a mapping_fraction of the blocks name the topics, those of
/// the others are the test. Throws Error without view episodes or objects, or when an object
/// has no view on either side.
ScatterExperimentResult run_scatter_experiment(const std::vector<episode::Episode>& episodes,
                                               const std::vector<episode::Episode>& view_episodes,
                                               const std::vector<std::string>& objects,
                                               const ScatterExperimentOptions& options,
                                               const features::Vocabulary* vocabulary = nullptr,
                                               const ProgressFn& progress = {});

/// The same for several seeds at once: one result per seed, each equal to a run with
/// options.seed = that seed alone (dictionary, documents, LDA and MoT all follow the seed), but
/// the frames' and the views' features are extracted only once (they do not depend on the seed),
/// which is most of a run's time. Throws Error without seeds.
/// `seed_done`, when given, is called with each seed's index in `seeds` and its finished result
/// before the next seed starts, so that a caller can keep (write out) the seeds already done
/// if a long run is stopped; an exception from it stops the run.
using ScatterSeedDoneFn =
    std::function<void(std::size_t index, const ScatterExperimentResult& result)>;
std::vector<ScatterExperimentResult> run_scatter_experiments(
    const std::vector<episode::Episode>& episodes,
    const std::vector<episode::Episode>& view_episodes, const std::vector<std::string>& objects,
    const ScatterExperimentOptions& options, const std::vector<std::uint64_t>& seeds,
    const features::Vocabulary* vocabulary = nullptr, const ProgressFn& progress = {},
    const ScatterSeedDoneFn& seed_done = {});

}  // namespace proprio::recognition
