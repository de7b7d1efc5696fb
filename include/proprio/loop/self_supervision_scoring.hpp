#pragma once
// Self-supervision (loop/self_supervision.hpp) measured against the simulator's ground truth
// (thesis 7.3.2, Tables 7.3 vs 7.4). The GroundTruthAttendant is the person at the simulated table:
// it re-scatters the objects when the learner asks (SimulatedRobot::scatter, logged) and, told
// what the learner does, records what really happened; the learner never reads it. Held-out
// views: each object alone on the plain table at its centre, seen by the robot's camera, its yaw
// stepped through 360 degrees, classified by the learned Mixture of Topics and by argmax theta
// (same LDA model, topics merged by the learner's own labels).

#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "proprio/core/json_io.hpp"
#include "proprio/episode/episode.hpp"
#include "proprio/features/vocabulary.hpp"
#include "proprio/loop/self_supervision.hpp"
#include "proprio/recognition/confusion.hpp"
#include "proprio/sim/simulated_robot.hpp"
#include "proprio/topics/lda_model.hpp"
#include "proprio/topics/mixture_of_topics.hpp"

namespace proprio::loop {

/// One push as the ground truth saw it.
struct PushTruth {
  int round = 0;
  std::string phase;     ///< "clear" or "learn"
  std::string intended;  ///< the object under the pushed blob (most of its features), or ""
  /// The pushed blob's feature points by the object under them, "name:share+name:share" (share
  /// of the points on an object, largest first; points on no object left out), "" none: tells a
  /// blob of two touching objects from a neighbour's own blob (drift diagnosis, session 26).
  std::string blob_truth;
  std::vector<std::string> moved;  ///< objects whose centre moved > kMovedThreshold
  bool only_intended = false;      ///< the intended object moved and nothing else
  int fell_off = 0;                ///< objects that left the table in this push
  /// Objects standing before the push and lying after it (sim::ObjectTruth::upright), by name.
  std::vector<std::string> tipped;
  bool lying_before = false;  ///< the intended object lay on its side when the push began
  bool executed = false;
  int views = 0;           ///< learn pushes: training views taken
  std::string view_truth;  ///< learn pushes: the object under most of the learner's last mask
  /// How far the push turned the intended object: |its yaw after - before| wrapped to 0..180,
  /// degrees (0 when it is not known or left the table).
  double turn_deg = 0;
};

/// One training view as the ground truth saw it (the oracle ladder's (a) and (b)).
struct ViewTruth {
  int round = 0;
  std::filesystem::path episode;  ///< its push's episode, or empty (the look after the push)
  int frame = -1;                 ///< its frame in the episode (-1: the look)
  std::string intended;           ///< the object the push was aimed at (PushTruth::intended)
  /// The object under most of the learner's mask (arm and background left out), "" none or
  /// unknown (an episode without ground-truth masks).
  std::string object;
  double share_object = 0;      ///< fraction of the mask's pixels on `object`
  double share_arm = 0;         ///< on the arm
  double share_background = 0;  ///< on the table or the backdrop
  bool known = false;           ///< ground truth was available for it
  /// The intended object's pose on the table when the view was taken (after its push): world
  /// x y of its origin (m) and yaw (rad); posed false when it was not on the table (or none).
  bool posed = false;
  Eigen::Vector2d position = Eigen::Vector2d::Zero();
  double yaw = 0;
  bool upright = true;  ///< its z axis pointed up then (not toppled)
};

/// A round as the ground truth saw it.
struct RoundTruth {
  std::string chosen;  ///< the object under the chosen blob at (a)/(d), or ""
  /// The object under each blob of the look (a)/(d) chose from, in the look's blob order (the
  /// decision log's "choose" scores name these blobs), "" where none is.
  std::vector<std::string> blobs;
  bool singulated = false;   ///< after (b) its footprint is >= 10 cm from every other's
  double least_gap = -1;     ///< that least footprint gap, m (-1: chosen object not seen)
  std::vector<double> yaws;  ///< the chosen object's yaw before and after each learn push, rad
};

/// The person at the simulated table and the scorer (see the file comment).
class GroundTruthAttendant final : public TableAttendant {
 public:
  GroundTruthAttendant(sim::SimulatedRobot& robot, std::uint64_t seed);
  std::string rescatter(int round) override;
  void chose(int round, const planning::PlanningView& view, int blob) override;
  void before_push(const PushIntent& intent) override;
  void after_push(const PushIntent& intent, bool executed) override;
  void cleared(int round, const planning::PlanningView& view, int blob) override;
  void views_taken(const PushIntent& intent, int views, const cv::Mat& last_mask) override;
  void view_taken(const PushIntent& intent, const std::filesystem::path& episode, int frame,
                  const cv::Mat& mask) override;

  [[nodiscard]] const std::vector<RoundTruth>& rounds() const { return rounds_; }
  [[nodiscard]] const std::vector<PushTruth>& pushes() const { return pushes_; }
  /// Every training view, in the order of Learning::views (view_taken's calls).
  [[nodiscard]] const std::vector<ViewTruth>& views() const { return views_; }

 private:
  RoundTruth& round(int r);
  std::string object_under(const planning::PutativeObject& blob);
  /// The blob's points on each object (ground-truth id -> count; points on no object left out).
  std::map<int, int> votes_under(const planning::PutativeObject& blob);
  sim::SimulatedRobot& robot_;
  std::uint64_t seed_;
  std::vector<RoundTruth> rounds_;
  std::vector<PushTruth> pushes_;
  std::vector<ViewTruth> views_;
  std::optional<episode::Episode> episode_;  ///< the last episode view_taken read
  std::vector<sim::ObjectTruth> before_;
};

/// Least distance between two objects' footprints, m: centre distance less both footprint radii
/// (conservative: the footprint is the circle about the bounding box), at least 0.
double footprint_gap(const sim::ObjectTruth& a, const sim::ObjectTruth& b);

/// The arc of yaw (degrees, 0..360) covered by `yaws` (rad): 360 less the largest gap between
/// neighbouring yaws around the circle; 0 for fewer than 2.
double yaw_coverage_deg(std::vector<double> yaws);

/// The turn between two yaws (rad): |b - a| wrapped to 0..180, degrees.
double turn_deg(double a, double b);

/// A held-out figure by the pooled words classifier (SelfSupervisionOptions::pooled_score).
struct PooledFigure {
  double weight = 0;               ///< of the word multinomials (pool_word_multinomials)
  bool once = false;               ///< the multinomials count each push's views once
  double accuracy = 0;             ///< held-out views given their own object's class
  std::vector<double> per_object;  ///< the same per held-out object

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.weight, {"weight", "Weight of the word multinomials"});
    v(self.once, {"once", "Each push's views counted once in the multinomials"});
    v(self.accuracy, {"accuracy", "Held-out views given their own object's class"});
    v(self.per_object, {"per_object", "The same per held-out object"});
  }
};

/// The weights SelfSupervisionOptions::pooled_score scores at.
inline constexpr std::array<double, 5> kPooledWeights{0.0, 0.25, 0.5, 0.75, 1.0};

/// Each class's log multinomial over the words, as topics::fit_word_multinomials (add-one),
/// but each document's counts scaled by its weight (`weights` empty: 1 each, the same as
/// fit_word_multinomials). counts_once() gives the weights that count each push once. Throws
/// Error when labels or weights differ from the documents in number, a label is >= classes, or a
/// weight is negative or not finite.
Eigen::MatrixXd weighted_word_multinomials(const topics::Corpus& corpus,
                                           std::span<const int> labels, int classes,
                                           std::span<const double> weights = {});

/// Weights for weighted_word_multinomials that make every view weigh alike (Experiment 8.2's
/// ClutterExperimentOptions::mot_word_per_view, learn's LearnOptions::mot_word_per_view): each
/// labelled document (label >= 0) with words is weighed by the mean number of words of those
/// documents over its own, so that each adds as many words as the mean view; an empty or
/// unlabelled one weighs 0. Throws Error when labels and documents differ in number.
std::vector<double> per_view_weights(const topics::Corpus& corpus, std::span<const int> labels);

/// The documents' words from `first` on, renumbered from 0 (their colour words, numbered after
/// the vocabulary's by features::with_colour_words: `first` = the vocabulary's size): a corpus
/// over those words alone, one document for each. Throws Error when `first` is not in
/// [0, corpus.num_words()).
topics::Corpus words_from(const topics::Corpus& corpus, int first);

/// Each class's log multinomial over the colour words alone (the documents' words from
/// `colour_from` on, words_from), every view weighing alike (per_view_weights), add-one: with
/// topics::pool_word_multinomials at weight 1 over words_from(held, colour_from), the colour
/// classifier (naive Bayes by colour; LearnWordScore::colour, session 39 of
/// docs/results/learn.md). Throws Error as words_from and weighted_word_multinomials.
Eigen::MatrixXd colour_multinomials(const topics::Corpus& training, std::span<const int> labels,
                                    int classes, int colour_from);

/// The colour classifier on `held` (documents of the vocabulary's words, then the colour words
/// from `colour_from` on): naive Bayes on each document's colour words (words_from) under
/// `log_colour` (colour_multinomials, one row a class of `model`) with the model's prior p(c):
/// topics::pool_word_multinomials at weight 1, whose MoT term then weighs nothing (so it is not
/// computed); the same classes as learn's LearnWordScore::colour. A document without colour words
/// gets the prior's class. Throws Error as words_from, and when log_colour's size is not the
/// model's classes x the colour words.
topics::MotClassification classify_by_colour(const topics::MotModel& model,
                                             const Eigen::MatrixXd& log_colour,
                                             const topics::Corpus& held, int colour_from);

/// 1 / (views of its group) for each view, its group the pair (labels[i], push[i]): every push's
/// views weigh 1 together. Throws Error when labels and push differ in number.
std::vector<double> counts_once(std::span<const int> labels, std::span<const int> push);

/// The object the executed learn pushes (phase "learn") of the rounds `in_round` accepts were
/// aimed at most (PushTruth::intended), "" when there is none. Among ties, the one those rounds'
/// training views show most (PushTruth::view_truth weighed by PushTruth::views: what the class
/// learned), then the first by name. Names each learned class (SelfSupervisionScore::
/// class_object) and round (round_object); scoring only, the robot never sees it.
std::string pushed_most(std::span<const PushTruth> pushes,
                        const std::function<bool(int round)>& in_round);

/// Per object: what the learner made of it.
struct ObjectScore {
  std::string name;
  std::vector<int> classes;    ///< learned classes named after it
  int views = 0;               ///< training views of those classes
  double purity = 0;           ///< of them, the fraction showing this object
  double yaw_range_deg = 0;    ///< yaw range seen in training
  int held_out = 0;            ///< held-out views with features
  double mot_accuracy = 0;     ///< of them, right by the Mixture of Topics
  double argmax_accuracy = 0;  ///< right by argmax theta (merged topics)
  /// SelfSupervisionOptions::colour_words: right by the colour words alone (classify_by_colour).
  std::optional<double> colour_accuracy;
  int learn_pushes = 0;  ///< executed learn pushes (7.2 c) aimed at it
  int chosen = 0;        ///< rounds whose (a)/(d) chose it
  /// Mean turn of it per executed learn push aimed at it (PushTruth::turn_deg), degrees.
  double turn_deg = 0;
  /// Executed pushes aimed at it (both phases), and of them those it stood before and lay after
  /// (PushTruth::tipped); learn pushes aimed at it that began with it lying (tipped earlier).
  int pushes = 0;
  int tipped = 0;
  int learn_lying = 0;
  /// Executed pushes aimed at another object during which it tipped over.
  int tipped_by_others = 0;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.name, {"name", "The object"});
    v(self.classes, {"classes", "Learned classes named after it"});
    v(self.views, {"views", "Training views of those classes"});
    v(self.purity, {"purity", "Of them, the fraction showing this object"});
    v(self.yaw_range_deg, {"yaw_range_deg", "Yaw range seen in training, degrees"});
    v(self.held_out, {"held_out", "Held-out views with features"});
    v(self.mot_accuracy, {"mot_accuracy", "Of them, right by the Mixture of Topics"});
    v(self.argmax_accuracy, {"argmax_accuracy", "Right by argmax theta"});
    v(self.colour_accuracy, {"colour_accuracy", "Right by the colour words alone"});
    v(self.learn_pushes, {"learn_pushes", "Executed learn pushes aimed at it"});
    v(self.chosen, {"chosen", "Rounds that chose it"});
    v(self.turn_deg, {"turn_deg", "Mean turn per learn push aimed at it, degrees"});
    v(self.pushes, {"pushes", "Executed pushes aimed at it (both phases)"});
    v(self.tipped, {"tipped", "Of them, those it stood before and lay after"});
    v(self.learn_lying, {"learn_lying", "Learn pushes aimed at it that began with it lying"});
    v(self.tipped_by_others,
      {"tipped_by_others", "Pushes aimed at another object during which it tipped over"});
  }
};

/// A held-out confusion matrix as the loop's records write it: true objects x the robot's learned
/// classes. Its "accuracy" is `accuracy`, the share of held-out views given a class learned from
/// their own object (what the printouts give), not the diagonal's: the columns are the robot's
/// classes in no row's order, so the diagonal means nothing there; "mean_class_accuracy" (also
/// the diagonal's) is left out for the same reason.
[[nodiscard]] core::Json held_out_confusion_json(const recognition::ConfusionMatrix& m,
                                                 double accuracy);

/// One rung of the oracle ladder: a supervised Mixture of Topics (ground-truth object names as
/// classes, every object with >= 2 views) trained on some views, scored on the held-out views.
struct LadderRung {
  std::string name;  ///< a0, a0_table, a, a_last, a_alone, b, b_pure, c_named, c, *_own
  std::string what;  ///< what it was trained on
  int training_views = 0;
  int classes = 0;                 ///< objects with a class
  double accuracy = 0;             ///< held-out views given their own object's class
  std::vector<double> per_object;  ///< the same per held-out object (SelfSupervisionScore order)
  double label_purity = -1;        ///< b, c: views whose label is the object mostly in view
  /// SelfSupervisionOptions::pooled_score: the same by the pooled words classifier.
  std::optional<std::vector<PooledFigure>> pooled;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.name, {"name", "The rung"});
    v(self.what, {"what", "What its Mixture of Topics was trained on"});
    v(self.training_views, {"training_views", "Its training views"});
    v(self.classes, {"classes", "Objects with a class (>= 2 views)"});
    v(self.accuracy, {"accuracy", "Held-out views given their own object's class"});
    v(self.per_object, {"per_object", "The same per held-out object"});
    v(self.label_purity, {"label_purity", "Views labelled with the object mostly in view (-1)"});
    v(self.pooled, {"pooled", "The same by the pooled words classifier"});
  }
};

/// The oracle ladder (docs/results/selfsupervision-history.md): how much of the held-out accuracy
/// each step from ideal training views to the robot's own costs, on the same run.
struct OracleLadder {
  std::vector<LadderRung> rungs;
  /// The robot's views (b): mean fractions of their masks on the object mostly in view, on the
  /// arm, on the background, on other objects.
  double share_object = 0;
  double share_arm = 0;
  double share_background = 0;
  double share_other = 0;
  /// SelfSupervisionOptions::ladder_probes: statistics of each push's last frame against the
  /// render of the same pose ("object.key" or "all.key", the mean over the pushes; keys: iou of
  /// the two masks, grey_diff_object / grey_diff_table_band (0-255, mean absolute grey difference
  /// on the object and on the table round it), frame_feat_touch_arm / _other / _table (fraction
  /// of the frame's features whose patch window reaches the arm, another object, the table),
  /// same_word_clean / same_word_arm_or_other (fraction of grid points where the frame's word is
  /// the render's, for windows on the object and table only / reaching the arm or another object),
  /// toppled (the object's z axis no longer up when the view was taken: the render is upright).
  std::vector<std::string> probe_names;
  std::vector<double> probe_values;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.rungs, {"rungs", "a0, a0_table, a, a_last, a_alone, b, b_pure, c_named, c"});
    v(self.share_object, {"share_object", "Robot's view masks: fraction on the object in view"});
    v(self.share_arm, {"share_arm", "Fraction on the arm"});
    v(self.share_background, {"share_background", "Fraction on the background"});
    v(self.share_other, {"share_other", "Fraction on other objects"});
    v(self.probe_names, {"probe_names", "ladder_probes: the statistics' names"});
    v(self.probe_values, {"probe_values", "ladder_probes: their means over the pushes"});
  }
};

// NOLINTNEXTLINE(bugprone-exception-escape)
struct SelfSupervisionScore {
  std::vector<std::string> class_object;  ///< each class named after the object pushed most
  /// Per round: the object its learn pushes pushed most ("" none; one a class unless
  /// SelfSupervisionOptions::rounds merges rounds).
  std::vector<std::string> round_object;
  std::vector<double> class_purity;  ///< fraction of its views showing that object
  /// The object under the blob the learner chose for each class at (a)/(d) ("" unknown), and
  /// each round's least footprint gap after (b), m (-1: the chosen object was lost). With
  /// SelfSupervisionOptions::rounds: of each class's first round.
  std::vector<std::string> class_chosen;
  std::vector<double> class_gap;
  /// Each class's (first round's) look at (a)/(d): the object under each of its blobs
  /// (RoundTruth::blobs).
  std::vector<std::vector<std::string>> class_blobs;
  /// Per class (its rounds'), each executed learn push as the ground truth saw it:
  /// "intended>moved+moved" (the object under the pushed blob, then every object that moved; "" for
  /// none).
  std::vector<std::vector<std::string>> class_learn_pushes;
  /// Per class, each executed learn push's blob as the ground truth saw it (PushTruth::blob_truth).
  std::vector<std::vector<std::string>> class_learn_blobs;
  std::vector<ObjectScore> objects;
  double singulation = 0;               ///< rounds singulated / rounds
  double pushes_per_cleared = 0;        ///< clear pushes / distinct objects they moved (per round)
  double only_intended = 0;             ///< executed pushes that moved the intended object alone
  int off_table = 0;                    ///< objects that fell off the table
  double purity = 0;                    ///< all training views
  recognition::ConfusionMatrix mot;     ///< held out: true objects x learned classes (named)
  recognition::ConfusionMatrix argmax;  ///< the same by argmax theta
  double mot_accuracy = 0;              ///< held-out views classified as their object
  double argmax_accuracy = 0;
  /// SelfSupervisionOptions::colour_words: the held-out figure (c) by the colour words alone
  /// (classify_by_colour, MotClassifier::kColour), on the same views and classes as
  /// mot_accuracy (a paired comparison); with mot_classifier colour the two are equal. Absent
  /// when the learning kept no view words (Learning::views.words: learn's scoring, which has
  /// its own, LearnWordScore::colour); 0 when nothing was learned.
  std::optional<double> colour_accuracy;
  /// SelfSupervisionOptions::pooled_score: the held-out figure (c) by the pooled words
  /// classifier at each of kPooledWeights, then at mot_word_weight with pushes counted once.
  std::optional<std::vector<PooledFigure>> pooled;
  std::optional<OracleLadder> ladder;  ///< SelfSupervisionOptions::oracle_ladder

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.class_object, {"class_object", "Each class named after the object pushed most"});
    v(self.round_object, {"round_object", "Per round: the object its learn pushes pushed most"});
    v(self.class_purity, {"class_purity", "Fraction of its views showing that object"});
    v(self.class_chosen, {"class_chosen", "The object under the blob chosen for each class"});
    v(self.class_gap, {"class_gap", "Each round's least footprint gap after (b), m (-1: lost)"});
    v(self.class_blobs, {"class_blobs", "Each round's choice look: the object under each blob"});
    v(self.class_learn_pushes,
      {"class_learn_pushes", "Each class's learn pushes (of its rounds): intended>what moved"});
    v(self.class_learn_blobs,
      {"class_learn_blobs", "Each round's learn pushes: the pushed blob's points by object"});
    v(self.singulation, {"singulation", "Rounds singulated / rounds"});
    v(self.pushes_per_cleared, {"pushes_per_cleared", "Clear pushes / objects they moved"});
    v(self.only_intended,
      {"only_intended", "Executed pushes that moved the intended object alone"});
    v(self.off_table, {"off_table", "Objects that fell off the table"});
    v(self.purity, {"purity", "Purity of all training views"});
    v(self.mot_accuracy, {"mot_accuracy", "Held-out views classified as their object"});
    v(self.argmax_accuracy, {"argmax_accuracy", "The same by argmax theta"});
    v(self.colour_accuracy, {"colour_accuracy", "The same by the colour words alone"});
    v(held_out_confusion_json(self.mot, self.mot_accuracy),
      {"mot_confusion", "Held out: true objects x learned classes"});
    v(held_out_confusion_json(self.argmax, self.argmax_accuracy),
      {"argmax_confusion", "The same by argmax theta"});
    v(self.objects, {"objects", "Per object"});
    v(self.pooled, {"pooled", "Held-out figure by the pooled words classifier"});
    v(self.ladder, {"oracle_ladder", "Held-out accuracy by training views (ground truth)"});
  }
};

/// One held-out view (thesis 7.3.2's test set, shared by selfsupervise, learn and experiment
/// clutter): `name`, the only object of `alone`'s table (ground-truth id `id`), placed at the
/// scatter region's middle (table frame (0.27, 0) m) with yaw 2 pi v / count rad, seen by the
/// robot's camera. Returns the image and the object's ground-truth mask (CV_8U, 255 on it).
struct HeldOutView {
  cv::Mat image;
  cv::Mat mask;
};
HeldOutView render_held_out_view(sim::SimulatedRobot& alone, const std::string& name, int id, int v,
                                 int count);

/// Scores the learning from the attendant's records (its robot is not used: it may be gone),
/// renders `held_out` views of each object of
/// `objects` (alone at the table's centre, yaw stepped through 360 degrees, width x height) and
/// classifies them (one simulated table at a time: no other SimulatedRobot may exist). `options`
/// gives the features, dilation and min_features.
SelfSupervisionScore score_self_supervision(const Learning& learning,
                                            const GroundTruthAttendant& attendant,
                                            const std::vector<std::string>& objects,
                                            const topics::LdaModel& model,
                                            const features::Vocabulary& vocabulary,
                                            const SelfSupervisionOptions& options);

}  // namespace proprio::loop
