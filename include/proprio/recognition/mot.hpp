#pragma once
// The Mixture of Topics (thesis 7.1; proprio/topics/mixture_of_topics.hpp) on pictures: labelled
// views become documents (folder-per-class images, or objects cut from episodes' frames by their
// ground-truth masks), LDA's E-step gives each its theta, a Dirichlet per object is fitted to the
// theta of its views, and new views are classified by eq 7.3. The library calls behind `proprio
// mot train|classify|info` (docs/formats/schemas/mot_*.schema.json): each reads its inputs, does
// the one job, writes its outputs and returns what it did with the record the CLI writes for
// --json.

#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "proprio/core/fields.hpp"
#include "proprio/core/json_io.hpp"
#include "proprio/core/provenance.hpp"
#include "proprio/features/extraction.hpp"
#include "proprio/features/vocabulary.hpp"
#include "proprio/recognition/confusion.hpp"
#include "proprio/recognition/image_corpus.hpp"
#include "proprio/topics/inference.hpp"
#include "proprio/topics/lda_model.hpp"
#include "proprio/topics/mixture_of_topics.hpp"
#include "proprio/topics/mot_model_io.hpp"

namespace proprio::recognition {

/// A supervised MoT learned from labelled documents and tested on others.
struct MotEvaluation {
  topics::MotFit fit;
  /// Test documents with features, classified (rows in the order of `classified`).
  topics::MotClassification classification;
  std::vector<int> classified;  ///< index of each classified test document
  ConfusionMatrix classes;  ///< test classes x the model's objects; empty documents unclassified
};

/// E[theta] of every document of `corpus` by the E-step of `model`, and which documents are
/// empty (no tokens: their theta is the prior's and says nothing).
struct DocumentTheta {
  Eigen::MatrixXd theta;  ///< D x K
  std::vector<bool> empty;
};
DocumentTheta document_theta(const topics::LdaModel& model, const topics::Corpus& corpus,
                             const topics::InferenceOptions& options = {});

/// Where a view's theta comes from.
enum class ThetaSource {
  /// E[theta] of LDA's variational E-step (document_theta): the thesis's theta.
  kEStep,
  /// The mean over the view's words of p(topic | word) = beta_kw / sum_k' beta_k'w (beta the
  /// model's topic_word()): each word's topic posterior under a uniform prior, with no mean-field
  /// iterations that let a view's dominant topic absorb its other words
  /// (word_posterior_theta).
  kWordPosterior,
};
inline constexpr core::ChoiceNames<ThetaSource, 2> kThetaSourceNames{
    {{"estep", ThetaSource::kEStep}, {"word-posterior", ThetaSource::kWordPosterior}}};

/// theta of every document by ThetaSource::kWordPosterior: row d = (1/N_d) sum_n p(k | w_dn);
/// empty documents get the uniform theta and are marked empty. The corpus must have the model's
/// W words (Error otherwise).
DocumentTheta word_posterior_theta(const topics::LdaModel& model, const topics::Corpus& corpus);

/// theta of every document from `source`.
DocumentTheta view_theta(const topics::LdaModel& model, const topics::Corpus& corpus,
                         ThetaSource source, const topics::InferenceOptions& options = {});

/// evaluate_mot with the views' theta from `source`.
MotEvaluation evaluate_mot(const topics::LdaModel& model, const LabelledCorpus& train,
                           const LabelledCorpus& test, const topics::MotOptions& options,
                           const topics::InferenceOptions& inference, ThetaSource source);

/// Fits a supervised MoT to the theta of `train`'s documents (labels: their classes; empty
/// documents left out) and classifies `test`'s (thesis 7.1, eq 7.3). train and test have the same
/// classes. Throws Error as topics::fit_mot (a class with fewer than 2 non-empty views).
MotEvaluation evaluate_mot(const topics::LdaModel& model, const LabelledCorpus& train,
                           const LabelledCorpus& test, const topics::MotOptions& options = {},
                           const topics::InferenceOptions& inference = {});

/// An unsupervised MoT learned from unlabelled documents and tested on others.
struct MotUnsupervisedEvaluation {
  topics::MotFit fit;  ///< with C = the number of classes
  /// The class each learned object is named after: the class most of its training documents
  /// have (the labels name the objects after learning, as topics are named; they do not guide
  /// it). Several objects may get one class, a class none.
  std::vector<int> object_class;
  ConfusionMatrix classes;  ///< test classes x classes, by the named objects
  int chosen_classes = 0;   ///< C chosen by BIC (options.max_classes) on the same theta
  /// For each class: the C BIC chooses on that class's training views alone (0 when it has
  /// fewer than 4). Above 1, one object's theta is itself a mixture: why BIC over-estimates the
  /// number of objects (docs/results/mot.md).
  std::vector<int> chosen_per_class;
};

/// Fits an unsupervised MoT (C = the number of classes) to the theta of `train`'s documents
/// without their labels, names each object after the majority class of its documents, and
/// classifies `test`'s documents; also reports the C that BIC would choose.
MotUnsupervisedEvaluation evaluate_mot_unsupervised(const topics::LdaModel& model,
                                                    const LabelledCorpus& train,
                                                    const LabelledCorpus& test,
                                                    const topics::MotOptions& options = {},
                                                    const topics::InferenceOptions& inference = {});

/// What a representation of the views allows, by classifiers that assume no Dirichlet: the
/// ceiling of any model of theta, and of the documents themselves (docs/results/mot.md, fifth
/// round). If the ceilings on theta are far below those on the words, the loss is in LDA's
/// topics, not in the Mixture of Topics.
struct RepresentationCeiling {
  /// knn-estep, knn-word-posterior (5 nearest labelled views by the Hellinger distance of their
  /// theta); logistic-estep, logistic-word-posterior (multinomial logistic regression on
  /// log theta smoothed by 0.01: the linear family one Dirichlet per object belongs to, since
  /// log Dir(theta | omega_c) is linear in log theta); knn-words (Hellinger distance of the
  /// views' word proportions); naive-bayes-words (multinomial naive Bayes over the words, each
  /// object's pooled counts with add-one smoothing).
  std::string name;
  ConfusionMatrix classes;
};

/// The ceilings of RepresentationCeiling for LDA `model`, labelled views `train` and test views
/// `test` (same classes; empty documents unclassified).
std::vector<RepresentationCeiling> representation_ceilings(
    const topics::LdaModel& model, const LabelledCorpus& train, const LabelledCorpus& test,
    const topics::InferenceOptions& inference = {});

/// Each test row's class by majority vote of its k nearest training rows (Euclidean distance;
/// ties go to the class of the nearest among the tied). Rows with label < 0 are not neighbours.
std::vector<int> knn_predict(const Eigen::MatrixXd& train, std::span<const int> labels, int classes,
                             const Eigen::MatrixXd& test, int k);

/// Multinomial logistic regression (softmax, L2 penalty `l2` on the weights, features
/// standardised on `train`, full-batch gradient descent for `iterations` steps): each test row's
/// most probable class. Rows with label < 0 are left out.
std::vector<int> logistic_predict(const Eigen::MatrixXd& train, std::span<const int> labels,
                                  int classes, const Eigen::MatrixXd& test, double l2 = 1e-3,
                                  int iterations = 500);

/// Multinomial naive Bayes over words: p(w | c) from class c's pooled counts in `train` plus one,
/// uniform class prior; each test document's class (-1 for an empty one).
std::vector<int> naive_bayes_predict(const LabelledCorpus& train, const topics::Corpus& test);

/// The identity of a visual vocabulary: CRC-32 of its word count, dimension and float32 words.
std::uint32_t vocabulary_checksum(const features::Vocabulary& vocabulary);

/// Where `mot train` and `mot classify` get their documents: either a folder-per-class image set
/// (each image a document, its folder its object) or episodes (each object of every
/// view_step-th frame cut out by its ground-truth mask, object_view_corpus).
struct MotSourceOptions {
  std::filesystem::path lda_model;   ///< LDA model file (required)
  std::filesystem::path vocabulary;  ///< vocabulary file (required)
  std::filesystem::path images;      ///< folder-per-class image set, or
  std::filesystem::path episodes;    ///< an episode, or a directory of episodes
  /// Episodes: the objects (catalogue names, comma-separated); empty: every object that is not
  /// the arm, named as EpisodeClassification::classes.
  std::string objects;
  int view_step = 5;      ///< episodes: every n-th frame
  int min_features = 20;  ///< episodes: a view needs this many features
  int dilate = 4;         ///< episodes: masks grown by this many pixels
  /// How documents' features are extracted: the same options (and flags) as `recognize`.
  features::ExtractOptions features;

  /// Throws Error unless exactly one of images and episodes is given, and bounds hold.
  void validate() const;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.objects, {"objects", "Episodes: objects to cut out, comma-separated (default: all)"});
    v(self.view_step, {"view_step", "Episodes: use every n-th frame", core::between(1, 1000000)});
    v(self.min_features,
      {"min_features", "Episodes: features a view needs", core::between(1, 1000000)});
    v(self.dilate, {"dilate", "Episodes: grow the masks by this many px", core::between(0, 100)});
  }
};

/// Where a MoT command's views came from, as its record writes it.
struct MotSourceRecord {
  std::filesystem::path lda_model;
  std::filesystem::path vocabulary;
  std::string source;           ///< "episodes" or "images"
  std::filesystem::path input;  ///< the episodes' or images' directory

  [[nodiscard]] static MotSourceRecord of(const MotSourceOptions& o);
  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.lda_model, {"lda_model", "The LDA model file"});
    v(self.vocabulary, {"vocabulary", "The vocabulary file"});
    v(self.source, {"source", "episodes or images"});
    v(self.input, {"input", "The episodes' or images' directory"});
  }
};

/// The LDA model and vocabulary a MoT model is built on, as records write them.
// NOLINTNEXTLINE(bugprone-exception-escape)
struct MotBasisRecord {
  std::string lda_checksum;  ///< 8 hex digits
  int lda_topics = 0;
  int lda_words = 0;
  core::Json vocabulary_checksum;  ///< 8 hex digits, or null when none was recorded

  [[nodiscard]] static MotBasisRecord of(const topics::MotBasis& b);
  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.lda_checksum, {"lda_checksum", "CRC-32 of the LDA model, hex"});
    v(self.lda_topics, {"lda_topics", "Its topics"});
    v(self.lda_words, {"lda_words", "Its words"});
    v(self.vocabulary_checksum, {"vocabulary_checksum", "The vocabulary's checksum, or null"});
  }
};

/// How an object's Dirichlet fit ended.
struct MotFitRecord {
  bool converged = false;
  std::string stop;
  int iterations = 0;
  double log_likelihood = 0.0;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.converged, {"converged", "Whether the fit converged"});
    v(self.stop, {"stop", "Why it stopped"});
    v(self.iterations, {"iterations", "Fixed-point and Newton iterations"});
    v(self.log_likelihood, {"log_likelihood", "eq 4 at the fitted alpha, nats"});
  }
};

/// One object of a MoT model (its Dirichlet) as records list it.
/// One Dirichlet of an object's mixture (MotOptions::components).
struct MotComponentRecord {
  double weight = 0;
  std::vector<double> alpha;
  double precision = 0;
  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.weight, {"weight", "The component's weight w_j"});
    v(self.alpha, {"alpha", "Its Dirichlet's parameters"});
    v(self.precision, {"precision", "Its precision, sum of alpha"});
  }
};

struct MotObjectRecord {
  std::string name;
  double views = 0;
  std::vector<double> alpha;
  std::optional<std::vector<double>> mean;  ///< in MoT model records
  double precision = 0.0;
  std::optional<MotFitRecord> fit;  ///< with `mot train`
  /// When the object is a mixture of Dirichlets (its density; alpha above is the one-Dirichlet
  /// fit of the same views).
  std::optional<std::vector<MotComponentRecord>> components;

  /// The objects of `model`, with their fits when `fits` (one per object) is given.
  [[nodiscard]] static std::vector<MotObjectRecord> of(
      const topics::MotModel& model,
      const std::vector<topics::DirichletFitSummary>* fits = nullptr);
  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.name, {"name", "The object"});
    v(self.views, {"views", "Views learned from"});
    v(self.alpha, {"alpha", "Its Dirichlet's parameters"});
    v(self.mean, {"mean", "Its Dirichlet's mean theta"});
    v(self.precision, {"precision", "Its Dirichlet's precision, sum of alpha"});
    v(self.fit, {"fit", "How its fit ended"});
    v(self.components, {"components", "Its mixture of Dirichlets, when it has one"});
  }
};

/// Numbers as records write them: null where not finite.
std::vector<core::Json> finite_or_null(const std::vector<double>& values);

struct MotTrainOptions {
  MotSourceOptions source;
  std::filesystem::path model;  ///< MoT model file to write (required, docs/formats/mot-model.md)
  /// Learn without labels (k-means over theta, mot.classes objects or chosen by BIC).
  bool unsupervised = false;
  topics::MotOptions mot;

  void validate() const;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.unsupervised,
      {"unsupervised", "Learn without labels: k-means over theta (thesis 7.3.3)"});
  }
};

// NOLINTNEXTLINE(bugprone-exception-escape)
struct MotTrainResult {
  topics::MotFit fit;
  topics::MotBasis basis;
  std::filesystem::path model_file;  ///< the model file written
  MotSourceRecord source;
  bool unsupervised = false;
  topics::MotOptions options;
  int documents = 0;        ///< views made
  int empty_documents = 0;  ///< of which without features (left out)
  core::Json document;      ///< format "proprio.mot.train" (mot_train.schema.json): describe()
  std::string message;      ///< one line: what happened (brief()'s first line)
  [[nodiscard]] std::string brief() const;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.model_file, {"model", "The MoT model file written"});
    MotSourceRecord::describe(self.source, v);
    v(self.unsupervised, {"unsupervised", "Learned without labels"});
    v(self.options, {"options", "The MoT options"});
    v(self.documents, {"documents", "Views made"});
    v(self.empty_documents, {"empty_documents", "Views without features, left out"});
    v(MotBasisRecord::of(self.basis), {"basis", "The LDA model and vocabulary it is built on"});
    v(MotObjectRecord::of(self.fit.model, &self.fit.summary.fits), {"objects", "Its objects"});
    v(self.fit.summary.log_likelihood, {"log_likelihood", "Of the fit, nats"});
    v(finite_or_null(self.fit.summary.bic), {"bic", "BIC per number of objects (null: none)"});
    v(self.brief(), {"summary", "The summary line"});
  }
};

/// Reads the LDA model, vocabulary and views, infers theta, fits the MoT (supervised by the
/// views' objects, or unsupervised), writes the model file recording the LDA model's and
/// vocabulary's checksums. Throws Error when the LDA model and the vocabulary disagree on the
/// number of words, an object has fewer than 2 views with features, or as fit_mot.
MotTrainResult run_mot_train(const MotTrainOptions& options, const core::Provenance& provenance);

/// How `mot classify` scores a view against each object.
enum class MotClassifyBy {
  /// Eq 7.3 on the view's E-step theta: log Dir(theta | omega_c) + log p(c) (topics::classify_mot).
  kTheta,
  /// The view's words' marginal likelihood with the object's Dirichlet (or mixture) as LDA's
  /// prior of theta, + log p(c) (topics::classify_mot_words): the view taken whole rather than
  /// reduced to one point theta.
  kWords,
};
inline constexpr core::ChoiceNames<MotClassifyBy, 2> kMotClassifyByNames{
    {{"theta", MotClassifyBy::kTheta}, {"words", MotClassifyBy::kWords}}};

struct MotClassifyOptions {
  MotSourceOptions source;
  std::filesystem::path model;  ///< MoT model file (required)
  /// theta (eq 7.3 on the E-step's theta, the thesis's) or words (topics::classify_mot_words).
  /// theta stays the default: on the scatter report (docs/results/mot.md, sixth round) words
  /// wins clearly only with a mixture per object (`mot train --components 10`; 3 objects 88.2%
  /// against 83.8%, better on 5 of 5 seeds), which is not the default model; with one Dirichlet
  /// it gains 2.7 points (3 objects, 4 of 5 seeds) and 0.5 (4 objects), and it costs an E-step
  /// per object (and component) per view.
  MotClassifyBy by = MotClassifyBy::kTheta;
  /// CSV to write (required): document, source (image file or episode directory), frame (-1 for
  /// images), truth (the folder's or mask's object), class (the MoT's, empty for a view without
  /// features), then p_<object> for each of the model's objects (eq 7.3).
  std::filesystem::path out;

  void validate() const;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v.choice(self.by,
             {"by",
              "Score a view by its theta (eq 7.3) or by its words' likelihood under each object's "
              "Dirichlet as LDA's prior"},
             kMotClassifyByNames);
  }
};

// NOLINTNEXTLINE(bugprone-exception-escape)
struct MotClassifyResult {
  ConfusionMatrix confusion;                 ///< truth classes x the model's objects
  MotClassifyBy by = MotClassifyBy::kTheta;  ///< how the views were scored
  std::filesystem::path model_file;
  MotSourceRecord source;
  std::filesystem::path out;  ///< the CSV written
  int documents = 0;
  int empty_documents = 0;
  core::Json document;  ///< format "proprio.mot.classify" (mot_classify.schema.json): describe()
  std::string message;  ///< one line: what happened (brief()'s first line)
  [[nodiscard]] std::string brief() const;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.model_file, {"model", "The MoT model file"});
    MotSourceRecord::describe(self.source, v);
    v(self.out, {"out", "The CSV written"});
    v.choice(self.by, {"by", "How the views were scored: theta or words"}, kMotClassifyByNames);
    v(self.documents, {"documents", "Views made"});
    v(self.empty_documents, {"empty_documents", "Views without features, unclassified"});
    v(self.confusion, {"confusion", "Truth classes x the model's objects"});
  }
};

/// Reads the MoT model and checks that the LDA model and vocabulary are the ones it was built on
/// (Error otherwise: the CLI exits 2), then classifies every view (by options.by) and writes the
/// CSV.
MotClassifyResult run_mot_classify(const MotClassifyOptions& options,
                                   const core::Provenance& provenance);

struct MotUpdateOptions {
  MotSourceOptions source;      ///< the new labelled views (their folder's or mask's object)
  std::filesystem::path model;  ///< MoT model file to update (required)
  /// Where the updated model goes (required; may be `model` itself: written atomically).
  std::filesystem::path out;
  /// The online rule (update: exact or resample), forgetting and seed; the smoothing is the
  /// model's own.
  topics::MotOptions mot;

  void validate() const;
};

// NOLINTNEXTLINE(bugprone-exception-escape)
struct MotUpdateResult {
  topics::MotUpdateSummary summary;
  topics::MotModel model;  ///< the updated model (as written)
  topics::MotBasis basis;  ///< its basis
  std::filesystem::path model_file;
  std::filesystem::path out;
  MotSourceRecord source;
  topics::MotUpdateRule rule = topics::MotUpdateRule::kExact;
  double forgetting = 0.0;
  int documents = 0;        ///< new views made
  int empty_documents = 0;  ///< of which without features (skipped)
  core::Json document;      ///< format "proprio.mot.update" (mot_update.schema.json): describe()
  std::string message;      ///< one line: what happened (brief()'s first line)
  [[nodiscard]] std::string brief() const;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.model_file, {"model", "The MoT model file updated"});
    v(self.out, {"out", "Where the updated model was written"});
    MotSourceRecord::describe(self.source, v);
    v.choice(self.rule, {"rule", "exact or resample"}, topics::kMotUpdateRuleNames);
    v(self.forgetting, {"forgetting", "The forgetting factor"});
    v(self.documents, {"documents", "New views made"});
    v(self.empty_documents, {"empty_documents", "Views without features, skipped"});
    v(self.summary.views, {"new_views", "New views learned from"});
    v(self.summary.new_objects, {"new_objects", "Objects new to the model"});
    v(self.summary.resampled, {"resampled", "Samples drawn from old Dirichlets"});
    v(MotBasisRecord::of(self.basis), {"basis", "The LDA model and vocabulary it is built on"});
    v(MotObjectRecord::of(self.model), {"objects", "Its objects"});
  }
};

/// Online update (thesis 8.1.2; topics::update_mot): reads the model and checks that the LDA
/// model and vocabulary are the ones it was built on (Error otherwise: the CLI exits 2), infers
/// the new views' theta, merges them into their objects (a new object name adds an object, which
/// needs 2 views) and writes the updated model to options.out. With the exact rule and no
/// forgetting the result equals training on the old and new views at once.
MotUpdateResult run_mot_update(const MotUpdateOptions& options, const core::Provenance& provenance);

/// What a MoT model file holds, under the Summary convention (core::Summary): brief() is what the
/// CLI prints (`lines`, each ended by '\n'), `message` its first line.
// NOLINTNEXTLINE(bugprone-exception-escape)
struct MotInfo {
  std::vector<std::string> lines;  ///< for a person
  std::string message;             ///< one line: brief()'s first
  [[nodiscard]] std::string brief() const {
    std::string text;
    for (const std::string& line : lines) text += line + '\n';
    return text;
  }
  std::filesystem::path model_file;
  topics::MotModelFile file;
  core::Json document;  ///< format "proprio.mot.info" (mot_info.schema.json): describe()

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.model_file, {"model", "The MoT model file"});
    v(topics::kMotModelFormatVersion, {"format_version_of_model", "The file's format version"});
    v.choice(self.file.model.prior, {"prior", "The prior over objects"}, topics::kMotPriorNames);
    v(self.file.model.smoothing, {"smoothing", "The theta smoothing"});
    v(MotBasisRecord::of(self.file.basis), {"basis", "The LDA model and vocabulary"});
    v(MotObjectRecord::of(self.file.model), {"objects", "Its objects"});
  }
};

/// What a MoT model file holds: its basis and each object's Dirichlet (alpha, precision, mean).
MotInfo run_mot_info(const std::filesystem::path& model, const core::Provenance& provenance);

}  // namespace proprio::recognition
