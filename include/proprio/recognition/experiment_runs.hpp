#pragma once
// The library calls behind `proprio experiment dictionary | batch-online | scatter` (thesis
// 6.3.1-6.3.3, 7.3.1): the experiments of experiments.hpp from files, with the text the CLI
// prints and the record it writes for --json (experiment_sets / experiment_scatter schemas).

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "proprio/core/json_io.hpp"
#include "proprio/core/provenance.hpp"
#include "proprio/recognition/experiments.hpp"

namespace proprio::recognition {

/// A dictionary built by k-means for an experiment, as its record writes it.
struct KmeansRecord {
  int descriptors = 0;  ///< descriptors it was built from
  int iterations = 0;
  double cost = 0;
  double seconds = 0;
  std::string termination;

  [[nodiscard]] static KmeansRecord of(const features::KmeansSummary& s, int descriptors);
  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.descriptors, {"descriptors", "Descriptors the dictionary was built from"});
    v(self.iterations, {"iterations", "Lloyd iterations"});
    v(self.cost, {"cost", "Sum of squared distances to the words"});
    v(self.seconds, {"seconds", "Wall time"});
    v(self.termination, {"termination", "converged or max_iterations"});
  }
};

/// One run of the dictionary / batch-online experiment: its evaluation's record and its set-up.
// NOLINTNEXTLINE(bugprone-exception-escape)
struct SetRunRecord {
  Evaluation evaluation;  ///< its fields are the run's
  std::string name;
  std::string set;
  std::string dictionary;
  std::string method;
  int train_documents = 0;
  int test_documents = 0;
  double train_seconds = 0;
  std::string lda_summary;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    Evaluation::describe(self.evaluation, v);
    v(self.name, {"name", "The run (thesis's name)"});
    v(self.set, {"set", "The image set, A or B"});
    v(self.dictionary, {"dictionary", "specific or wide"});
    v(self.method, {"method", "batch or online LDA"});
    v(self.train_documents, {"train_documents", "Training images"});
    v(self.test_documents, {"test_documents", "Test images"});
    v(self.train_seconds, {"train_seconds", "LDA training time"});
    v(self.lda_summary, {"lda_summary", "The learner's summary"});
  }
};

/// The record of `experiment dictionary` and `experiment batch-online`.
// NOLINTNEXTLINE(bugprone-exception-escape)
struct SetExperimentRecord {
  std::filesystem::path images;
  std::vector<std::string> set_a, set_b, wide;
  int words = 0;
  int test_per_class = 0;
  std::string features;
  std::optional<KmeansRecord> specific_dictionary, wide_dictionary;
  std::vector<SetRunRecord> runs;
  double seconds = 0;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.images, {"images", "The image set"});
    v(self.set_a, {"set_a", "Classes of set A"});
    v(self.set_b, {"set_b", "Classes of set B"});
    v(self.wide, {"wide", "Classes of the wide dictionary"});
    v(self.words, {"words", "Words per dictionary"});
    v(self.test_per_class, {"test_per_class", "Test images per class"});
    v(self.features, {"features", "The feature kind"});
    v(self.specific_dictionary, {"specific_dictionary", "The specific dictionary's k-means"});
    v(self.wide_dictionary, {"wide_dictionary", "The wide dictionary's k-means"});
    v(self.runs, {"runs", "The runs"});
    v(self.seconds, {"seconds", "Wall time"});
  }
};

/// A scatter run's supervised Mixture of Topics: its confusion matrix's record and its fit.
// NOLINTNEXTLINE(bugprone-exception-escape)
struct ScatterMotRecord {
  ConfusionMatrix classes;  ///< its fields are this record's
  std::string summary;
  double smoothing = 0;
  std::vector<MotObjectRecord> objects;  ///< without their mean theta

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    ConfusionMatrix::describe(self.classes, v);
    v(self.summary, {"summary", "The fit's summary"});
    v(self.smoothing, {"smoothing", "The theta smoothing"});
    v(self.objects, {"objects", "The objects"});
  }
};

/// A scatter run's unsupervised Mixture of Topics.
// NOLINTNEXTLINE(bugprone-exception-escape)
struct ScatterUnsupervisedRecord {
  ConfusionMatrix classes;  ///< its fields are this record's
  int chosen_classes = 0;
  std::vector<int> object_class;
  std::vector<int> chosen_classes_per_object;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    ConfusionMatrix::describe(self.classes, v);
    v(self.chosen_classes, {"chosen_classes", "The number of objects BIC would choose"});
    v(self.object_class, {"object_class", "The class each learned object is named after"});
    v(self.chosen_classes_per_object, {"chosen_classes_per_object", "BIC's choice per object"});
  }
};

/// A point of a scatter run's smoothing grid.
// NOLINTNEXTLINE(bugprone-exception-escape)
struct ScatterGridRecord {
  ConfusionMatrix classes;  ///< its fields are this record's
  ThetaSource theta = ThetaSource::kEStep;
  double smoothing = 0;
  std::string prior;
  std::string model = "dirichlet";
  /// The mixtures': the most components per object (absent before 2026-12-03: 10).
  std::optional<int> components;
  /// The -words-multinomial models': the multinomials' weight (absent before session 22).
  std::optional<double> word_weight;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    ConfusionMatrix::describe(self.classes, v);
    v.choice(self.theta, {"theta", "Where theta comes from"}, kThetaSourceNames);
    v(self.smoothing, {"smoothing", "The theta smoothing"});
    v(self.prior, {"prior", "uniform or views"});
    v(self.model, {"model", "The object model: dirichlet, shared-precision or mixture"});
    v(self.components, {"components", "The mixture's most components per object"});
    v(self.word_weight, {"word_weight", "The word multinomials' weight in the pooled score"});
  }
};

/// A classifier that bounds what a representation allows (RepresentationCeiling).
// NOLINTNEXTLINE(bugprone-exception-escape)
struct ScatterCeilingRecord {
  ConfusionMatrix classes;  ///< its fields are this record's
  std::string name;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    ConfusionMatrix::describe(self.classes, v);
    v(self.name, {"name", "The classifier and representation"});
  }
};

/// Where a test view of the scatter experiment comes from (ViewOrigin) and its object.
// NOLINTNEXTLINE(bugprone-exception-escape)
struct ScatterViewRecord {
  int episode = 0;
  int frame = 0;
  std::string object;
  int features = 0;
  int mask_pixels = 0;
  bool at_border = false;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.episode, {"episode", "Index into view_episodes"});
    v(self.frame, {"frame", "Frame of that episode"});
    v(self.object, {"object", "The view's object"});
    v(self.features, {"features", "Its features (inside the mask it is cut by)"});
    v(self.mask_pixels, {"mask_pixels", "Pixels of the object's bare mask"});
    v(self.at_border, {"at_border", "Whether the bare mask touches the image's border"});
  }
};

/// One K of the scatter experiment.
// NOLINTNEXTLINE(bugprone-exception-escape)
struct ScatterRunRecord {
  Evaluation evaluation;  ///< its fields are the run's
  int topics_k = 0;
  std::int64_t updates = 0;
  double train_seconds = 0;
  std::optional<ScatterMotRecord> mot;
  std::optional<ScatterUnsupervisedRecord> mot_unsupervised;
  std::optional<std::vector<ScatterGridRecord>> mot_grid;
  std::optional<std::vector<ScatterCeilingRecord>> ceilings;
  std::optional<std::vector<int>> mixture_words_predicted;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    Evaluation::describe(self.evaluation, v);
    v(self.topics_k, {"topics_k", "Topics K"});
    v(self.updates, {"updates", "Online LDA's mini-batch updates"});
    v(self.train_seconds, {"train_seconds", "LDA training time"});
    v(self.mot, {"mot", "The supervised Mixture of Topics"});
    v(self.mot_unsupervised, {"mot_unsupervised", "The unsupervised Mixture of Topics"});
    v(self.mot_grid, {"mot_grid", "The smoothing grid"});
    v(self.ceilings, {"ceilings", "What the views' theta and words allow"});
    v(self.mixture_words_predicted,
      {"mixture_words_predicted",
       "Each test view's object index by the mixture (E-step fit, first component cap) by "
       "words, in test_view_origins' order (-1: an empty view)"});
  }
};

/// The record of `experiment scatter`.
// NOLINTNEXTLINE(bugprone-exception-escape)
struct ScatterExperimentRecord {
  std::vector<std::string> episodes;
  std::optional<std::string> views;
  std::optional<std::vector<std::string>> view_episodes;
  std::optional<int> view_step, view_block;
  /// With view episodes: the masks' growth in pixels (views and each-object frames), since
  /// 2026-12-03 (4 before, not recorded).
  std::optional<int> mask_dilate;
  /// With view episodes: the masks' shrinking in pixels, since 2026-12-03 (0 before).
  std::optional<int> mask_erode;
  /// With view episodes: the adaptive shrink's least features (0: off), since 2026-12-04.
  std::optional<int> mask_erode_min_features;
  std::optional<std::string> view_selection;
  std::optional<std::string> view_split;
  bool mot = false;
  std::vector<std::string> objects;
  std::string region;
  std::string features;
  int frames = 0;
  int documents = 0;
  std::int64_t tokens = 0;
  int words = 0;
  int batch_size = 0;
  int batch_documents = 0;
  int passes = 0;
  int mapping_views = 0;
  int test_views = 0;
  std::optional<std::vector<ScatterViewRecord>> test_view_origins;
  std::optional<KmeansRecord> dictionary;
  std::vector<ScatterRunRecord> runs;
  double seconds = 0;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.episodes, {"episodes", "The training episodes"});
    v(self.views, {"views", "The folder-per-object views"});
    v(self.view_episodes, {"view_episodes", "The episodes the views were cut from"});
    v(self.view_step, {"view_step", "Every n-th frame of them"});
    v(self.view_block, {"view_block", "Frames per block of the naming / test split"});
    v(self.mask_dilate, {"mask_dilate", "Pixels the object masks were grown by"});
    v(self.mask_erode, {"mask_erode", "Pixels the object masks were shrunk by"});
    v(self.mask_erode_min_features,
      {"mask_erode_min_features",
       "Adaptive shrink: each mask shrunk only as far as it keeps this many features (0: off)"});
    v(self.view_selection, {"view_selection",
                            "Which mask's features kept a view: \"mask\" (the one it is cut by) or "
                            "\"bare\" (the object's bare mask)"});
    v(self.view_split, {"view_split", "blocks or episodes"});
    v(self.mot, {"mot", "Whether the Mixture of Topics classified the views too"});
    v(self.objects, {"objects", "The objects"});
    v(self.region, {"region", "What of a frame is a document"});
    v(self.features, {"features", "The feature kind"});
    v(self.frames, {"frames", "Frames used"});
    v(self.documents, {"documents", "Training documents"});
    v(self.tokens, {"tokens", "Their tokens"});
    v(self.words, {"words", "Words of the dictionary"});
    v(self.batch_size, {"batch_size", "Frames per mini-batch"});
    v(self.batch_documents, {"batch_documents", "Documents per mini-batch"});
    v(self.passes, {"passes", "Passes over the frames"});
    v(self.mapping_views, {"mapping_views", "Labelled views that name the topics"});
    v(self.test_views, {"test_views", "Test views"});
    v(self.test_view_origins, {"test_view_origins", "Where each test view comes from"});
    v(self.dictionary, {"dictionary", "The dictionary's k-means, when built here"});
    v(self.runs, {"runs", "One per K"});
    v(self.seconds, {"seconds", "Wall time"});
  }
};

/// What an experiment command prints and records (`document`, from the set or scatter record),
/// under the Summary convention (core::Summary): brief() is what the CLI prints, `message` its
/// first line.
// NOLINTNEXTLINE(bugprone-exception-escape)
struct ExperimentRun {
  std::string report;  ///< brief()'s text: lines, each ending in '\n'
  std::optional<SetExperimentRecord> set;
  std::optional<ScatterExperimentRecord> scatter;
  core::Json document;
  std::string message;  ///< one line: brief()'s first
  [[nodiscard]] std::string brief() const { return report; }
};

struct SetExperimentRunOptions {
  std::filesystem::path images;  ///< folder-per-class image set, Caltech-256's layout (required)
  /// The runs, seeds and sizes; runs empty: dictionary_runs() when `dictionary`, else
  /// batch_online_runs(). The batch, online and k-means seeds are set to options.seed.
  SetExperimentOptions options;
  bool dictionary = true;  ///< 6.3.1 (specific vs wide dictionary) or 6.3.2 (batch vs online)
  bool progress = false;
};

ExperimentRun run_set_experiment_files(const SetExperimentRunOptions& options,
                                       const core::Provenance& provenance);

struct ScatterExperimentRunOptions {
  std::vector<std::filesystem::path> episodes;  ///< training videos (episodes or their parents)
  std::filesystem::path views;                  ///< folder-per-object views, or
  std::vector<std::filesystem::path> view_episodes;  ///< held-out episodes to cut views from
  std::vector<std::string> objects;  ///< with view_episodes: the objects (catalogue names)
  std::filesystem::path vocabulary;  ///< a vocabulary file; none: built from the frames
  /// The experiment's options; view_features is set from frames.features (frames themselves get
  /// no centre crop: the region decides, and neither do segmented views).
  ScatterExperimentOptions options;
  /// With view_episodes: several seeds over one feature extraction (run_scatter_experiments),
  /// one run each; empty: options.seed alone.
  std::vector<std::uint64_t> seeds;
  bool progress = false;

  /// Throws Error unless exactly one of views and view_episodes is given, and objects with
  /// view_episodes.
  void validate() const;
};

ExperimentRun run_scatter_experiment_files(const ScatterExperimentRunOptions& options,
                                           const core::Provenance& provenance);

/// Called with a seed's index in ScatterExperimentRunOptions::seeds and its run as soon as that
/// seed is done (before the next seed starts): a caller writes each seed's JSON there, so a run
/// stopped part-way keeps the seeds it finished.
using ScatterRunDoneFn = std::function<void(std::size_t index, const ExperimentRun& run)>;

/// One run per seed of options.seeds (or options.seed alone), in that order; each run's
/// provenance records its seed; `run_done` gets each run as it is finished. Throws Error for
/// several seeds with views (only view episodes share their features between seeds).
std::vector<ExperimentRun> run_scatter_experiments_files(const ScatterExperimentRunOptions& options,
                                                         const core::Provenance& provenance,
                                                         const ScatterRunDoneFn& run_done = {});

}  // namespace proprio::recognition
