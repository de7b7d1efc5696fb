#pragma once
// `proprio learn` (thesis Ch 8, issue 21): look, plan, move. The robot learns the objects of a
// cluttered table by itself without clearing it: it looks, picks a putative object (the
// candidates standing out of the table in its RGB-D camera's depth image, LearnCandidates::kDepth,
// the default; feature-density blobs with --candidates blobs; the first at random), pushes it
// (planning/push_planner.hpp), segments the push bottom-up by the arm's motion (the dense
// Motion-Likelihood segmentation of segmentation/ml_segmentation.hpp, the default: its views were
// purer on the seeds measured, docs/results/learn-history.md; --segmentation sparse: SIFT matched
// at keyframes, mean shift on velocities, motion models' likelihood against the arm's motion,
// thresholded), takes the segmented frames as views, updates the object's words and their
// Dirichlet (loop/object_words.hpp), recognises the object again top-down in the next look and
// plans its next push from the recognised region. After `pushes` pushes it moves to the candidate
// least likely under the object models so far (7.2 d), until C objects are learned. Then a
// vocabulary (k-means over the descriptors of all its views) and an LDA model (over their
// documents: SIFT words and, by default, a colour word a feature, LearnOptions::colour_words) are
// built from the robot's own views, unless given, and the views feed a supervised Mixture of
// Topics whose labels are the robot's own classes object_1..object_C.
//
// The learner talks to robot::Robot only; a TableAttendant (in simulation the
// GroundTruthAttendant of loop/self_supervision_scoring.hpp) is told what it does, for scoring.
// Every decision and recovery (object lost, push not planned or refused, push moved nothing,
// recognition found nothing) is a line of DIR/decisions.jsonl. The run directory (the layout the
// report, loop/learn_report.hpp, reads): learn.json (format "proprio.learn"), decisions.jsonl,
// pushes/push_NNN/{before,after,map,mask,frame}.png and episode/, table.png, vocabulary.vocab,
// lda.model, model.mot; DIR/INCOMPLETE while it runs (removed as the last step).
//
// Frames: table points world x y (m, robot base frame); pixels as planning::PlanningView.

#include <filesystem>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "proprio/core/fields.hpp"
#include "proprio/core/json_io.hpp"
#include "proprio/core/provenance.hpp"
#include "proprio/features/colour_words.hpp"
#include "proprio/features/extraction.hpp"
#include "proprio/loop/object_words.hpp"
#include "proprio/loop/record_fields.hpp"
#include "proprio/loop/self_supervision.hpp"
#include "proprio/loop/self_supervision_scoring.hpp"
#include "proprio/planning/push_planner.hpp"
#include "proprio/robot/robot_interface.hpp"
#include "proprio/segmentation/ml_segmentation.hpp"
#include "proprio/topics/mixture_of_topics.hpp"

namespace proprio::loop {

inline constexpr const char* kLearnFormat = "proprio.learn";

/// Bottom-up segmentation of a push.
enum class PushSegmentation {
  kSparse,  ///< SIFT at keyframes, mean shift on velocities (Algorithm 3, 8.1.1)
  kDense    ///< the dense Motion-Likelihood segmentation (Ch 4)
};
inline constexpr core::ChoiceNames<PushSegmentation, 2> kPushSegmentationNames{
    {{"sparse", PushSegmentation::kSparse}, {"dense", PushSegmentation::kDense}}};

/// Where a push's training views come from (LearnOptions::views).
enum class LearnViews {
  /// Every view_step-th frame of the push's episode from the touch, cut out by its motion
  /// segmentation (8.1.1).
  kMotion,
  /// One view a push: the look after it (the arm parked), cut out by the blob where the learner
  /// believes its object now lies; the push's motion views when it has no blob there.
  kAfter,
  /// One view a push: the look before it, cut out by the blob the push was planned on (the
  /// object the robot chose to push, tracked from push to push by its motion segmentation).
  kBefore,
  /// kMotion's views and kBefore's view of each push that gave motion views, the latter entered
  /// once a motion view of its push (as a weight: it counts as much as all of them).
  kBoth
};
inline constexpr core::ChoiceNames<LearnViews, 4> kLearnViewsNames{{{"motion", LearnViews::kMotion},
                                                                    {"after", LearnViews::kAfter},
                                                                    {"before", LearnViews::kBefore},
                                                                    {"both", LearnViews::kBoth}}};

/// How 7.2 (d) tells a new object from the known ones, among the blobs no cue marks as known.
enum class NewObjectScore {
  kWords,  ///< the blob least likely under the known objects' word Dirichlets (mean log p)
  kMatch,  ///< the blob with the fewest descriptors matched to a known object's views (NN ratio)
  /// the blob whose features' colour words (LearnOptions::colour) are least likely under the
  /// known classes' colour multinomials (their views' colour words, add-one smoothed; mean log p)
  kColour,
  /// the blob whose pixels' colours are farthest from every known class's: the colour word of
  /// every pixel of the blob (features::colour_word_counts) against each class's pooled from the
  /// pushed blob in the look before each of its pushes (the views before, 96.6 % pure in session
  /// 40, not the motion views, a third of which show another object); Hellinger distance to the
  /// nearest class. Needs views before or both.
  kPixels
};
inline constexpr core::ChoiceNames<NewObjectScore, 4> kNewObjectScoreNames{
    {{"words", NewObjectScore::kWords},
     {"match", NewObjectScore::kMatch},
     {"colour", NewObjectScore::kColour},
     {"pixels", NewObjectScore::kPixels}}};

/// Learn's headline held-out figure (LearnOptions::headline): the classifier printed first, shown
/// first in report.html and given as learn.json's "headline".
enum class LearnHeadline {
  kMot,     ///< the Mixture of Topics by theta (eq 7.3; ground_truth.mot_accuracy)
  kArgmax,  ///< argmax theta (merged topics; ground_truth.argmax_accuracy)
  kPooled,  ///< the MoT by words pooled with the word multinomials (held_out_words; the
            ///< multinomials of LearnOptions::mot_word_per_view)
  kColour,  ///< the colour words alone (held_out_words' colour; needs colour words)
  kAuto     ///< colour with colour words, else pooled (LearnOptions::resolved() picks)
};
inline constexpr core::ChoiceNames<LearnHeadline, 5> kLearnHeadlineNames{
    {{"mot", LearnHeadline::kMot},
     {"argmax", LearnHeadline::kArgmax},
     {"pooled", LearnHeadline::kPooled},
     {"colour", LearnHeadline::kColour},
     {"auto", LearnHeadline::kAuto}}};

/// Where the putative objects offered to 7.2 (d) come from.
enum class LearnCandidates {
  kBlobs,  ///< feature-density blobs, split by the known objects' segmented regions (as before)
  kDepth   ///< objects standing out of the table in the depth image (depth_candidates; RGB-D)
};
inline constexpr core::ChoiceNames<LearnCandidates, 2> kLearnCandidatesNames{
    {{"blobs", LearnCandidates::kBlobs}, {"depth", LearnCandidates::kDepth}}};

/// The objects a depth image shows on the table: pixels whose back-projected point
/// (X = R^T (depth K^-1 (u, v, 1)^T - t), base frame, table top z = 0) lies at least
/// `min_height` m above the table, split where the depth jumps by more than `max_step` m
/// between 4-neighbours (an object in front of another: its edge pixels are left out), in
/// 8-connected components of at least `min_pixels` px, largest first. Each is an 8-bit mask of
/// the image's size (255 inside). `ignore` (8-bit of the image's size or empty): pixels that are
/// no object (the arm). Depth 0 or not finite: no measurement. Throws Error unless `depth` is
/// CV_32FC1 of the camera's image size, min_height > 0, max_step > 0 and min_pixels >= 1.
std::vector<cv::Mat> depth_candidates(const cv::Mat& depth, const geometry::Camera& camera,
                                      double min_height, double max_step, int min_pixels,
                                      const cv::Mat& ignore = {});

/// moving_wait: a pixel whose depth changed by more than this between the two looks moved, m
/// (1 cm: the simulated depth is exact; a real RGB-D camera's noise at 1 m is a few mm).
inline constexpr double kMovingDepth = 0.01;
/// moving_wait: a candidate with at least this fraction of its measured pixels moved moves by
/// itself: it is mostly a moving thing. On the tuning seeds (session 37, 0.3 and 0.5 s) the
/// distractors' candidates moved 0.70-1.00 of their pixels, objects at rest 0.00, and table
/// objects pushed to the back, into the distractors' path (a ghost distractor passing through
/// them), 0.08-0.66: 0.2 left out 2 of those 4, 0.5 leaves out 1 (the 0.66).
inline constexpr double kMovingFraction = 0.5;

/// moving_wait's test: per mask (8-bit, the depth images' size, nonzero inside), the fraction of
/// its pixels measured in `before` (depth > 0 and finite) whose depth in `after` is unmeasured or
/// differs by more than `change` m; 0 for a mask with no measured pixel. Depth images as
/// robot::Look::depth (CV_32FC1, m). Throws Error unless both depth images are CV_32FC1 of one
/// size, every mask 8-bit of that size and `change` > 0 and finite.
std::vector<double> moved_fractions(const cv::Mat& before, const cv::Mat& after,
                                    const std::vector<cv::Mat>& masks,
                                    double change = kMovingDepth);

/// Which candidate each known object is: per known object r, the candidate (8-bit masks of one
/// size) lying most inside its `regions[r]` (where the robot left it: its last push's segmented
/// region; empty = unknown): the fraction of the candidate's pixels inside the region, to a
/// tenth; among equal fractions the candidate nearest `ends[r]` (the pixel where the robot's
/// pusher ended, when given: the object lies just ahead of it), then the larger overlap. One
/// candidate per known object (the best pairs are taken first; a candidate taken by one object
/// is not another's). -1 when it overlaps none left. Throws Error unless every non-empty mask is
/// 8-bit of one size and `ends` is empty or has one entry per region.
std::vector<int> known_candidates(const std::vector<cv::Mat>& regions,
                                  const std::vector<cv::Mat>& candidates,
                                  const std::vector<std::optional<cv::Point2d>>& ends = {});

/// The points a depth image shows above the table: every `step`-th pixel (in x and y) whose
/// back-projected point (as depth_candidates) stands at least `min_height` m above the table, in
/// the base frame (x, y, height), m. `ignore` (8-bit of the image's size or empty): pixels that
/// are no object (the arm). Throws Error unless `depth` is CV_32FC1 of the camera's image size,
/// min_height >= 0 and step >= 1.
std::vector<Eigen::Vector3d> depth_points(const cv::Mat& depth, const geometry::Camera& camera,
                                          double min_height, int step = 1,
                                          const cv::Mat& ignore = {});

/// The hand coming straight down to a push's start, as seen from above: the pusher's tip
/// (pushing at `pusher_height`) and, higher up, the fingers and the palm around it.
struct HandClearance {
  double pusher = 0.02;          ///< a point within this of the start (table x y) meets the pusher
  double pusher_height = 0.008;  ///< ... when it stands higher than this (the tip's height), m
  double hand = 0.045;           ///< within this (m) a point meets the fingers or the palm
  double hand_height = 0.035;    ///< ... when it stands higher than this (the fingers' bottom), m
};

/// How many of `points` (depth_points: x, y, height, m) the hand would meet coming straight down
/// to the push start `start` (table x y, m): those within `clearance.pusher` of it and higher
/// than `clearance.pusher_height`, or within `clearance.hand` and higher than
/// `clearance.hand_height`. 0: the way down is clear of everything the camera sees. Throws Error
/// unless the clearance's distances and heights are >= 0 and finite.
int hand_meets(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector2d& start,
               const HandClearance& clearance);

/// The fraction of `query`'s descriptors (rows, CV_32F) whose nearest neighbour among `known`
/// lies closer than `ratio` times their nearest neighbour among `rest` (the look's other
/// features: the alternative that the descriptor is not the known object's). With `rest` empty
/// every descriptor that has a neighbour in `known` matches. 0 when `query` or `known` is empty.
/// Throws Error unless the non-empty matrices are CV_32F with one column count and
/// 0 < ratio <= 1.
double descriptor_match_fraction(const cv::Mat& query, const cv::Mat& known, const cv::Mat& rest,
                                 double ratio);

/// What became of a known object's region that another object's push moved over.
enum class RegionFate {
  kStayed,   ///< its features are still where the region was
  kCarried,  ///< its features are where the push's motion carried the region
  kLost      ///< neither: its appearance changed unexplained (the region is forgotten)
};

/// Where a known object's `region` (8-bit mask) lies after a push whose motion moved `shift`
/// (px, the pusher from the touch to the push's end) passed over it: the region where it was
/// and the region moved by `shift` are each scored by descriptor_match_fraction of the look's
/// features inside it (`points`, rows of `descriptors`, CV_32F) against the object's views'
/// descriptors (`pool`), the look's other features being the alternative. The better of the
/// two with at least `min_matched` is the object's (`out`: that region; empty when kLost).
/// Throws Error unless `points` and `descriptors` have one row each and the region is 8-bit.
RegionFate carry_region(const cv::Mat& region, const cv::Point2d& shift,
                        const std::vector<cv::Point2f>& points, const cv::Mat& descriptors,
                        const cv::Mat& pool, double ratio, double min_matched, cv::Mat& out);

/// The features of proprio learn's views, looks and vocabulary: dense SIFT every 4 px.
inline features::ExtractOptions learn_features() {
  features::ExtractOptions f;
  f.dense.step = 4;
  return f;
}

struct LearnOptions {
  /// Objects to learn, catalogue names, comma-separated (the learner is told only how many).
  std::string objects = "book,bottle,cd,giraffe";
  /// More catalogue objects on the table (clutter): never scored; learned as classes of their
  /// own with learn_clutter (the robot cannot tell them from the named objects).
  std::string clutter = "mug,rabbit,calculator";
  /// The simulated world's backdrop (the learner never knows it): "plain", "photo" or "moving"
  /// (a video of people walking, advancing with the robot's clock, with distractors sliding
  /// about behind the work area; sim::TableOptions::background).
  std::string background = "moving";
  /// Moving distractors behind the work area: -1 = 2 with the moving backdrop, else 0.
  int distractors = -1;
  std::uint64_t seed = 1;  ///< the table, the choices, the paths
  /// The robot is told how many objects lie on the table, not which to learn: it learns every
  /// one (objects and clutter, one class each) and the named objects' held-out views score it.
  /// Off: it learns as many as `objects` names, whichever it picks.
  bool learn_clutter = true;
  /// Pushes of each object before moving on (7 objects x 6 keeps `make demo` inside 10 min).
  int pushes = 6;
  /// A blob whose mean log p under a known object's words is at least that object's own views'
  /// (its last push) less this many nats is that object (7.2 d leaves it out: no second class
  /// of one object). -1: off (only where the object was segmented, recognised or left counts).
  double known_margin = -1;
  /// Turns (an object chosen and pushed) at most: 0 = one a class (C turns). More: a turn that
  /// gave its class no views leaves the class for the next turn (the blob it tried is not chosen
  /// again), and the run goes on until every class has views or the turns are spent.
  int rounds = 0;
  /// 7.2 (d): "words" (the blob least likely under the object words so far), "match" (the blob
  /// whose descriptors match a known object's views least: descriptor_match_fraction) or
  /// "colour" (the blob whose colour words are least likely under the classes' colour
  /// multinomials: an object's colours do not change when it turns or falls over, its SIFT
  /// words do; not with known_margin, which compares word likelihoods) or "pixels" (the blob
  /// whose pixels' colours are farthest from every class's looks before its pushes; not with
  /// known_margin; needs views before or both).
  NewObjectScore new_object = NewObjectScore::kWords;
  /// "match": a descriptor is a known object's when its nearest neighbour in that object's views
  /// is closer than this times its nearest among the look's other features.
  double match_ratio = 0.8;
  /// "match": a blob with at least this fraction of its descriptors matched to one known
  /// object's views is that object (7.2 d leaves it out: no second class of one object).
  /// 1 = off (only where the object was segmented, recognised or left counts).
  double match_known = 1.0;
  /// After a push, another known object's region that the push's motion overlapped is looked
  /// for (carry_region: where it was, or moved with the push, by its descriptors) instead of
  /// forgotten; a carried region is cut out of the pushed object's. Off: forgotten (as before).
  bool carry_regions = false;
  /// The putative objects offered to (d): "depth" (depth_candidates of the look; turns on the
  /// RGB-D camera, `depth`): a known object is the candidate lying most inside its last push's
  /// region (known_candidates), one each; or "blobs" (feature-density blobs split by the known
  /// objects' regions: a camera without depth; the default before session 21). Depth by
  /// default: every named object pushed more often, held out higher on report seeds 2-7
  /// (docs/results/learn-history.md, "Session 21").
  LearnCandidates candidates = LearnCandidates::kDepth;
  /// "depth": a candidate's pixels stand at least this high above the table, m (the cd is 5 mm).
  double candidate_height = 0.003;
  /// "depth": candidates are split where the depth jumps more than this between pixels, m.
  double candidate_step = 0.01;
  /// "depth": the planner's footprint of a candidate (its centre, hull and height) measured
  /// from the depth points of the whole candidate, not only inside its features' hull (a
  /// texture on part of an object gave a footprint too small: the hand came down on it). Off
  /// by default.
  bool candidate_footprint = false;
  /// With depth: a push whose start has a depth point higher than the fingers (HandClearance)
  /// within this many m, or one higher than the pusher's tip within 0.02 m, is not tried (another
  /// side is planned); 0: off (the default; the robot refuses such transits itself).
  double start_clearance = 0;
  /// Before choosing (7.2 d), a push is planned for the candidates in the order of choice; the
  /// first that can be pushed (planned, start clear) is chosen. Off: the best is chosen and
  /// others are tried only after three failures.
  bool prefer_pushable = false;
  /// Identity check after a turn's first push that gave views (session 26): the mean log p of
  /// those views' descriptors under each known object's words (eq 8.4) less that object's own
  /// yardstick (its last push's views' mean log p under its words, as known_margin), nats; when
  /// the best such difference is at least -identity_margin the pushed object is that known one:
  /// the views are merged into its class (its words and Dirichlet updated as by a later push, its
  /// region and place taken from the push), the turn's class is emptied and the turn chooses
  /// again (7.2 d: the merged object now known, its blob not chosen again), at most twice a
  /// turn. -1 (any negative): off (the check is still logged: decisions.jsonl's "identity" events).
  double identity_margin = -1;
  /// Hold on to the chosen object between a turn's pushes (session 26): after a push the object
  /// is the candidate nearest the push's planned landing point (the plan's target, within
  /// 0.05 m), before what moved with the arm (its segmented region, which also takes in
  /// neighbours that moved with it or lay beside it: 27 of the 67 later push attempts of the
  /// tuning seeds 1, 8-10 --quick were aimed at another object than the turn chose, 18 of them
  /// located by that region; docs/results/learn-history.md "Session 26"); the next push is aimed at
  /// the blob nearest where it was held. Off: the segmented region first (as before). Off by
  /// default: on report seeds 2-7 it halved the drift and gave more named objects a class, but
  /// held-out MoT fell 20.2 -> 8.5 % (docs/results/learn-history.md, "Session 26").
  bool hold_target = false;
  /// Keep pushed objects in reach (session 27): a push target (push_target) outside the area the
  /// arm can push an object again (within 0.36 m of the base axis, beyond 0.16 m, at least
  /// 0.12 m in front of the base, within 0.27 m of the view's centre line; robot base frame) is
  /// taken only when no direction keeps it inside, and when the planned push cannot be made the
  /// other sides' pushes (0.08 m each) that end inside the area are tried before those that
  /// end outside it. Off: the area only weighs against a target's gap to the other blobs (up
  /// to 0.15 m; targets up to 0.49 m from the base axis were taken) and the other sides are tried
  /// in turn whatever their end (with more pushes a turn, --pushes 5 --hold-target on the tuning
  /// seeds, 4 of 29 choices found nothing in reach to choose, against none at 3 pushes). Off by
  /// default: with --hold-target --pushes 5 on the tuning seeds 1, 8-10 (--quick) every turn
  /// found an object again (7 classes with views on every seed, against 5-7), but held-out MoT
  /// stayed below the defaults' (paired -8.8 +- 21.1 points; docs/results/learn-history.md,
  /// "Session 27").
  bool keep_in_reach = false;
  /// Hold a known object's segmented region to where its push meant to put it (session 34): a
  /// region (what moved with the arm in the object's last push, known_candidates) names only a
  /// candidate whose centre lies within this distance of that push's planned target, m; within
  /// a turn, when the region names none, the next push is aimed at the blob nearest that target
  /// (within this distance, "held"), and when no blob lies that near the target the object is
  /// lost: the turn ends (where it was left: the target), no push goes to whatever lies nearest
  /// (top-down recognition, the landing radius). The region otherwise names the
  /// candidate lying most inside it, which is often a neighbour that moved with the object or lay
  /// beside it: over 16 learn runs 96 of the 131 pushes aimed at another object than the turn
  /// chose were located so, and an earlier turn's region lying on an object never pushed was the
  /// tuning seeds' largest cause of skipped candidates (docs/results/learn.md, "Session 33").
  /// 0: off (the default until session 39: on 20 fresh seeds in session 36, before colour
  /// words, 0.08 changed the held-out headline by -0.9 +- 8.5 points at --quick and -6.5 +-
  /// 18.2 in the demo's mode, 10 seeds).
  /// 0.08 by default since session 39's third rule (with quick_pushes 6 and the colour
  /// headline, on fresh seeds 131-150: docs/results/learn.md "Session 39").
  double region_agree = 0.08;
  /// region_agree's lost object (session 34, second round): the turn does not end but chooses
  /// again among the look's blobs by the usual choice (7.2 d: the blob least like the objects
  /// learned before this turn; logged `rechoose`, "region_agree: lost ..."), and its remaining
  /// pushes go to the new choice (the class keeps the views it has). Needs region_agree > 0.
  /// Off by default (docs/results/learn.md, "Session 34, second round").
  bool lost_rechoose = false;
  /// Passes over the objects (session 35, second round). 1: each class has its turn once. N > 1:
  /// after every class's turn, passes 2..N go over the classes that have views, fewest views
  /// first (ties by class; the classes that need views most are pushed before the others'
  /// revisits move them), each turn starting from where its object was last left (with
  /// region_agree: the blob of its segmented region, else the blob within region_agree of its
  /// last push's target; else as locate() finds a known object: its region, top-down, tracked),
  /// pushing it up to `pushes` times more, views and word updates going to the same class (later
  /// pushes: the incremental mean). Not found, or found on another class's blob: logged
  /// (`revisit`, with where it looked and why) and skipped. 1: off (the default).
  int passes = 1;
  /// passes with region_agree: a revisit that finds no blob near its object's last push's
  /// target (nor its region) looks for it by top-down recognition (its words), as locate() does
  /// without region_agree (session 35, second round: 15 of T2's 28 revisits on the tuning seeds
  /// found nothing because the class's turn had ended lost). Needs region_agree > 0 and
  /// passes > 1. Off by default.
  bool revisit_top_down = false;
  /// Candidates that move by themselves (session 37): at each choice of a blob to learn (7.2 a
  /// and d: a turn's first, and a turn's choice again), the robot holds still this long
  /// (robot::Robot::hold_still), looks again, chooses on the new look's view and leaves out
  /// every candidate whose depth moved between the two looks (moved_fractions: at least
  /// kMovingFraction of its blob's pixels changed depth by more than kMovingDepth; revisits,
  /// which choose nothing, do not wait), logged with skip reason `moving` (learn.json
  /// `skipped`; the choose event's `skipped`, and a `moving` event giving each candidate's moved
  /// fraction). Why: in session 36's 150 runs 8.7 % of the turns chose a blob of a distractor
  /// sliding behind the table (a class spent on no object on the table); a person does not push
  /// a thing that moves by itself. Needs the depth image (candidates "depth", or `depth`).
  /// Seconds, 0..5; 0 = off (the default): no extra look, no extra step of the world. 0.3 left
  /// out every distractor candidate on the tuning seeds 1, 8, 9, 10 (docs/results/learn.md,
  /// "Session 37 (branch moving37)"); the report seeds decide the default.
  double moving_wait = 0;
  /// The documents of the robot's views and of the held-out views carry a colour word a
  /// feature after its SIFT word (features::colour_words on `colour`: the patch's mean colour on
  /// a fixed HSV grid, 28 words), so that the vocabulary, LDA, the Mixture of Topics and the
  /// pooled classifier see colour, which does not change when an object turns or falls over.
  /// A given --model must have the colour words (the vocabulary's words + 28). Not with
  /// --oracle-ladder (its rungs are SIFT only). On by session 38's rule
  /// (docs/results/learn/rule-s38-colour.md): on seeds 51-90 --quick, the same pushes as the
  /// defaults (the robot's choices do not read documents), the pooled headline rose 25.8 ->
  /// 44.2 % (paired +18.5 +- 4.9 points, higher on 35 of 40 seeds, lower on 4), the MoT 24.5 ->
  /// 34.7 % (+10.2 +- 5.3); --no-colour-words: SIFT words only, as the thesis
  /// (docs/results/learn.md "Session 38").
  bool colour_words = true;
  /// colour_words (without them it has no effect): in the documents of the topic model learn fits
  /// to its views each colour word counts this many times (topics::weighted_from), so that the
  /// topics follow the objects' colours, which do not change when an object turns or falls over,
  /// more than their SIFT words, which do. The model records the weights
  /// (topics::LdaModel::word_weights, lda-model format version 2) and weighs every document it
  /// reads alike: the views' theta, the Mixture of Topics, argmax theta, the held-out views'
  /// theta. A given --model weighs as it was made (its own word weights), not by this option. The
  /// loop never reads the topic model (the pushes are the same at any weight), nor does the colour
  /// words classifier (the headline); the words classifiers' documents count each colour word
  /// once. 1: as the thesis's words count. 128, the default since session 46
  /// (docs/results/learn/rule-s46-colour-weight.md; K chosen offline on tuning seeds 1-20): on
  /// fresh seeds 211-230 at --quick, the same pushes, the Mixture of Topics 35.9 -> 60.6 % (+24.7
  /// +- 7.6, higher on 19 of 20, lower on none), argmax theta 42.0 -> 55.4 %, the colour headline
  /// the same on every seed, LDA 0.09 -> 0.20 s of CPU a run.
  int colour_weight = 128;
  features::ColourWordOptions colour;  ///< colour_words: the grid (not a flag)
  /// The colour words of the documents (colour_words: `colour`), or none.
  [[nodiscard]] std::optional<features::ColourWordOptions> document_colour() const {
    return features::colour_if(colour_words, colour);
  }
  int topics = 10;  ///< LDA topics (when no --model is given)
  int words = 200;  ///< vocabulary words (when no --vocabulary is given)
  /// Small and fast: quick_pushes (6) pushes an object, 240 x 180 images, 100 words, 6 topics,
  /// each only where that option holds its default (resolved()): a value given equal to its
  /// default (e.g. `--quick --pushes 6`) cannot be told from one not given and becomes the quick
  /// one; `--quick --quick-pushes 3` gives 3 pushes an object.
  bool quick = false;
  /// Pushes of each object under `quick` where `pushes` holds its default (session 35: `--quick
  /// --pushes 6` gave 3 pushes, so 6 pushes a turn could not be measured at quick's size).
  /// 3 until session 39 (alone, 6 lost on 20 fresh seeds in session 36: -5.7 +- 7.2 points).
  /// 6 since session 39's third rule (with region_agree 0.08 and the colour headline).
  int quick_pushes = 6;
  /// Dense by default: its views were purer (docs/results/learn-history.md).
  PushSegmentation segmentation = PushSegmentation::kDense;
  /// Where a push's training views come from (LearnViews; kBoth by default since session 40).
  /// kBoth never gives a push fewer views than kMotion, so it makes the same pushes (checked on
  /// 60 seeds); kAfter and kBefore can leave a push without views, which can change a turn (kBefore
  /// made the same pushes on all 20 tuning seeds, kAfter did not). Why: on the tuning seeds (1-20
  /// --quick, session 40) 35 % of the motion views showed another object than their class's
  /// (ground truth), often because the arm hid the pushed object at the touch. kBefore's views
  /// alone were 97 % pure but too few (headline 70.8 -> 62.2 %), kAfter's 47.4 %; kBoth passed
  /// docs/results/learn/rule-s40-views-both-quick.md: fresh seeds 171-210 --quick, 62.1 -> 73.7 %
  /// (+11.6 +- 5.0, lower on 2 of 40); in the demo's mode (seeds 151-170) +2.2 +- 2.9, lower on
  /// none (docs/results/learn.md, "Session 40").
  LearnViews views = LearnViews::kBoth;
  DirichletUpdate dirichlet_update = DirichletUpdate::kExact;
  /// The push's mask: map >= this fraction of its maximum (the sweep of experiment 8.2).
  double mask_fraction = 0.5;
  int view_step = 3;  ///< views: every n-th frame from the first touch
  /// A push's mask (or a view's) that covers more than this share of the image is the scene, not
  /// one object (a map with no clear peak, camera-motion residue): the push gives no views (or
  /// the frame none). The objects fill 1-7 % of the image; on the tuning seeds (1-20 --quick,
  /// session 40) 16 of 283 pushes' masks covered more than 20 %, most of them 83-90 %. 1 (the
  /// default): off. At 0.2 the views' purity rose 64 -> 69 % but the colour headline did not
  /// (-2.0 +- 7.7 points on those seeds; docs/results/learn.md, "Session 40").
  double max_mask_share = 1.0;
  int min_features = 10;  ///< a view needs this many features
  int dilate = 4;         ///< masks grown by this many px
  double fps = 15;        ///< frame rate of the pushes' episodes
  int width = 320;        ///< image size of the camera, px
  int height = 240;
  int held_out = 20;  ///< held-out ground-truth views per object (scoring)
  /// Scoring: the held-out views are also classified by their words (topics::classify_mot_words:
  /// the Mixture of Topics' bound on log p(w | c)) pooled with each class's word multinomial
  /// fitted to the robot's own views (topics::fit_word_multinomials, pool_word_multinomials) at
  /// this weight (0: by words alone; 1: multinomial naive Bayes), beside the Mixture of Topics by
  /// theta and argmax theta (learn.json "held_out_words", the printout; docs/results/mot.md,
  /// session 22). 0.25 as chosen there.
  double mot_word_weight = 0.25;
  /// Scoring: learn's pooled classifier fits each class's word multinomial weighing every view
  /// alike (per_view_weights + weighted_word_multinomials, Experiment 8.2's mot_word_per_view,
  /// session 30 there) instead of pooling its views' counts (topics::fit_word_multinomials: a
  /// view with many features weighs more). Both are scored in every run (learn.json
  /// held_out_words: pooled/grid with the pooled counts, pooled_per_view/grid_per_view per view);
  /// this says which is learn's pooled classifier (the printout's and the headline's "pooled").
  /// false (the default): the pooled counts. Off by session 32's rule: on the report seeds 2-7
  /// --quick the per-view multinomials at weight 0.1 (chosen on the tuning seeds) scored 21.0 %
  /// against the pooled counts' 25.0 % at 0.25, lower on 4 of 6 seeds (at 0.25 both: 19.0
  /// against 25.0 %; docs/results/learn-history.md "Session 32").
  bool mot_word_per_view = false;
  /// Scoring: the held-out figure printed first, shown first in report.html and written as
  /// learn.json's "headline": "auto" (the default since session 39's third rule,
  /// docs/results/learn/rule-s39-p6-colour.md: resolved() makes it "colour" with colour words,
  /// else "pooled"), "colour" (the colour words alone: LearnWordScore::colour), "pooled" (the
  /// pooled words classifier at mot_word_weight, with the word multinomials of
  /// mot_word_per_view; the default of sessions 32-38, by session 32's rule: on the report seeds
  /// 2-7 --quick it scored 25.0 % against the MoT's 22.7 %), "mot" (the Mixture of Topics by
  /// theta, the headline before) or "argmax" (argmax theta). Every figure is in learn.json
  /// whichever it is.
  LearnHeadline headline = LearnHeadline::kAuto;
  /// Scoring: also the oracle ladder (SelfSupervisionOptions::oracle_ladder).
  bool oracle_ladder = false;
  /// Scoring, with oracle_ladder only: every rung (and c) is also scored by the pooled words
  /// classifier with per-view word multinomials at kPooledWeights
  /// (SelfSupervisionOptions::pooled_score; Experiment 8.2's default classifier), so that a
  /// rung such as (a), the true masks and labels of the push frames, compares with Experiment
  /// 8.2's figures, which are by that classifier (session 33). Off (the default): the rungs by
  /// theta only, as before.
  bool ladder_pooled = false;
  /// Also write the run's documents (documents.txt in the run directory): every training view's
  /// words with its class and what the ground truth says it shows, and every held-out view's
  /// words with its object, one document a line ("count word:count ...", as lda-c's format),
  /// so that other classifiers can be fitted to exactly the robot's own training set and
  /// judged on the same held-out views. The simulated table then also records its ground-truth
  /// masks (scoring only), so each view's line names the object under most of its mask. Off by
  /// default (about 1 MB a run, and the masks).
  bool write_documents = false;
  /// The robot's camera is an RGB-D one (sim::TableOptions::depth, robot::Look::depth): the
  /// planner measures each blob's footprint and height from depth, as `selfsupervise --depth`.
  /// Turned on by resolved() with candidates "depth" (the default): off only with "blobs".
  bool depth = false;
  std::filesystem::path vocabulary;  ///< given vocabulary (else built from the robot's views)
  std::filesystem::path lda_model;   ///< given LDA model (else trained on the robot's views)
  std::filesystem::path out;         ///< the run directory (required)
  bool overwrite = false;
  bool progress = true;  ///< progress on stderr (the CLI's --quiet turns it off)
  /// Dense SIFT every 4 px (as `proprio selfsupervise`'s experiments): twice the grid of the
  /// default gives an object of a 320 x 240 view four times the features.
  features::ExtractOptions features = learn_features();
  planning::PushPlanOptions plan;
  segmentation::SparseOptions sparse;
  /// The dense segmentation's options; --seg-touch-fm sets its touch_fm (the baseline's touch
  /// cut as evidence in monocular M-L, issue 20; MlOptions's default 1,
  /// docs/results/learn-history.md "Session 24").
  segmentation::MlOptions dense;
  ObjectWordOptions words_model;
  topics::MotOptions mot;

  /// The options with --quick applied (pushes, image size, words, topics made small).
  [[nodiscard]] LearnOptions resolved() const;
  /// Throws Error naming the first bad option: bounds, an empty or repeated name (objects and
  /// clutter together), an unknown background.
  void validate() const;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.objects, {"objects", "Objects to learn, catalogue names, comma-separated"});
    v(self.clutter, {"clutter", "More catalogue objects on the table (never scored); '' none"});
    v(self.background, {"background", "Backdrop: plain, photo or moving (people walking)"});
    v(self.distractors, {"distractors", "Moving distractors: -1 = 2 with a moving backdrop, else 0",
                         core::between(-1, 4)});
    v(self.seed, {"seed", "Seed of the table, the choices and the paths"});
    v(self.learn_clutter,
      {"learn_clutter", "Learn every object on the table (the clutter too), score the named"});
    v(self.pushes, {"pushes", "Pushes of each object", core::between(1, 1000)});
    v(self.known_margin, {"known_margin",
                          "A blob within this many nats of a known object's own mean log p is "
                          "that object, not chosen as new; -1 off",
                          core::between(-1.0, 1000.0)});
    v(self.rounds, {"rounds",
                    "Turns at most (0 = one a class); a turn that gave no views is retried "
                    "on another blob until every class has views",
                    core::between(0, 1000)});
    v.choice(self.new_object,
             {"new_object",
              "How (d) picks a new object: words (least likely), match (fewest descriptors "
              "matched to known objects' views), colour (colour words least likely) or pixels "
              "(pixel colours farthest from the classes' looks before their pushes)"},
             kNewObjectScoreNames);
    v(self.match_ratio, {"match_ratio",
                         "match: nearest in a known object's views closer than this times the "
                         "nearest among the look's other features",
                         core::between(0.05, 1.0)});
    v(self.match_known, {"match_known",
                         "match: a blob with this fraction of its descriptors matched to a "
                         "known object is that object, not chosen as new; 1 off",
                         core::between(0.0, 1.0)});
    v(self.carry_regions, {"carry_regions",
                           "Look for a known object's region that another push moved over "
                           "(where it was, or moved with the push) instead of forgetting it"});
    v.choice(self.candidates,
             {"candidates",
              "Putative objects offered to (d): blobs (feature density) or depth (objects "
              "standing out of the table in the depth image; an RGB-D camera)"},
             kLearnCandidatesNames);
    v(self.candidate_height,
      {"candidate_height", "depth candidates: least height above the table, m",
       core::between(0.001, 0.2)});
    v(self.candidate_step,
      {"candidate_step", "depth candidates: split where the depth jumps more than this, m",
       core::between(0.001, 0.5)});
    v(self.candidate_footprint,
      {"candidate_footprint",
       "depth candidates: the planner's footprint measured over the whole candidate"});
    v(self.start_clearance,
      {"start_clearance",
       "depth: skip push starts with a depth point above the fingers within this, m; 0 off",
       core::between(0.0, 0.2)});
    v(self.prefer_pushable,
      {"prefer_pushable", "Plan a push before choosing a candidate; choose the first pushable"});
    v(self.identity_margin,
      {"identity_margin",
       "After a turn's first push: views within this many nats of a known object's own mean "
       "log p are merged into it and the turn chooses again; -1 off",
       core::between(-1.0, 1000.0)});
    v(self.hold_target,
      {"hold_target",
       "After a push the object is the blob nearest the push's target (within 0.05 m) before "
       "its segmented region: the turn holds on to it"});
    v(self.keep_in_reach,
      {"keep_in_reach",
       "Push targets and side pushes that end outside the area the arm can push again are "
       "taken last"});
    v(self.region_agree,
      {"region_agree",
       "A known object's segmented region names only a candidate within this of its last "
       "push's target (else the blob nearest that target; none: the turn ends), m; 0 off",
       core::between(0.0, 0.5)});
    v(self.lost_rechoose,
      {"lost_rechoose",
       "region_agree's lost object: the turn chooses a blob again (the usual choice) for its "
       "remaining pushes instead of ending (needs region_agree > 0)"});
    v(self.passes,
      {"passes",
       "Passes over the objects: passes 2..N push each class with views again (fewest views "
       "first) from where its object was left, its views to the same class; 1 off",
       core::between(1, 100)});
    v(self.revisit_top_down,
      {"revisit_top_down",
       "passes with region_agree: a revisit that finds nothing near its object's last target "
       "looks for it by top-down recognition (needs region_agree > 0, passes > 1)"});
    v(self.moving_wait,
      {"moving_wait",
       "Before choosing a blob the robot holds still this long and looks again; candidates "
       "whose depth moved (things moving by themselves) are left out (needs depth), s; 0 off",
       core::between(0.0, 5.0)});
    v(self.colour_words,
      {"colour_words",
       "Documents carry a colour word a feature (its patch's mean colour, 28 HSV words) after "
       "its SIFT word; --no-colour-words: SIFT words only (the thesis)"});
    v(self.colour_weight,
      {"colour_weight",
       "colour_words: each colour word counts this many times in the topic model's documents "
       "(LDA, theta, Mixture of Topics); the words classifiers keep 1",
       core::between(1, 1000)});
    v(self.topics, {"topics", "LDA topics (no --model)", core::between(2, 1000)});
    v(self.words, {"words", "Vocabulary words (no --vocabulary)", core::between(2, 100000)});
    v(self.quick, {"quick",
                   "Small and fast: quick_pushes pushes, 240x180, 100 words, 6 topics (each "
                   "where left at its default)"});
    v(self.quick_pushes,
      {"quick_pushes", "--quick: pushes of each object (pushes left at its default)",
       core::between(1, 1000)});
    v.choice(self.segmentation, {"segmentation", "Push segmentation: sparse or dense"},
             kPushSegmentationNames);
    v.choice(self.views,
             {"views",
              "Training views: motion (the push's frames by its segmentation), after (the look "
              "after the push, its object's blob), before (the look before it, the pushed "
              "blob) or both (motion's and before's, weighing alike a push)"},
             kLearnViewsNames);
    v.choice(self.dirichlet_update,
             {"dirichlet_update", "Object-word Dirichlet update: exact or fifty-fifty"},
             kDirichletUpdateNames);
    v(self.mask_fraction,
      {"mask_fraction", "Push mask: map >= fraction x its maximum", core::between(0.05, 1)});
    v(self.dense.touch_fm,
      {"seg_touch_fm",
       "dense: regions in the baseline's touch cut score at least this x the map's peak "
       "(MlOptions::touch_fm); 0 off",
       core::between(0.0, 1.0)});
    v(self.view_step,
      {"view_step", "Views: every n-th frame from the touch", core::between(1, 1000)});
    v(self.max_mask_share,
      {"max_mask_share",
       "A push's (or a view's) mask covering more than this share of the image gives no views "
       "(the scene, not one object); 1 off",
       core::positive_at_most(1)});
    v(self.min_features, {"min_features", "Features a view needs", core::between(1, 100000)});
    v(self.dilate, {"dilate", "Grow the masks by this many px", core::between(0, 100)});
    v(self.fps, {"fps", "Frame rate of the push episodes", core::positive_at_most(100)});
    v(self.width, {"width", "Image width, px", core::between(64, 4096)});
    v(self.height, {"height", "Image height, px", core::between(48, 4096)});
    v(self.held_out, {"held_out", "Held-out views per object", core::between(1, 100000)});
    v(self.mot_word_weight,
      {"mot_word_weight",
       "Scoring: weight of the word multinomials pooled with the MoT by words (0 words alone)",
       core::between(0.0, 1.0)});
    v(self.mot_word_per_view,
      {"mot_word_per_view",
       "Scoring: the pooled classifier's word multinomials weigh every view alike (off: the "
       "views' pooled counts); both are scored"});
    v.choice(self.headline,
             {"headline",
              "Scoring: the held-out figure given first: mot, argmax, pooled (the pooled "
              "words classifier), colour (the colour words alone) or auto (colour with colour "
              "words, else pooled)"},
             kLearnHeadlineNames);
    v(self.oracle_ladder,
      {"oracle_ladder", "Also score the oracle ladder (ground-truth masks and labels)"});
    v(self.ladder_pooled,
      {"ladder_pooled",
       "Scoring, with --oracle-ladder: also score every rung by the pooled words classifier "
       "(per-view word multinomials)"});
    v(self.write_documents,
      {"write_documents",
       "Also write documents.txt: the training views' and held-out views' words (lda-c lines), "
       "each training view with the object under most of its mask (ground-truth masks "
       "recorded)"});
    v(self.depth, {"depth",
                   "An RGB-D camera: plan from each blob's footprint and height "
                   "measured from depth"});
    v(self.vocabulary, {"vocabulary", "Visual vocabulary file (default: built from the views)"});
    v(self.lda_model, {"model", "LDA model file (default: trained on the views)"});
    v(self.out, {"out", "Run directory"});
    v(self.overwrite, {"overwrite", "Replace an existing run directory"});
  }
};

/// A push's plan as learn.json lists it: the pusher's path in the image and on the table.
struct LearnPushPlan {
  Eigen::Vector2d start_px = Eigen::Vector2d::Zero();  ///< the path's start in the image, px
  Eigen::Vector2d end_px = Eigen::Vector2d::Zero();    ///< its end, px
  Eigen::Vector2d start = Eigen::Vector2d::Zero();     ///< table m
  Eigen::Vector2d end = Eigen::Vector2d::Zero();       ///< table m
  Eigen::Vector2d target = Eigen::Vector2d::Zero();    ///< the object's target, table m
  double cost = -1;  ///< feature density along the path (eq 7.5); -1 when not finite

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(xy(self.start_px), {"start_px", "The path's start in the image, px"});
    v(xy(self.end_px), {"end_px", "Its end in the image, px"});
    v(xy(self.start), {"start", "The pusher's start, table m"});
    v(xy(self.end), {"end", "The pusher's end, table m"});
    v(xy(self.target), {"target", "The object's target, table m"});
    v(self.cost, {"cost", "Feature density along the path (eq 7.5); -1: not finite"});
  }
};

/// What a push really moved (ground truth, scoring only), listed in the push's row.
struct LearnPushTruth {
  std::string intended;              ///< the object under the pushed blob, or ""
  std::vector<std::string> moved;    ///< objects whose centre moved
  bool moved_intended = false;       ///< the intended object is among them
  bool moved_only_intended = false;  ///< and nothing else

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.intended, {"intended", "Ground truth: the object under the pushed blob"});
    v(self.moved, {"moved", "Ground truth: the objects that moved"});
    v(self.moved_intended, {"moved_intended", "Ground truth: the intended object moved"});
    v(self.moved_only_intended,
      {"moved_only_intended", "Ground truth: the intended object moved and nothing else"});
  }
};

/// One push as the learner did it (the "pushes" array of learn.json).
struct LearnPush {
  int index = 0;
  int object = 0;          ///< class 0..C-1
  std::string class_name;  ///< its name (object_1, ...), filled by the record
  std::string dir;         ///< "pushes/push_NNN"
  LearnPushPlan plan;
  bool executed = false;
  int frames = 0;
  int views = 0;
  std::string located;  ///< how the object was found: "chosen", "top-down", "tracked"
  std::string outcome;
  /// Executed: how long the push lasted on the robot's clock (from the transit's start to the
  /// arm's rest), s.
  double robot_seconds = 0;
  /// Executed: the perception of the push, processor seconds of the whole process (every
  /// thread): the segmentation of its frames, the word and Dirichlet updates, and the top-down
  /// recognition of the looks after it, up to the next executed push (issue 21's speed goal: less
  /// than robot_seconds on one core, so that a real robot would not wait for it).
  double perception_cpu_seconds = 0;
  std::optional<LearnPushTruth> truth;  ///< simulation: what it really moved
  /// passes > 1: the pass it was made in (2..N); left out in the first pass.
  std::optional<int> pass;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.index, {"index", "The push's number"});
    v(self.class_name, {"class", "The class it pushed"});
    v(self.dir, {"dir", "Its directory in the run"});
    v(self.plan, {"plan", "The plan"});
    v(self.executed, {"executed", "The robot executed it"});
    v(self.frames, {"frames", "Frames of its episode"});
    v(self.views, {"views", "Training views it gave"});
    v(self.located, {"located", "How the object was found: chosen, top-down or tracked"});
    v(self.outcome, {"outcome", "What came of it"});
    v(self.robot_seconds, {"robot_seconds", "Executed: the push's duration, robot clock, s"});
    v(self.perception_cpu_seconds,
      {"perception_cpu_seconds",
       "Executed: processor time of its segmentation, word updates and the recognition after it, "
       "s"});
    v(self.pass, {"pass", "passes > 1: the pass it was made in (2..N); none in the first"});
    if (self.truth) LearnPushTruth::describe(*self.truth, v);
  }
};

/// An object learned already and the blob it is in now (7.2 d: not chosen again).
struct KnownBlob {
  int object = 0;
  int blob = 0;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.object, {"object", "The object (class) learned already"});
    v(self.blob, {"blob", "The blob it is in"});
  }
};

/// (d)'s score of a blob: its best mean log p of the features under the object models so far.
struct BlobMeanLogP {
  int blob = 0;
  /// -infinity (written null) when no model is learned; new_object pixels: minus the Hellinger
  /// distance (-1..0) of the blob's pixel colours to the nearest class's
  double best_mean_log_p = 0;
  int best_object = -1;  ///< the object (class) whose model gives it
  /// best_mean_log_p less that object's own views' mean log p (its last push), nats: near 0 or
  /// above, the blob looks like that object (LearnOptions::known_margin).
  double below_own = 0;
  /// new_object "match": the largest fraction of its descriptors matched to one known object's
  /// views, and that object (absent with "words").
  std::optional<double> matched = {};
  std::optional<int> matched_object = {};

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.blob, {"blob", "The blob"});
    v(self.best_mean_log_p, {"best_mean_log_p", "Its best mean log p under the models so far"});
    v(self.best_object, {"best_object", "The object whose model gives it"});
    v(self.below_own, {"below_own", "It less that object's own views' mean log p, nats"});
    v(self.matched, {"matched", "match: its largest fraction matched to one known object"});
    v(self.matched_object, {"matched_object", "match: that object"});
  }
};

/// Why a candidate in view was not the one chosen (7.2 d) or was given up: the decisions log's
/// "skipped" of choose and rechoose events.
struct CandidateSkip {
  int blob = -1;  ///< the candidate (blob index in the look); -1: out of reach (not in the look)
  /// out-of-reach, tried (given up earlier), known (a learned object), no-features (fewer than
  /// min_features), no-push-path (no side planned), start-blocked (the hand would come down on
  /// something), transit-refused / not-planned (given up after failures), not-drawn (the first
  /// choice is at random), less-new (a newer-looking candidate was chosen), moving (its depth
  /// moved while the robot held still: LearnOptions::moving_wait).
  std::string reason;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.blob, {"blob", "The candidate (-1: out of reach, not in the look)"});
    v(self.reason, {"reason", "Why it was not chosen"});
  }
};

/// learn.json's "skipped": how often candidates were skipped for one reason, over the run.
struct SkipCount {
  std::string reason;
  int count = 0;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.reason, {"reason", "Why (CandidateSkip::reason)"});
    v(self.count, {"count", "Candidates skipped for it over the run's choices"});
  }
};

/// One line of learn's decision log (decisions.jsonl): an event and the fields it has (the
/// others are left out). Events: start, retry, look, split, region, choose, recognise, refound,
/// rechoose, replan, push, views, identity, move-on, fault, no-views, revisit, end. revisit (passes
/// > 1): a class's turn of a later pass, where its object was looked for (`at`), how it was
/// located (`located`, `blob`) or why it was skipped (`why`). identity (a turn's
/// first push that gave views, classes after the first): `scores` per known object (blob: the
/// pushed blob; best_object: the object; best_mean_log_p and below_own: the views' mean log p
/// under its words and that less its own), `why` when they were merged into one.
struct LearnDecision {
  std::string event = {};
  std::optional<int> object = {};                       ///< the object (class) being learned
  std::optional<int> index = {};                        ///< push: its number
  std::optional<int> blob = {};                         ///< the blob chosen, found or pushed
  std::optional<int> blobs = {};                        ///< look: blobs in reach
  std::optional<int> classes = {};                      ///< start: C
  std::optional<std::vector<double>> work_centre = {};  ///< start: table m
  std::optional<bool> found = {};                       ///< recognise
  std::optional<double> kappa = {};                     ///< recognise: the threshold chosen
  std::optional<double> log_density = {};               ///< recognise: 0 when not finite
  std::optional<int> features = {};                     ///< recognise: in the region
  std::optional<std::vector<double>> centre_px = {};    ///< recognise: their mean, px
  std::optional<std::string> located = {};              ///< push: chosen, top-down or tracked
  std::optional<LearnPushPlan> plan = {};               ///< push
  std::optional<bool> executed = {};                    ///< push
  std::optional<int> views = {};                        ///< views; end: all
  std::optional<int> words = {};                        ///< views: the object's words
  std::optional<std::string> segmentation = {};         ///< views: the segmentation's message
  std::optional<std::vector<std::vector<double>>> centres = {};       ///< look: blobs, table m
  std::optional<std::vector<std::vector<double>>> out_of_reach = {};  ///< look: dropped, m
  std::optional<std::string> why = {};
  std::optional<std::vector<KnownBlob>> known = {};      ///< choose (7.2 d)
  std::optional<std::vector<BlobMeanLogP>> scores = {};  ///< choose (7.2 d)
  std::optional<int> sides_rejected = {};                ///< replan
  std::optional<int> sides_hand = {};  ///< replan: sides whose start the hand would meet (depth)
  std::optional<std::vector<CandidateSkip>> skipped = {};  ///< choose, rechoose
  std::optional<std::string> fault = {};                   ///< fault: its kind
  std::optional<std::string> message = {};
  std::optional<int> blobs_before = {};            ///< split
  std::optional<int> blobs_after = {};             ///< split
  std::optional<std::string> by = {};              ///< split: what split it (top-down)
  std::optional<int> pixels = {};                  ///< region: its size, px
  std::optional<std::vector<int>> forgotten = {};  ///< region: objects whose region was forgotten
  std::optional<std::vector<int>> carried = {};    ///< region: regions moved with the push
  std::optional<int> blobs_out_of_reach = {};      ///< end
  std::optional<int> looks_split = {};             ///< end: looks whose blobs were split
  std::optional<int> pushes = {};                  ///< end
  std::optional<int> faults = {};                  ///< end
  std::optional<int> pass = {};                    ///< revisit: the pass (2..N)
  std::optional<std::vector<double>> at = {};      ///< revisit: where it was looked for, m

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.event, {"event", "What happened"});
    v(self.object, {"object", "The object (class) being learned"});
    v(self.index, {"index", "The push's number"});
    v(self.blob, {"blob", "The blob"});
    v(self.blobs, {"blobs", "Blobs in reach"});
    v(self.classes, {"classes", "Objects C"});
    v(self.work_centre, {"work_centre", "Centre of the work area, table m"});
    v(self.found, {"found", "Top-down recognition found the object"});
    v(self.kappa, {"kappa", "The threshold chosen"});
    v(self.log_density, {"log_density", "log Dir of the region's words"});
    v(self.features, {"features", "Features in the region"});
    v(self.centre_px, {"centre_px", "Their mean position, px"});
    v(self.located, {"located", "How the object was found"});
    v(self.plan, {"plan", "The plan"});
    v(self.executed, {"executed", "The robot executed the push"});
    v(self.views, {"views", "Views"});
    v(self.words, {"words", "The object's words"});
    v(self.segmentation, {"segmentation", "The segmentation's message"});
    v(self.centres, {"centres", "The blobs' centres, table m"});
    v(self.out_of_reach, {"out_of_reach", "Blobs out of reach, table m"});
    v(self.why, {"why", "Why"});
    v(self.known, {"known", "Objects learned already"});
    v(self.scores, {"scores", "Each scored blob"});
    v(self.sides_rejected, {"sides_rejected", "Sides rejected"});
    v(self.sides_hand, {"sides_hand", "Sides whose start the hand would meet (depth)"});
    v(self.skipped, {"skipped", "Candidates not chosen and why"});
    v(self.fault, {"fault", "The fault's kind"});
    v(self.message, {"message", "What happened, in words"});
    v(self.blobs_before, {"blobs_before", "Blobs before the split"});
    v(self.blobs_after, {"blobs_after", "Blobs after the split"});
    v(self.by, {"by", "What split the blob"});
    v(self.pixels, {"pixels", "The region's size, px"});
    v(self.forgotten, {"forgotten", "Objects whose region was forgotten"});
    v(self.carried, {"carried", "Objects whose region moved with the push (carry_regions)"});
    v(self.blobs_out_of_reach, {"blobs_out_of_reach", "Blobs out of reach over all looks"});
    v(self.looks_split, {"looks_split", "Looks whose blobs were split"});
    v(self.pushes, {"pushes", "Pushes"});
    v(self.faults, {"faults", "Logged faults"});
    v(self.pass, {"pass", "The pass (2..N)"});
    v(self.at, {"at", "Where the object was looked for, table m"});
  }
};

/// Coverage of one named object (ground truth, scoring only): the turns (classes) whose
/// executed pushes moved it as the intended object.
struct LearnCoverage {
  std::string name;
  int turns = 0;   ///< classes with at least one such push
  int pushes = 0;  ///< executed pushes that moved it as the intended object

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.name, {"name", "The named object"});
    v(self.turns, {"turns", "Turns (classes) whose pushes moved it as the intended object"});
    v(self.pushes, {"pushes", "Executed pushes that moved it as the intended object"});
  }
};

/// Per named object (`objects`, in order) its coverage by `pushes` (their ground truth; pushes
/// without it count for nothing).
std::vector<LearnCoverage> learn_coverage(const std::vector<std::string>& objects,
                                          const std::vector<LearnPush>& pushes);

/// A learned object (class) in learn.json.
struct LearnObjectRecord {
  std::string name;                  ///< the class (object_1, ...)
  int pushes = 0;                    ///< executed pushes of it
  int views = 0;                     ///< its training views
  std::optional<std::string> truth;  ///< simulation: the object it was named after
  std::optional<double> purity;      ///< simulation: its views showing that object

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.name, {"class", "The class"});
    v(self.pushes, {"pushes", "Executed pushes of it"});
    v(self.views, {"views", "Its training views"});
    v(self.truth, {"truth", "Ground truth: the object it was named after"});
    v(self.purity, {"purity", "Ground truth: its views showing that object"});
  }
};

/// Wall-clock and processor time of one stage of the loop (look, push, segment, words, ...).
/// "push_robot_clock" is the pushes' own duration on the robot's clock (no processor time).
struct StageSeconds {
  std::string stage;
  double seconds = 0;
  /// Processor time of the whole process in the stage (every thread), s; empty for the stages
  /// not timed by this process (push_robot_clock).
  std::optional<double> cpu_seconds;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.stage, {"stage", "The stage"});
    v(self.seconds, {"seconds", "Its wall-clock time, s"});
    v(self.cpu_seconds, {"cpu_seconds", "Its processor time, every thread, s"});
  }
};

/// 8.1.2's comparison of the two Dirichlet updates on a later push of an object: the predictive
/// log-likelihood of its frames under each.
struct PredictiveLikelihood {
  int object = 0;  ///< class
  int push = 0;    ///< push of the object
  double exact = 0;
  double fifty_fifty = 0;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.object, {"object", "The class"});
    v(self.push, {"push", "Push of the object"});
    v(self.exact, {"exact", "Predictive log-likelihood under the exact update"});
    v(self.fifty_fifty, {"fifty_fifty", "Under the 50:50 update"});
  }
};

/// What a run did (the learner's side and the ground truth's).
// NOLINTNEXTLINE(bugprone-exception-escape)
struct LearnSummary {
  int classes = 0;
  int pushes_executed = 0;
  int views = 0;
  int faults = 0;
  int model_classes = 0;
  double seconds = 0;
  std::optional<double> mot_accuracy;     ///< held out (simulation)
  std::optional<double> argmax_accuracy;  ///< held out (simulation)
};

/// A model file of the run directory and its size (learn.json's "vocabulary" and "topics").
struct LearnModelFile {
  const char* size_key = "words";  ///< "words" (vocabulary) or "count" (topics)
  int size = 0;
  std::string file;  ///< relative to the run directory

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.size, {self.size_key, "Its size: words or topics"});
    v(self.file, {"file", "The file in the run directory"});
  }
};

/// learn.json's "dirichlet_update": the update used and the two compared.
struct LearnDirichletUpdate {
  DirichletUpdate update = DirichletUpdate::kExact;
  const std::vector<PredictiveLikelihood>* likelihoods = nullptr;  ///< not null

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v.choice(self.update, {"default", "The update used"}, kDirichletUpdateNames);
    v(*self.likelihoods, {"predictive_log_likelihood", "The two updates compared, per push"});
  }
};

/// The word weights held-out views are also scored at (LearnWordScore::grid): 0 is the
/// Mixture of Topics by words alone, 1 multinomial naive Bayes.
inline constexpr double kLearnWordWeights[] = {0.0, 0.1, 0.25, 0.5, 0.75, 1.0};

/// One held-out object classified by words (LearnWordScore).
struct LearnWordObject {
  std::string name;
  int held_out = 0;          ///< its held-out views with features
  double theta = 0;          ///< right by the Mixture of Topics by theta (eq 7.3)
  double words = 0;          ///< right by the Mixture of Topics by words (classify_mot_words)
  double pooled = 0;         ///< right by that pooled with the word multinomials at the weight
  std::vector<double> grid;  ///< right by the pooled classifier at each kLearnWordWeights
  /// The same two with the per-view word multinomials (LearnOptions::mot_word_per_view).
  double pooled_per_view = 0;
  std::vector<double> grid_per_view;
  /// Right by the colour words alone (LearnWordScore::colour); none without colour words.
  std::optional<double> colour;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.name, {"name", "The object"});
    v(self.held_out, {"held_out", "Its held-out views with features"});
    v(self.theta, {"theta", "Right by the Mixture of Topics by theta"});
    v(self.words, {"words", "Right by the Mixture of Topics by words"});
    v(self.pooled, {"pooled", "Right by that pooled with the word multinomials"});
    v(self.grid, {"grid", "Right by the pooled classifier at each weight of word_weights"});
    v(self.pooled_per_view,
      {"pooled_per_view", "Right by the pooled classifier with per-view word multinomials"});
    v(self.grid_per_view,
      {"grid_per_view", "The same at each weight of word_weights (per-view multinomials)"});
    v(self.colour, {"colour", "Right by the colour words alone"});
  }
};

/// The held-out views classified by their words (LearnOptions::mot_word_weight), beside the
/// Mixture of Topics by theta on the same documents: a view is right when it is given a class
/// named after its own object (as SelfSupervisionScore's figures).
// NOLINTNEXTLINE(bugprone-exception-escape)
struct LearnWordScore {
  double weight = 0.25;
  /// Learn's pooled classifier is the one with per-view word multinomials (pooled_per_view)
  /// rather than the pooled counts (pooled): LearnOptions::mot_word_per_view.
  bool per_view = false;
  double theta = 0;   ///< held-out views right by the MoT by theta (the score's mot_accuracy)
  double words = 0;   ///< right by the MoT by words
  double pooled = 0;  ///< right by that pooled with the word multinomials at weight (counts)
  std::vector<double> word_weights;  ///< kLearnWordWeights
  std::vector<double> grid;          ///< right by the pooled classifier at each of them
  /// The same two with each class's word multinomial weighing its views alike (per_view_weights).
  double pooled_per_view = 0;
  std::vector<double> grid_per_view;
  /// Right by the colour words alone (documents with colour words): each class's multinomial
  /// over the colour words of its views, every view weighing alike (per_view_weights), add-one
  /// smoothed; a held-out view goes to the class under which its colour words are most likely
  /// (naive Bayes with the model's prior p(c)). The SIFT words are left out: they change when
  /// an object turns or topples, its colours do not (session 39). None without colour words.
  std::optional<double> colour;
  std::vector<LearnWordObject> objects;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.weight, {"weight", "The word multinomials' weight in the pooled score"});
    v(self.per_view, {"per_view", "Learn's pooled classifier is pooled_per_view (else pooled)"});
    v(self.theta, {"theta", "Held-out views right by the Mixture of Topics by theta"});
    v(self.words, {"words", "Right by the Mixture of Topics by words"});
    v(self.pooled, {"pooled", "Right by that pooled with the word multinomials"});
    v(self.word_weights, {"word_weights", "The weights of grid"});
    v(self.grid, {"grid", "Right by the pooled classifier at each weight"});
    v(self.pooled_per_view,
      {"pooled_per_view", "Right by the pooled classifier with per-view word multinomials"});
    v(self.grid_per_view, {"grid_per_view", "The same at each weight (per-view multinomials)"});
    v(self.colour, {"colour", "Right by the colour words alone (per-view colour multinomials)"});
    v(self.objects, {"objects", "Per held-out object"});
  }
};

/// Scores held-out documents by theta and by words. `training`/`labels`: the robot's views and
/// their model classes (-1: left out), for the word multinomials, fitted both ways: the views'
/// pooled counts (pooled, grid) and every view weighing alike (pooled_per_view, grid_per_view);
/// `per_view` says which is learn's pooled classifier (LearnWordScore::per_view); `held[i]`:
/// object i's held-out documents (objects[i]); `class_object[m]`: the object model class m is
/// named after ("" none). `colour_from` >= 0: the documents' words from that id on are colour
/// words (features::with_colour_words: the vocabulary's size), scored alone too
/// (LearnWordScore::colour); -1: none. Throws Error when the sizes disagree (held vs objects,
/// labels vs training, class_object vs the model's classes), on a weight outside [0, 1], on an
/// empty model or on a colour_from the documents' words do not reach past.
LearnWordScore score_by_words(const topics::MotModel& model, const topics::LdaModel& lda,
                              const topics::Corpus& training, const std::vector<int>& labels,
                              const std::vector<topics::Corpus>& held,
                              const std::vector<std::string>& objects,
                              const std::vector<std::string>& class_object, double weight,
                              bool per_view = false, int colour_from = -1);

/// Learn's headline held-out figure (LearnOptions::headline), learn.json's "headline".
struct LearnHeadlineFigure {
  /// "mot", "argmax", "pooled" (counts), "pooled_per_view" or "colour"
  std::string classifier;
  std::string what;                ///< the classifier in words
  double accuracy = 0;             ///< held-out views given a class named after their own object
  std::vector<std::string> names;  ///< the held-out objects
  std::vector<int> held_out;       ///< their held-out views with features
  std::vector<double> per_object;  ///< the accuracy per object

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.classifier, {"classifier", "mot, argmax, pooled (counts) or pooled_per_view"});
    v(self.what, {"what", "The classifier in words"});
    v(self.accuracy, {"accuracy", "Held-out views given their own object's class"});
    v(self.names, {"objects", "The held-out objects"});
    v(self.held_out, {"held_out", "Their held-out views with features"});
    v(self.per_object, {"per_object", "The accuracy per object"});
  }
};

/// The headline of `headline` from the ground-truth score and the words' score (either may be
/// absent: nullopt when the figure asked for is not there).
std::optional<LearnHeadlineFigure> learn_headline(LearnHeadline headline,
                                                  const std::optional<SelfSupervisionScore>& score,
                                                  const std::optional<LearnWordScore>& words);

struct LearnResult;

/// learn.json's "held_out": the views per object and the held-out confusion matrices, or why
/// there are none.
struct LearnHeldOut {
  const LearnResult* result = nullptr;  ///< not null
  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v);
};

// NOLINTNEXTLINE(bugprone-exception-escape)
struct LearnResult {
  LearnSummary summary;
  /// The options of the run (resolved; out: the directory the record names).
  LearnOptions options;
  bool complete = false;  ///< false: learn.json of a run not yet scored (written before it)
  std::vector<std::string> classes;  ///< object_1 .. object_C
  std::vector<LearnObjectRecord> objects;
  std::vector<LearnPush> pushes;
  std::vector<StageSeconds> timing;
  std::optional<LearnModelFile> vocabulary;  ///< made or given (vocabulary.vocab)
  std::optional<LearnModelFile> topics;      ///< made or given (lda.model)
  std::vector<std::string> model_classes;    ///< the Mixture of Topics' classes (model.mot)
  std::vector<PredictiveLikelihood> dirichlet_likelihoods;
  bool held_out = false;        ///< the held-out views were asked for (simulation)
  bool record_seconds = false;  ///< the record lists summary.seconds (simulation)
  std::optional<SelfSupervisionScore> score;
  /// Simulation: the held-out views classified by their words (LearnOptions::mot_word_weight).
  std::optional<LearnWordScore> words;
  /// Simulation: the headline held-out figure (LearnOptions::headline).
  std::optional<LearnHeadlineFigure> headline;
  /// Simulation: per named object, the turns whose pushes moved it as the intended object.
  std::vector<LearnCoverage> coverage;
  /// Per reason, the candidates skipped at the run's choices (decisions.jsonl's "skipped").
  std::vector<SkipCount> skipped;
  core::Json document;  ///< format "proprio.learn" (also DIR/learn.json)
  /// The run's HTML page (loop/learn_report.hpp), written last by the simulated run; empty
  /// after the robot-only run (it has no held-out views to show).
  std::filesystem::path report;
  std::string message;  ///< one line: what happened (brief()'s first line)
  [[nodiscard]] std::string brief() const;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.complete, {"complete", "The run was scored (false: written before the held-out views)"});
    v(self.options, {"options", "The run's options (resolved)"});
    v(self.classes, {"classes", "The classes, one an object"});
    v(self.objects, {"objects", "Per class"});
    v(self.pushes, {"pushes", "Every push"});
    v(self.timing, {"timing", "Wall-clock and processor time per stage"});
    v(std::string("wall"), {"clock", "The clock of the timings"});
    v(self.vocabulary, {"vocabulary", "The vocabulary"});
    v(self.topics, {"topics", "The LDA model"});
    if (!self.model_classes.empty()) v(std::string("model.mot"), {"model", "The object model"});
    v(self.model_classes, {"model_classes", "The object model's classes"});
    v(self.summary.faults, {"faults", "Logged faults"});
    v(LearnDirichletUpdate{self.options.dirichlet_update, &self.dirichlet_likelihoods},
      {"dirichlet_update", "The object-word Dirichlet update and the two updates compared"});
    if (self.held_out) v(LearnHeldOut{&self}, {"held_out", "Held-out views"});
    v(self.headline, {"headline", "The headline held-out figure (--headline)"});
    v(self.score, {"ground_truth", "Scored against the ground truth"});
    v(self.words, {"held_out_words", "Held-out views classified by their words"});
    if (!self.coverage.empty()) {
      v(self.coverage, {"coverage", "Ground truth: per named object, the turns that pushed it"});
      int covered = 0;
      for (const LearnCoverage& c : self.coverage) covered += c.turns > 0 ? 1 : 0;
      v(covered, {"covered", "Ground truth: named objects pushed as the intended object"});
    }
    if (!self.skipped.empty()) {
      v(self.skipped, {"skipped", "Per reason, candidates not chosen at the run's choices"});
    }
    if (self.record_seconds) v(self.summary.seconds, {"seconds", "Wall clock, s"});
  }
};

template <class Self, class Visitor>
void LearnHeldOut::describe(Self& self, Visitor& v) {
  const LearnResult& r = *self.result;
  v(r.options.held_out, {"views_per_object", "Held-out views per object"});
  if (r.score) {
    v(held_out_confusion_json(r.score->mot, r.score->mot_accuracy),
      {"mot", "Held out: true objects x classes, Mixture of Topics"});
    v(held_out_confusion_json(r.score->argmax, r.score->argmax_accuracy),
      {"argmax", "The same by argmax theta"});
  } else {
    v(false, {"scored", "Whether they were scored"});
    v(std::string("no model: the robot took no view it could learn from (see decisions.jsonl)"),
      {"why", "Why not"});
  }
}

/// The loop on `robot` with `attendant` told what it does; writes the run directory (but not
/// the held-out scores: that is the sim wrapper's). `classes` is C. Throws Error for bad options,
/// an existing out without overwrite, unreadable --vocabulary/--model.
LearnResult run_learn(const LearnOptions& options, robot::Robot& robot, TableAttendant& attendant,
                      int classes, const core::Provenance& provenance);

/// The scoring options run_learn gives score_self_supervision for `options` (already
/// resolved): the named objects, seed, image size, held-out views, features, masks, MoT, the
/// oracle ladder and (ladder_pooled) the ladder's pooled words classifier.
SelfSupervisionOptions learn_score_options(const LearnOptions& options);

/// The simulated table run_learn (below) makes of `options` (already resolved): the named
/// objects, the clutter, the backdrop and distractors, the seed, the image size, the ground-truth
/// masks (oracle_ladder) and an RGB-D camera (depth). Throws Error for an unknown backdrop.
sim::TableOptions learn_table(const LearnOptions& options);

/// run_learn on a simulated table of options.objects + options.clutter (seed options.seed),
/// scored against the ground truth and on held-out views (20 per object, as
/// score_self_supervision renders them). Throws Error for an unknown or repeated object, more
/// objects than the table holds (8), zero pushes, an unknown background, an existing out.
LearnResult run_learn(const LearnOptions& options, const core::Provenance& provenance);

}  // namespace proprio::loop
