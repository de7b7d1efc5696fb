#pragma once
// The robot teaches itself (thesis 7.2 a-d, 7.3.2): given only the number of objects C on a table
// with a plain static backdrop, it (a) picks a putative object (a feature-density blob) at random,
// (b) pushes every other blob toward the edge of the view until the chosen one stands alone,
// (c) pushes the chosen object again and again from several sides so that it turns, each push's
// frames becoming its training views (Motion-Likelihood mask -> visual words -> LDA theta -> one
// Mixture of Topics class), then (d) asks for the objects to be re-scattered (a person does it;
// logged) and chooses the blob least likely under the classes learned so far, until C classes
// are learned; the Mixture of Topics (a Dirichlet per class, thesis 7.1) is fitted to them.
//
// The learner talks to robot::Robot only (look, push) and names its classes object_1..object_C;
// what the objects really are, and how well it did, is for a TableAttendant (the person who
// re-scatters, and in simulation the ground-truth scorer, loop/self_supervision_scoring.hpp),
// which the learner tells what it does but never asks anything of the world.
//
// Every decision goes to a log of JSON lines: the blobs seen, the choice and why, each planned
// path and its cost, what happened. Faults (fewer blobs than C, the chosen object lost, a push
// that cannot be planned or is refused, a push that moves nothing) are logged outcomes: re-look,
// re-plan, or stop the round with the reason; never a crash, never a view given a class it was
// not seen with.
//
// Frames: table points are world x y (m, robot base frame); pixels as planning::PlanningView.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "proprio/core/fields.hpp"
#include "proprio/core/json_io.hpp"
#include "proprio/core/provenance.hpp"
#include "proprio/features/colour_words.hpp"
#include "proprio/features/extraction.hpp"
#include "proprio/features/vocabulary.hpp"
#include "proprio/loop/record_fields.hpp"
#include "proprio/planning/push_planner.hpp"
#include "proprio/robot/robot_interface.hpp"
#include "proprio/segmentation/ml_segmentation.hpp"
#include "proprio/topics/corpus.hpp"
#include "proprio/topics/lda_model.hpp"
#include "proprio/topics/mixture_of_topics.hpp"

namespace proprio::loop {

/// Where a push's training views come from.
enum class ViewSource {
  /// Motion-Likelihood segmentation of the push's episode (thesis Ch 4): every view_step-th frame
  /// from the first touch on, cut out by the integrated map painted with that frame's regions.
  kMotion,
  /// The planner's blob of the chosen object in the look after the push (one view a push, arm
  /// parked out of view).
  kBlob,
  /// kMotion's views and the look before the push cut out by the pushed blob (the blob the push
  /// was planned on), entered once a motion view so that it weighs as much as all of them: learn's
  /// LearnViews::kBoth (docs/results/learn.md, session 40: its views before were 96.6 % pure).
  /// Off: on fresh seeds 11-30, on the same pushes, c moved -1.6 +- 3.8 points (session 41).
  kBoth,
};
inline constexpr core::ChoiceNames<ViewSource, 3> kViewSourceNames{
    {{"motion", ViewSource::kMotion}, {"blob", ViewSource::kBlob}, {"both", ViewSource::kBoth}}};

/// SelfSupervisionOptions::rounds: what the robot judges two rounds' objects the same by.
enum class RoundSimilarity {
  /// Their views' word counts (round_distance, nats a word; below same_object: one object). The
  /// default; it did not separate one object's rounds from different objects' (session 31).
  kWords,
  /// Their looks' pixel colours (colour_round_distance: the Hellinger distance of the pooled
  /// colour histograms, as the claims by colour compare a blob with a class; below same_colour:
  /// one object). (d)'s claims by this signal are right for 87 of 118 on seeds 77-96.
  kColour,
};
inline constexpr core::ChoiceNames<RoundSimilarity, 2> kRoundSimilarityNames{
    {{"words", RoundSimilarity::kWords}, {"colour", RoundSimilarity::kColour}}};

/// How the held-out views are classified by the learned Mixture of Topics (scoring only).
enum class MotClassifier {
  /// Eq 7.3 on each view's theta (the thesis's; the default).
  kTheta,
  /// The Mixture of Topics by words pooled with each class's word multinomial
  /// (topics::pool_word_multinomials at SelfSupervisionOptions::mot_word_weight; the classifier
  /// that met issue 17 on the scatter videos, docs/results/mot.md session 22).
  kPooled,
  /// The colour words alone (SelfSupervisionOptions::colour_words, which validate() requires):
  /// naive Bayes on each view's colour words with the MoT's prior p(c), each class's colour
  /// multinomial from its training views weighing alike (classify_by_colour; learn's
  /// LearnWordScore::colour, session 39 of docs/results/learn.md).
  kColour,
};
inline constexpr core::ChoiceNames<MotClassifier, 3> kMotClassifierNames{
    {{"theta", MotClassifier::kTheta},
     {"pooled", MotClassifier::kPooled},
     {"colour", MotClassifier::kColour}}};

/// How (d) chooses the next object to learn.
enum class NextObjectRule {
  /// choose_unlearned: each learned class claims the blob nearest its own looks (one blob a
  /// class), the unclaimed blob farthest from every class is chosen.
  kLooks,
  /// The thesis's literal rule: the blob whose best log Dir(theta | omega_c) + log p(c) under
  /// the Mixture of Topics of the views so far (push frames) is least.
  kDirichlet,
};
inline constexpr core::ChoiceNames<NextObjectRule, 2> kNextObjectRuleNames{
    {{"looks", NextObjectRule::kLooks}, {"dirichlet", NextObjectRule::kDirichlet}}};

/// What (d)'s claims (choose_unlearned) judge a blob against: which learned class is its object.
enum class ClaimSignal {
  /// Each class's looks: the thetas of its tracked blob in the looks of its learn round
  /// (choose_unlearned; the default until session 41).
  kLooks,
  /// Each class's views: the words its learn pushes' views gave (the pushed object's masks in
  /// the push frames), pooled into one multinomial a class (choose_unlearned_by_words).
  kViewWords,
  /// Each class's looks as words: the words of its tracked blob in the looks of its learn round
  /// (the same looks as kLooks, the same kind of image as the candidates), pooled into one
  /// multinomial a class (choose_unlearned_by_words) instead of thetas.
  kLookWords,
  /// As kLookWords, but only each class's first look (after (b), before its first learn push:
  /// the object as it stood, as the candidates stand after a re-scatter, not lying after it
  /// toppled).
  kFirstLookWords,
  /// Each class's SIFT descriptors: the features inside its tracked blob in the looks of its
  /// learn round (the same looks as kLooks, at most SelfSupervisionOptions::descriptor_cap a
  /// class), matched to each blob's descriptors with OpenCV's matcher and Lowe's ratio test
  /// (choose_unlearned_by_descriptors).
  kDescriptors,
  /// Each class's looks as pixel colours: the colour word (features::colour_word_counts, the
  /// grid SelfSupervisionOptions::colour) of every pixel of its tracked blob in the looks of its
  /// learn round (the same looks as kLooks), pooled into one histogram a class; a blob's distance
  /// to a class is the Hellinger distance between their histograms (choose_unlearned). Not the
  /// features' points only: a blob of 30-60 px has a few dozen SIFT features but thousands of
  /// pixels, and an object's colours do not change as it turns. The default since session 41.
  kColour,
  /// No signal: only as SelfSupervisionOptions::other_claims_by (no comparison made).
  kNone,
};
/// The claim signals' names (SelfSupervisionOptions::claims_by and other_claims_by); "none"
/// serves other_claims_by only (validate() refuses it as claims_by).
inline constexpr core::ChoiceNames<ClaimSignal, 7> kClaimSignalNames{
    {{"looks", ClaimSignal::kLooks},
     {"view-words", ClaimSignal::kViewWords},
     {"look-words", ClaimSignal::kLookWords},
     {"first-look-words", ClaimSignal::kFirstLookWords},
     {"descriptors", ClaimSignal::kDescriptors},
     {"colour", ClaimSignal::kColour},
     {"none", ClaimSignal::kNone}}};

/// Where a class's descriptors come from (SelfSupervisionOptions::descriptor_source).
enum class DescriptorSource {
  /// Its looks: the features inside its tracked blob in the looks of its learn round (whole-blob
  /// masks, arm parked, the same camera as the candidates; the default).
  kLooks,
  /// Its first look only: the look after (b), before its first learn push (the object as the
  /// robot judged it cleared, before its pushes could merge it with a neighbour).
  kFirstLook,
  /// Its views: the features of its training views (the pushed object's masks in its learn
  /// pushes' frames: what the class learned and is named by).
  kViews,
};
inline constexpr core::ChoiceNames<DescriptorSource, 3> kDescriptorSourceNames{
    {{"looks", DescriptorSource::kLooks},
     {"first-look", DescriptorSource::kFirstLook},
     {"views", DescriptorSource::kViews}}};

/// planning::PushPlanOptions with descent_clearance 0.04 m (SelfSupervisionOptions::plan's).
inline planning::PushPlanOptions descent_checked() {
  planning::PushPlanOptions p;
  p.descent_clearance = 0.04;
  return p;
}

/// topics::MotOptions with up to 3 Dirichlets per object (SelfSupervisionOptions::mot's default).
inline topics::MotOptions three_components() {
  topics::MotOptions m;
  m.components = 3;
  return m;
}

struct SelfSupervisionOptions {
  /// The objects on the table, catalogue names, comma-separated: the world's business (the
  /// simulated table is made of them); the learner is told only how many there are (C).
  std::string objects = "calculator,bike,bottle";
  std::filesystem::path lda_model;   ///< LDA model file (T topics; required)
  std::filesystem::path vocabulary;  ///< its visual vocabulary (required, same number of words)
  int pushes = 10;                   ///< (c): pushes of each chosen object
  int clear_pushes = 12;             ///< (b): pushes at most to clear the others, per round
  /// (b): the chosen object stands alone when every other blob's footprint (hull on the table)
  /// is at least this far from its own, m (the learner's own estimate). 0.15 with the feature
  /// hulls (session 45, tuning seeds 97-122): singulation 30.8 -> 49.0 % but objects with a class
  /// -0.31 +- 0.27 and the colour figure -8.7 +- 8.4 (docs/results/selfsupervision.md).
  double clearance = 0.10;
  /// (c): pushes aim at points on a circle of this radius about the table point at the image's
  /// centre, m, stepped by the golden angle, so the object is pushed from ever other sides.
  double circle_radius = 0.07;
  /// (c): learn pushes meet the object off its centre line so that it turns (turning_push): the
  /// pusher's line shifted sideways by this fraction of the object's half width (at most
  /// kMaxTurnOffset; negative: to the right). 0 (the default): through the centre. Session 16,
  /// tuning seed 1: pushes through the centre already turned their object 13-39 degrees a push
  /// (bike 13, giraffe 35, bottle 39); with 0.5 (every offset 3 cm, the feature hulls being
  /// wide) 10-14, and the pushes that moved nothing rose 2 -> 6
  /// (docs/results/selfsupervision-history.md).
  double turn_offset = 0;
  /// (c): learn pushes the run may spend in all are C x pushes; a round that ends early (its
  /// object lost, pushes not planned) leaves its unspent pushes to the later rounds
  /// (round_budget), which then push their objects longer (up to twice `pushes`).
  bool carry_budget = true;
  /// (c): after each learn push the object is the blob that moved (followed by its motion)
  /// unless its look no longer matches the round's own looks and another blob's does, by this
  /// much of Hellinger distance (follow_by_looks; the push's views are then not learned). 0 (the
  /// default): off, motion only. Session 16, report seeds 2-6 with 0.1: 9 re-finds, most of
  /// them (by the episodes' ground-truth masks) to another object than the chosen one; the
  /// rounds whose object pushed most was the chosen one fell 14 -> 12 of 20: the resting-view
  /// looks (T = 32) do not tell the objects apart well enough
  /// (docs/results/selfsupervision-history.md).
  double refind_margin = 0;
  /// (c): when the look before a learn push finds no blob where the object was left (within
  /// 8 cm of its last centre: a push that moved it far, or whose look after it did not find it,
  /// lost it), the object is found again by the pixel colours of the round's own looks (the
  /// signal of claims_by colour): the blob whose colour distribution is nearest them, when that
  /// Hellinger distance is below this and no other round's looks are nearer (logged "refound";
  /// none: the round stops, "chosen object lost", as before). 0 (the default): off. Session 43
  /// (fresh seeds 77-96, 0.5 against off, paired): colour figure +3.3 +- 5.2 points, c +2.1 +-
  /// 3.1, but objects with a class 3.25 -> 3.10 (the rounds after a re-find get fewer carried
  /// pushes and choose on another table): its rule failed (docs/results/selfsupervision.md).
  double refind_colour = 0;
  /// claims_by colour (and refind_colour): a round's colours from its first look only (its object
  /// after (b), before any learn push) instead of all its looks. Session 43, read off 180 classes
  /// of the default runs of seeds 51-96 (ground truth): the first look's blob was 88 % the
  /// round's chosen object (pure, >= 95 %, in 68 % of rounds), all looks' 74 % (pure 54 %), and
  /// (d)'s colour claims were wrong mostly where the class's looks held a neighbour. Off (the
  /// default): all looks. Tuning seeds 71-76 (session 43): objects with a class 3.67 -> 3.33,
  /// colour figure -3.2 +- 12.3, claims right 28 -> 25 of 35: its gate failed, no report run
  /// (docs/results/selfsupervision.md, "Session 43").
  bool colour_first_look = false;
  /// claims_by colour (and refind_colour, same_object_by colour): a round's colours from the
  /// pixels its learn pushes moved (moved_pixels: within the pushed blob in the look before each
  /// push and within the blob found after it in the look after, the pixels whose colour changed
  /// by more than kMovedLevels in a channel), instead of its tracked blob's whole mask in the looks
  /// before its pushes. A neighbour inside the blob that the push left where it was is left out,
  /// and so is the plain table around the object. Not with colour_first_look. Off (the default):
  /// tuning seeds 97-102 (session 45), objects with a class 3.33 -> 3.00, claims right 27 -> 25
  /// of 36; its gate failed, no report run (docs/results/selfsupervision.md, "Session 45").
  bool moved_colours = false;
  /// claims_by colour: a blob's distance to a class is its least Hellinger distance to any one of
  /// the class's looks' colour distributions, rather than to their pooled colours
  /// (choose_unlearned on colours, as kLooks takes thetas). A class whose looks held a neighbour in
  /// some rounds' looks keeps its pure looks apart: its object's blob is near them. Not with
  /// colour_first_look or moved_colours. Off (the default): tuning seeds 97-122 (session 45),
  /// objects with a class -0.23 +- 0.26, colour figure -5.9 +- 7.5, claims right 117 -> 112; its
  /// gate failed, no report run (docs/results/selfsupervision.md, "Session 45").
  bool colour_by_look = false;
  /// Claims by colour (claims_by or other_claims_by kColour): the table's own colour words
  /// (table_colour_words: those of at least kTableColourShare of the look's pixels outside every
  /// blob) are left out of every blob's pixel colours, the classes' looks' and the candidates'
  /// alike (without_table_colours), so that how much table shows through a blob (a lying bike's
  /// box is a third table) no longer moves its distance to a class. Session 49: of the 12
  /// rounds of tuning seeds 97-122 that learned an object again, 10 chose it as "unclaimed by
  /// the learned classes' pixel colours", 7 of them the bike. Off (the default): on those seeds
  /// objects with a class -0.19 +- 0.16, c -5.4 +- 5.3, such rounds 12 -> 17 (the grey objects
  /// look alike without the table showing through them); its gate failed, no report run
  /// (docs/results/selfsupervision.md, "Session 49").
  bool table_colours_out = false;
  /// (c): a learn push keeps the corridor its object sweeps (the blob's footprint hull carried
  /// from its centre to the push's target, in the table plane) at least this far from every
  /// other blob's footprint, m (learn_push_lack: a neighbour nearer already may not come nearer).
  /// A push that does not is replaced by another side, then by a shorter push (kShortLearnPush);
  /// when none keeps clear the round stops, logged (fault "crowded"). 0: off, the default.
  /// Measured in session 17 with stop_on_drift and alone_views (0.03 m): learn pushes moving
  /// their object alone 41% -> 35% (ground truth, report seeds 2-6), c 35.4 -> 33.2% (noise),
  /// the tuning seed's c 49.7 -> 42.0%: the blobs' hulls are not the objects', so all three
  /// stay off (docs/results/selfsupervision-history.md, "Keeping a round on its object by
  /// geometry").
  double learn_clearance = 0.0;
  /// (c), with learn_clearance: a round stopped "crowded" (its object drifted back among the
  /// others, so that every learn push would sweep it toward one) runs (b) again about the
  /// object's place and then goes on with (c) and its pushes left, at most this many times a
  /// round (logged, event "replan"). The ground truth's singulation stays scored after the
  /// round's first (b). 0: the round stops (the default). Session 46, tuning seeds 97-122 with
  /// clearance 0.15, learn_clearance 0.05 and 2: 31 re-clears, training views a run 231 -> 251
  /// (the defaults: 303), but against the defaults objects with a class -0.12 +- 0.26, colour
  /// figure -1.5 +- 8.9, c -6.2 +- 7.5: its gate failed, no report run
  /// (docs/results/selfsupervision.md, "Session 46").
  int crowded_reclears = 0;
  /// (c): a round stops, logged, when its push moved another blob most (fault "drift":
  /// push_motion) or left the pushed blob merged with another one (fault "merged":
  /// merged_blob); a round then no longer drifts to a neighbour and learns it as its object.
  /// Off by default (measured, see learn_clearance).
  bool stop_on_drift = false;
  /// (c): a push whose motion (push_motion) shows a second blob moving gives no training views
  /// (fault "two-moved"), so the views show the round's object alone. Session 17: the looks'
  /// motion saw a second object in few of the pushes that moved one (purity 68 -> 75%, within
  /// the seeds' spread): a neighbour inside the pushed blob does not count as a blob. Off by
  /// default (see learn_clearance).
  bool alone_views = false;
  /// A blob moved in a push when at least this share of its feature points changed between the
  /// looks before and after it (planning::moved_share; push_motion).
  double moved_share = 0.25;
  /// (c), views kMotion: blobs that are objects (session 18). After a learn push its own motion
  /// segmentation splits the blobs (thesis 8.1.1: what moved with the arm is one object;
  /// planning::split_putative_objects): the look before by the mask at the first touch, before
  /// what moved is judged (episode_motion: from the episode's frames, what the push's motion does
  /// not explain), and the look after by the mask at the push's end, on which the next push is
  /// planned. Off (the default): the looks' blobs and push_motion (the looks' difference).
  /// Measured in session 18 with alone_views: the verdict of what moved agrees with the ground
  /// truth for 64% of learn pushes (the looks: about 33%), but the pushes moved their object
  /// alone no more often (41 -> 42%, report seeds 2-6), c 35.4 -> 39.4% (noise) and the tuning
  /// seed's c 49.7 -> 32.3%: off (docs/results/selfsupervision-history.md, "Blobs that are
  /// objects").
  bool split_by_motion = false;
  /// (c): a learn push's fallback sides (when its first goal cannot be planned) go inward first
  /// and never farther from the work centre than the object already is (fallback_goals).
  bool inward_sides = false;
  /// (b), (c): the chosen object itself is pushed into free space (session 19). When another blob
  /// is nearer than `clearance`, (b) first pushes the chosen object (at most kFreeMoves times a
  /// round) to the point within this radius (m) of the work centre where its footprint would lie
  /// farthest from every other blob (free_spots), then clears the others as before; the learn
  /// pushes (c) then aim at the circle of targets about the object's place after (b) (its free
  /// spot) instead of the work centre, which the others often crowd; when no learn push can be
  /// planned there, about the work centre again. 0: off (the default). Measured with 0.12 m:
  /// learn pushes moving their object alone 41% -> 49% (report seeds 2-6), but c 35.4 -> 34.9%
  /// (noise), and the free-space push was executed only 3 times in 5 runs (its spots are mostly
  /// out of reach) (docs/results/selfsupervision-history.md, "Session 19").
  double free_space = 0.0;
  /// (a), (b), (d): merged blobs split (split_merged_blobs, session 20): every look of the
  /// choice and of (b) that shows fewer blobs than C splits its largest blob by k-means on its
  /// feature points' positions and colours (split_colour weighs the colours; logged, event
  /// "split"). The looks of (c) are not split: there an object lost off the table is the usual
  /// cause, and splitting the object being learned left most learn pushes unplannable (tuning
  /// seed 1: 87 "not-planned" faults, c 49.7 -> 27.3%). Off (the default): measured with
  /// singulate_tries 2, c 49.7 -> 25.0% on the tuning seed and 35.4 +- 10.7% -> 32.4 +- 10.8%
  /// on seeds 2-6, singulation (ground truth) 30% -> 30%: a k-means cut is not the boundary
  /// between two objects (docs/results/selfsupervision-history.md, "Session 20"). Session 49,
  /// alone under the claims by colour (tuning seeds 97-122): objects with a class -0.38 +- 0.26,
  /// c -6.3 +- 7.7, singulation +9.6 +- 10.7, 2.03 pushes an object moved to the edge: a half
  /// of a merged blob is claimed as readily as an object (docs/results/selfsupervision.md).
  bool split_merged = false;
  /// split_merged: the colours' weight against the positions in the k-means split (0: positions).
  double split_colour = 1.0;
  /// (b): when (b) ends without the chosen object singulated by the robot's own check (every
  /// other blob at least `clearance` away), (b) starts again with a new budget of clear_pushes,
  /// at most this many times, before (c) starts (logged, event "replan"). 0: (c) starts anyway
  /// (the default; the fault "not-singulated" is logged either way). Session 20, seeds 2-6 with
  /// split_merged and 2: retries in 4 of 20 rounds, none of which then singulated.
  int singulate_tries = 0;
  /// (b): the robot's singulation check from depth (loop::depth_alone, session 21): the chosen
  /// object's footprint measured in the depth image (height above the table, split at depth
  /// discontinuities) and its gap to every other footprint, instead of the feature hulls' gap;
  /// a blob whose features lie on two footprints, or another blob on its footprint, is not alone.
  /// The blobs pushed away are those whose footprint lies nearer than `clearance`. Turns the
  /// RGB-D camera on (as `depth`). Off (the default). Either way, with `depth` on, every look of
  /// (b) logs both verdicts (`why`: "feature hulls: N too near; depth: ..."; `gap`: the depth
  /// gap). Tuning seed 1 (session 21): the feature hulls said "alone" in all 4 rounds of a
  /// `depth` run, none alone by the ground truth; over 12 rounds of three runs the depth check
  /// at clearance 0.10 was right in 8, measuring gaps 2-9 cm too wide (the objects' hidden
  /// backs), at 0.15 in 12 (docs/results/selfsupervision-history.md, "Session 21").
  bool alone_by_depth = false;
  /// (b): when (b) (and its singulate_tries) ends with the chosen object not alone by the robot's
  /// check, choose instead the blob of the last look that stands farthest from the others by
  /// that check and run (b) on it, at most this many times a round (logged, event "replan").
  /// 0: (c) starts on the object not alone (the default).
  int switch_tries = 0;
  /// (c), rounds after the first: "an object learned twice" (session 24). The first learn push
  /// of a round that gives views is tested against the classes learned so far (explained_by on
  /// the views' theta and the Mixture of Topics of the earlier rounds' views): when a class
  /// already explains them, the round drops those views, gives its looks of the object to that
  /// class (so that (d)'s choice sees the object as learned) and chooses again (logged, event
  /// "repeat"), with the pushes left, at most this many times a round. 0: off (the default).
  int repeat_tries = 0;
  /// repeat_tries: the share of the views a class must explain (explained_by).
  double repeat_share = 0.5;
  /// (c), rounds after the first: "a round that drifts onto a learned object" (session 25). Every
  /// learn push's views after the round's first push with views are tested as repeat_tries
  /// tests the first (explained_by at repeat_share against the Mixture of Topics of the earlier
  /// rounds' views): when a learned class explains them the round has drifted onto that class's
  /// object (its tracked blob is now a neighbour it pushed): those views are dropped, the look
  /// after the push is given to that class and the round stops (logged, event "repeat"; its
  /// unspent pushes go to the next round with carry_budget). Off (the default).
  bool repeat_later = false;
  /// (c): a learn push that merged the round's object with a neighbour, as the robot sees it
  /// (session 27; merged_by_growth: the look after the push shows fewer blobs than the look
  /// before, and the pushed object's blob holds at least this many times its feature points
  /// before), gives no training views and the round stops (logged, fault "grown"; its unspent
  /// pushes go to the next round with carry_budget): the class is not trained on a blob of two
  /// objects, and the round does not drift onto the neighbour. Session 26 (report seeds 2-6,
  /// ground truth): 9 of the defaults' 12 drifts were the chosen object and a neighbour
  /// becoming one blob, 7 right after a learn push that moved both. The same test in (b): a
  /// clearing push that pushed a neighbour into the chosen object (its blob grown by the ratio
  /// while the blobs fell, as on tuning seed 1: 128 -> 398, 100 -> 231 features) makes the object
  /// count as lost, and the round chooses again (fault "grown"). 0: off (the default);
  /// otherwise more than 1. Session 27 with 1.5: tuning seed 1 c 37.2 -> 53.8%, report seeds
  /// 2-6 33.6 +- 13.9% -> 31.5 +- 15.0% (paired -2.1 +- 3.8 points; it fired on 2 seeds, both in
  /// (b)): off (docs/results/selfsupervision-history.md, "Session 27").
  double merge_ratio = 0.0;
  /// (b) -> (c): after (b), before the first learn push, the robot looks again and checks the
  /// chosen blob against the classes learned so far (session 34; choose_unlearned on that look:
  /// each learned class claims the blob nearest its looks, one blob a class). When a class
  /// claims the chosen blob (a clearing push moved that class's object into it, or the blob
  /// tracked is now that object) and some scored blob is unclaimed (recheck_claimed), the round
  /// chooses again from that look (the unclaimed blob farthest from the classes, 7.2 d) and
  /// clears it, at most this often a round (logged, event "recheck"). Session 33's coverage
  /// trace: each tuning seed spent one of its 4 rounds on an object already learned, two of
  /// the three after a clearing push merged a learned neighbour into the chosen blob. 0: off
  /// (the default); needs choice looks. Off: with 2 on tuning seeds 1, 7, 8 it never chose again
  /// (9 checks: the chosen blob unclaimed, or every blob claimed), the runs identical to the
  /// defaults; the looks' claims were right for 6 of 18 claims (4.5 at random)
  /// (docs/results/selfsupervision.md, "Session 34").
  int recheck_tries = 0;
  /// (d) (choice looks): what the learned classes' claims judge each blob against (session 35).
  /// kLooks (the default): each class's looks, the thetas of its tracked blob in its round's
  /// looks (choose_unlearned); they were right for 6 of 18 claims on tuning seeds 1, 7, 8 (4.5
  /// at random), as a class's looks are of another object whenever its round drifted.
  /// kViewWords: each class's views, the words of the pushed object's masks in its learn
  /// pushes' frames (what the class learned), pooled into one multinomial a class; a blob's
  /// distance is minus its words' mean log-likelihood ratio, that class against the look's
  /// blobs pooled (choose_unlearned_by_words). kLookWords: the looks of kLooks, but their words
  /// pooled a class and judged as kViewWords judges; kFirstLookWords: only each class's first
  /// look. Needs choice looks. Session 35 (tuning seeds 1, 7, 8): view-words, look-words and
  /// first-look-words right for 7, 6 and 5 of 18 claims, no better than the looks' thetas on the
  /// same looks; look-words learned more objects (10 of 12, 8 by default) but c fell on every
  /// seed (docs/results/selfsupervision.md, "Session 35"). kLooks stays the default.
  /// kDescriptors (session 36): each class's SIFT descriptors from the same looks, a blob's
  /// distance minus the share of its descriptors whose match passes Lowe's ratio test in that
  /// class (choose_unlearned_by_descriptors; descriptor_ratio, descriptor_min_share,
  /// descriptor_cap). Session 36 (tuning seeds 1, 7, 8): right for 3 of 15 claims (looks) and
  /// 3 of 16 (first-look), below chance and the looks' thetas on the same looks (7 of 18);
  /// coverage and c fell (docs/results/selfsupervision.md, "Session 36"). kLooks stayed.
  /// kColour (session 41, the default): the looks' pixel colours. On fresh seeds 11-30 (rule
  /// docs/results/selfsupervision/rule-s41-claims-colour.md) the objects with a class rose from
  /// 2.65 to 3.10 of 4 (paired +0.45 +- 0.41), c 31.4 -> 33.1 % (+1.8 +- 4.7, lower on 9 of 20);
  /// on the same looks its claims were right for 73 of 120 against the thetas' 46. With choice
  /// dirichlet no claims are made: claims_by must then stay at this default.
  ClaimSignal claims_by = ClaimSignal::kColour;
  /// A diagnostic (choice looks): the claims of another signal on the same looks, logged as
  /// each scored blob's other_claimed_by, so that two signals are compared on the same looks.
  /// kNone (the default): not computed (session 35 computed the views' words on every choice;
  /// session 36 made it asked for). Not claims_by itself, and not look-words with
  /// first-look-words (they keep the same counts).
  ClaimSignal other_claims_by = ClaimSignal::kNone;
  /// claims_by descriptors: Lowe's ratio. A blob's descriptor matches class c when its nearest
  /// descriptor of c is nearer than this times its nearest descriptor of every other object:
  /// the other classes and the look's other blobs (Lowe 2004, 7.1: the second neighbour taken
  /// from another object, as a class holds many looks of its own object).
  double descriptor_ratio = 0.8;
  /// claims_by descriptors: a class claims a blob only when at least this share of the blob's
  /// descriptors match it (below, the class claims nothing: the matching counts such a pair as
  /// no claim).
  double descriptor_min_share = 0.05;
  /// claims_by descriptors: at most this many descriptors a class keeps (over the cap, evenly
  /// spaced rows of all its looks' descriptors are kept; a look has about 100-400).
  int descriptor_cap = 2000;
  /// claims_by descriptors: a class's descriptors from its looks (the default), its first look
  /// only, or its views.
  DescriptorSource descriptor_source = DescriptorSource::kLooks;
  /// (a)-(d): more rounds than objects, merged by the robot's own judgement (session 31). The
  /// robot runs up to this many rounds (0: C rounds, the default; otherwise at least C), each
  /// round a candidate class with its own views. After each round from the C-th on it groups
  /// the round classes by their own similarity (merge_rounds on their views' word counts: two
  /// round classes nearer than same_object are one object; or on their looks' colours,
  /// same_object_by and same_colour) and stops when it judges that C
  /// distinct objects are learned, or when the rounds run out; (d) chooses by the groups' looks
  /// (a group claims one blob), so an object learned twice is not chosen a third time. At the
  /// end the round classes are merged into C classes (the nearest first; every merge logged,
  /// event "merge"). Learning::round_class says which class each round became. Off: on tuning
  /// seeds 1, 7, 8 (--rounds 8 --same-object 1.0) c fell 5.2 +- 11.9 points: the word-count
  /// distance does not separate one object's rounds from different objects'
  /// (docs/results/selfsupervision-history.md, "Session 31").
  int rounds = 0;
  /// rounds: two round classes are one object when their distance (round_distance) is below
  /// this, nats a word.
  double same_object = 0.3;
  /// rounds: the judgement's signal, the views' words (the default) or the looks' pixel colours
  /// (then same_colour is the bound and each round's looks keep their colours). Needs rounds.
  /// Not the default: on fresh seeds 103-122, --rounds 8 --same-object-by colour --same-colour
  /// 0.35 pushed all four objects in some round on every seed, but grouped the rounds wrongly
  /// on 7 of 20 (objects with a class +0.05 +- 0.28, c -0.4 +- 6.4, wall time +114 %;
  /// docs/results/selfsupervision.md, "Session 44").
  RoundSimilarity same_object_by = RoundSimilarity::kWords;
  /// rounds with same_object_by colour: two round classes are one object when the Hellinger
  /// distance of their looks' pooled colour histograms (colour_round_distance) is below this.
  double same_colour = 0.3;
  ViewSource views = ViewSource::kMotion;
  /// (d): kLooks (the default since 2026-12-03: with kDirichlet the calculator was never pushed
  /// in a learn round on 4 of 5 report seeds, docs/results/selfsupervision-history.md) or
  /// kDirichlet.
  NextObjectRule choice = NextObjectRule::kLooks;
  int view_step = 2;  ///< kMotion: every n-th frame from the first touch
  /// kMotion: cut the arm's own image (its kinematics at each frame's joints) out of the views.
  bool cut_arm = true;
  /// kMotion: also leave out of the views every feature whose patch (features.dense.size px
  /// square) reaches the arm's own image (its kinematics at the frame's joints, as cut_arm):
  /// cut_arm takes the arm's pixels out of the mask, but the patches of the object's pixels
  /// beside the arm still describe the arm (docs/results/selfsupervision-history.md, "Session 28").
  /// Scoring: the ladder's a and a_last rungs then leave out the patches reaching the arm's
  /// ground-truth pixels.
  bool arm_patches_out = false;
  int min_features = 15;   ///< a view needs this many features (else left out, logged)
  int dilate = 4;          ///< masks grown by this many pixels (features on the outline count)
  double fps = 15;         ///< frame rate of the pushes' episodes
  std::uint64_t seed = 1;  ///< (a)'s choice, the planner's paths, the re-scatters
  int width = 320;         ///< image size of the simulated camera, px
  int height = 240;
  int held_out = 100;  ///< held-out views per object (yaw stepped through 360 degrees)
  /// Scoring (simulated table): also the oracle ladder (SelfSupervisionScore::ladder): the
  /// Mixture of Topics trained on held-out-like renders, on ground-truth masks of the pushed
  /// objects in the push frames, on the robot's views with ground-truth labels. The pushes'
  /// episodes then carry ground-truth masks (never read by the learner).
  bool oracle_ladder = false;
  /// Scoring, with oracle_ladder: also the ladder's probes, each push's last frame against a
  /// render of the object alone in the same pose with one thing changed at a time (the arm's or
  /// the other objects' pixels replaced by the render's, the masks swapped, features whose
  /// patch reaches the arm left out), as rungs p_*, and OracleLadder::probe_names/values.
  bool ladder_probes = false;
  /// Scoring: the classifier of the held-out figure (mot_accuracy, the confusion, the ladder's
  /// c). The learner's own choices (d) use theta either way.
  MotClassifier mot_classifier = MotClassifier::kTheta;
  /// kPooled: the weight of the word multinomials (0: the MoT by words alone, 1: naive Bayes on
  /// the words with the MoT's prior). 0.25 was chosen on the scatter videos' tuning seeds.
  double mot_word_weight = 0.25;
  /// Scoring: also score c and every ladder rung by the pooled words classifier at the weights
  /// kPooledWeights, and c with each push's views counted once (SelfSupervisionScore::pooled),
  /// on the same run as the theta figures (a paired comparison).
  bool pooled_score = false;
  /// Scoring, with oracle_ladder: also the own-model rungs (a0_own, a_own, b_own, c_own: the
  /// training views of a0, a, b and c; a_up and a_up_own: a's views whose object stood upright
  /// after its push, by the run's model and an own one): each rung's views through a vocabulary of
  /// own_words words and an LDA model of own_topics topics built from those views' own descriptors
  /// (loop::views_vocabulary, views_lda: as Experiment 8.2 builds its own from its push views,
  /// docs/results/learn-history.md), a supervised Mixture of Topics (mot) on their theta, and the
  /// held-out views classified by the pooled words classifier at mot_word_weight with per-view word
  /// multinomials (loop::per_view_weights: Experiment 8.2's default). The learner then keeps its
  /// views' descriptors (TrainingViews::descriptors). The run itself is unchanged.
  bool own_model_rungs = false;
  int own_words = 200;  ///< own_model_rungs: vocabulary words (Experiment 8.2's, learn's)
  int own_topics = 20;  ///< own_model_rungs: LDA topics (Experiment 8.2 scores T >= 15)
  /// Scoring only: skip the robot and score the ladder's render rungs (a0, a0_table) alone, the
  /// ceiling the vocabulary and LDA model set, in seconds instead of a run's minutes (to tune
  /// them without a robot run; the other rungs are then empty, the run learns nothing).
  bool ceiling_only = false;
  /// The robot's camera is an RGB-D one (sim::TableOptions::depth, robot::Look::depth): the
  /// planner measures each blob's footprint and height from depth (descent check by height).
  bool depth = false;
  /// Pushes that would tip the pushed object over are not taken (planning::PushPlanOptions::
  /// topple_ratio, judged from its depth points: where the pusher and the hand meet it first
  /// against how far its foot reaches ahead): a learn push tries the other sides instead. Turns
  /// the RGB-D camera on (as `depth`). 0 (the default): off. Session 29: the giraffe and the bike
  /// toppled in nearly every push.
  double topple_ratio = 0;
  /// With topple_ratio: a tipping push is tried with the jaws across, then shifted sideways by up
  /// to this (planning::PushPlanOptions::topple_offset), m. 0 (the default): neither.
  double topple_offset = 0;
  std::filesystem::path out;  ///< output directory (required by run_self_supervision)
  bool overwrite = false;
  bool progress = true;  ///< a progress bar on stderr (not an option: the CLI's --quiet)
  /// How documents' features are extracted: must be how the vocabulary and model were made.
  features::ExtractOptions features;
  /// Every document made with the given vocabulary (the views', the looks' blobs' for (d)'s
  /// claims, the held-out views') carries a colour word a feature after its SIFT word
  /// (features::document_words on `colour`: the patch's mean colour on a fixed HSV grid, 28
  /// words), so the LDA model must have the vocabulary's words + 28 (`proprio recognize train
  /// --colour-words`). Off (the default): SIFT words only, as the thesis. `proprio learn
  /// --colour-words` sets it for its scoring. validate() refuses it with the oracle ladder and
  /// the own-model rungs, whose documents are SIFT words only. Scoring: c is then also scored by
  /// the colour words alone (SelfSupervisionScore::colour_accuracy, beside the theta figure). A
  /// model made with `recognize train --colour-weight K` weighs its colour words K times in every
  /// document it reads (topics::LdaModel::word_weights): theta, so the Mixture of Topics, the
  /// claims' and the held-out views'; the documents themselves count each once.
  bool colour_words = false;
  /// colour_words is turned on when the LDA model has the vocabulary's words and the colour words
  /// after them (a model made with `recognize train --colour-words`), so such a model is read as
  /// it was made; a model of the vocabulary's words alone keeps SIFT words only (resolved when
  /// the inputs are read: the run's record says which). Measured in session 42 (fresh seeds
  /// 51-70, docs/results/selfsupervision.md "Session 42"). Off: a colour model needs
  /// --colour-words, as before.
  bool colour_words_from_model = true;
  features::ColourWordOptions colour;  ///< colour_words and claims by colour: the grid (not a flag)
  /// The colour words of the documents (colour_words: `colour`), or none.
  [[nodiscard]] std::optional<features::ColourWordOptions> document_colour() const {
    return features::colour_if(colour_words, colour);
  }
  /// The planner's options; descent_clearance 0.04 m (paths whose arm would come down on a
  /// blob are not planned: every refused transit of the report seeds was that).
  planning::PushPlanOptions plan = descent_checked();
  segmentation::MlOptions segmentation;
  /// The Mixture of Topics: up to 3 Dirichlets per object (their number chosen by BIC), not the
  /// thesis's one. Session 14: on renders of each object alone (the ladder's a0 rung,
  /// `--ceiling-only`, tuning seed 1), T = 8 LDA models of seeds 1-3: one Dirichlet 71.7%
  /// (76.2, 66.8, 72.2), up to 3 81.8% (79.0, 80.2, 86.2), better on every model: an object's
  /// views from all round are not one cluster in topic space
  /// (docs/results/selfsupervision-history.md).
  topics::MotOptions mot = three_components();

  /// Throws Error naming the first bad option (bounds, an empty, unknown or repeated object is
  /// checked by the world that gets the names).
  void validate() const;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.objects, {"objects", "Objects on the table, catalogue names, comma-separated"});
    v(self.lda_model, {"model", "LDA model file (T topics)"});
    v(self.vocabulary, {"vocabulary", "Its visual vocabulary"});
    v(self.pushes, {"pushes", "Pushes of each chosen object (7.2 c)", core::between(1, 1000)});
    v(self.clear_pushes, {"clear_pushes", "Most pushes to clear the others per round (7.2 b)",
                          core::between(0, 1000)});
    v(self.clearance,
      {"clearance", "Gap that makes the chosen object alone, m", core::between(0.01, 0.5)});
    v(self.circle_radius,
      {"circle_radius", "Radius of the circle of push targets, m", core::between(0.02, 0.3)});
    v(self.turn_offset,
      {"turn_offset", "Learn pushes' sideways offset, of the half width (0: none)",
       core::between(-0.9, 0.9)});
    v(self.carry_budget, {"carry_budget", "Unspent learn pushes of a round go to later rounds"});
    v(self.refind_margin,
      {"refind_margin", "Re-find the object by its looks by this margin (0: off)",
       core::between(0.0, 1.0)});
    v(self.refind_colour,
      {"refind_colour",
       "A lost object is found again by its looks' pixel colours within this Hellinger distance "
       "(0: off)",
       core::between(0.0, 1.0)});
    v(self.colour_first_look,
      {"colour_first_look", "A round's colours (claims by colour) from its first look only"});
    v(self.moved_colours,
      {"moved_colours",
       "A round's colours (claims by colour) from the pixels its learn pushes moved"});
    v(self.colour_by_look,
      {"colour_by_look",
       "Claims by colour: a blob's distance to a class is its least to any one of its looks"});
    v(self.table_colours_out,
      {"table_colours_out", "Claims by colour: leave the table's own colour words out"});
    v(self.learn_clearance,
      {"learn_clearance",
       "Learn pushes keep their object's corridor this far from other blobs, m (0: off)",
       core::between(0.0, 0.2)});
    v(self.crowded_reclears,
      {"crowded_reclears",
       "learn_clearance: a round stopped crowded clears the others again and goes on, this often "
       "(0: off)",
       core::between(0, 10)});
    v(self.stop_on_drift,
      {"stop_on_drift", "Stop a round when its push moved another blob most or merged it"});
    v(self.alone_views,
      {"alone_views", "Views only from pushes that moved the round's object alone"});
    v(self.moved_share, {"moved_share", "Share of a blob's features that changed: it moved",
                         core::between(0.01, 1.0)});
    v(self.inward_sides,
      {"inward_sides", "Learn pushes' fallback sides go toward the work centre, never away"});
    v(self.free_space,
      {"free_space",
       "Push the chosen object into free space within this radius of the work centre, m (0: off)",
       core::between(0.0, 0.3)});
    v(self.split_merged,
      {"split_merged",
       "Split the largest blob by k-means while fewer blobs than objects are seen"});
    v(self.split_colour, {"split_colour", "split_merged: the colours' weight against the positions",
                          core::between(0.0, 10.0)});
    v(self.singulate_tries,
      {"singulate_tries", "Start (b) again this many times until the chosen object is alone",
       core::between(0, 10)});
    v(self.alone_by_depth,
      {"alone_by_depth",
       "(b)'s check from depth footprints and their gaps (turns the RGB-D camera on)"});
    v(self.switch_tries,
      {"switch_tries",
       "When (b) cannot singulate the chosen object, choose the most isolated other, this often",
       core::between(0, 5)});
    v(self.repeat_tries,
      {"repeat_tries",
       "When a round's first views are already explained by a learned class, choose again, "
       "this often (0: off)",
       core::between(0, 5)});
    v(self.repeat_share, {"repeat_share", "repeat_tries: share of the views a class must explain",
                          core::between(0.01, 1.0)});
    v(self.repeat_later,
      {"repeat_later",
       "Stop a round when a later push's views are already explained by a learned class"});
    v(self.merge_ratio,
      {"merge_ratio",
       "Stop a round, without the push's views, when a learn push left fewer blobs and its "
       "object's blob this many times larger (0: off)",
       core::between(0.0, 100.0)});
    v(self.recheck_tries,
      {"recheck_tries",
       "After (b), choose again when a learned class claims the chosen blob, this often (0: "
       "off)",
       core::between(0, 5)});
    v.choice(self.claims_by,
             {"claims_by",
              "(d)'s claims judge a blob against each class's looks (thetas), their words "
              "(look-words), its first look's words (first-look-words), its views' words "
              "(view-words), its looks' descriptors (descriptors) or its looks' pixel colours "
              "(colour)"},
             kClaimSignalNames);
    v.choice(self.other_claims_by,
             {"other_claims_by",
              "A diagnostic: another claim signal's claims on the same looks, logged as "
              "other_claimed_by (none: not computed)"},
             kClaimSignalNames);
    v(self.descriptor_ratio,
      {"descriptor_ratio",
       "claims-by descriptors: Lowe's ratio (nearest in the class against the nearest of every "
       "other object)",
       core::between(0.1, 1.0)});
    v(self.descriptor_min_share,
      {"descriptor_min_share",
       "claims-by descriptors: the least share of a blob's descriptors matching a class for it "
       "to claim the blob",
       core::between(0.0, 1.0)});
    v(self.descriptor_cap,
      {"descriptor_cap", "claims-by descriptors: at most this many descriptors a class keeps",
       core::between(10, 100000)});
    v.choice(self.descriptor_source,
             {"descriptor_source",
              "claims-by descriptors: a class's descriptors from its looks (its tracked blob), "
              "its first look only (first-look) or its views (its training views' masks)"},
             kDescriptorSourceNames);
    v(self.split_by_motion,
      {"split_by_motion", "Split blobs by each learn push's motion segmentation (views motion)"});
    v(self.rounds,
      {"rounds",
       "Rounds at most, merged into C classes by the robot's own similarity (0: C rounds)",
       core::between(0, 64)});
    v(self.same_object,
      {"same_object", "rounds: two round classes nearer than this (nats a word) are one object",
       core::between(0.0, 10.0)});
    v.choice(self.same_object_by,
             {"same_object_by",
              "rounds: rounds judged one object by their views' words or their looks' colours"},
             kRoundSimilarityNames);
    v(self.same_colour,
      {"same_colour",
       "rounds, same-object-by colour: two rounds' looks nearer than this (Hellinger) are one "
       "object",
       core::between(0.0, 1.0)});
    v.choice(self.views, {"views", "Training views: motion (M-L segmentation) or blob"},
             kViewSourceNames);
    v.choice(self.choice,
             {"choice", "Next object (7.2 d): looks (one blob a learned class) or dirichlet"},
             kNextObjectRuleNames);
    v(self.view_step, {"view_step", "Motion views: every n-th frame", core::between(1, 1000)});
    v(self.cut_arm, {"cut_arm", "Motion views: cut the arm's own image out"});
    v(self.arm_patches_out, {"arm_patches_out",
                             "Motion views: leave out the features whose patch reaches the arm's "
                             "own image"});
    v(self.min_features, {"min_features", "Features a view needs", core::between(1, 100000)});
    v(self.colour_words,
      {"colour_words",
       "Documents carry a colour word a feature (its patch's mean colour, 28 HSV words) after "
       "its SIFT word; the model needs the vocabulary's words + 28 (recognize train "
       "--colour-words); off: SIFT words only (the thesis)"});
    v(self.colour_words_from_model,
      {"colour_words_from_model",
       "Colour words on when the model has the vocabulary's words + 28 (a model made with "
       "recognize train --colour-words)"});
    v(self.dilate, {"dilate", "Grow the masks by this many px", core::between(0, 100)});
    v(self.fps, {"fps", "Frame rate of the push episodes", core::positive_at_most(100)});
    v(self.seed, {"seed", "Seed of the table, choices, paths and re-scatters"});
    v(self.width, {"width", "Image width, px", core::between(64, 4096)});
    v(self.height, {"height", "Image height, px", core::between(48, 4096)});
    v(self.held_out, {"held_out", "Held-out views per object", core::between(1, 100000)});
    v(self.oracle_ladder,
      {"oracle_ladder", "Also score the oracle ladder (ground-truth masks and labels)"});
    v(self.ladder_probes,
      {"ladder_probes", "With oracle_ladder: also probe push frames against renders (p_* rungs)"});
    v.choice(self.mot_classifier,
             {"mot_classifier",
              "Held-out figure's classifier: theta (eq 7.3), pooled (words + multinomials) or "
              "colour (the colour words alone; needs colour_words)"},
             kMotClassifierNames);
    v(self.mot_word_weight, {"mot_word_weight", "Pooled classifier: weight of the multinomials",
                             core::between(0.0, 1.0)});
    v(self.pooled_score,
      {"pooled_score", "Also score c and the ladder by the pooled words classifier"});
    v(self.own_model_rungs,
      {"own_model_rungs",
       "With oracle_ladder: also the rungs a0_own, a_own, b_own, c_own, a_up, a_up_own "
       "(vocabulary and LDA from each rung's own views, pooled per-view words classifier)"});
    v(self.own_words, {"own_words", "own_model_rungs: vocabulary words", core::between(2, 100000)});
    v(self.own_topics, {"own_topics", "own_model_rungs: LDA topics", core::between(2, 1000)});
    v(self.ceiling_only,
      {"ceiling_only", "No robot run: score only the ladder's renders (a0, a0_table)"});
    v(self.depth, {"depth",
                   "An RGB-D camera: plan from each blob's footprint and height "
                   "measured from depth"});
    v(self.topple_ratio,
      {"topple_ratio",
       "Depth: pushes whose first contact would tip the object (friction x contact height / its "
       "foot's reach above this) are not taken; turns the RGB-D camera on (0: off)",
       core::between(0.0, 10.0)});
    v(self.topple_offset,
      {"topple_offset",
       "With topple_ratio: a tipping push is tried with the jaws across, then shifted sideways by "
       "up to this to meet a low part, m (0: neither)",
       core::between(0.0, 0.05)});
    v(self.mot.components,
      {"mot_components", "Mixture of Topics: Dirichlets per object at most (1: the thesis's)",
       core::between(1, 10)});
    v(self.mot.shared_precision,
      {"mot_shared_precision", "Mixture of Topics: one precision shared by every object"});
    v(self.mot.smoothing,
      {"mot_smoothing",
       "Mixture of Topics: theta smoothing s, (1 - s) theta + s / T before the log (0: off)",
       core::Bounds{0, 0.5, false}});
    v(self.out, {"out", "Output directory: episodes, decision log, model, results"});
    v(self.overwrite, {"overwrite", "Replace an existing output directory"});
  }
};

/// The objects named in `list` (comma-separated, blanks trimmed). Throws Error for an empty list,
/// an empty or repeated name.
std::vector<std::string> parse_object_list(const std::string& list);

/// What the learner tells the attendant about a push.
struct PushIntent {
  int round = 0;
  std::string phase;  ///< "clear" (7.2 b) or "learn" (7.2 c)
  int index = 0;      ///< push of the round (both phases counted)
  /// The look before the push, the planning view and the blob pushed.
  const planning::PlanningView* view = nullptr;
  int blob = -1;
  const planning::PushPlan* plan = nullptr;
};

/// The person at the table (7.2 d: re-scatters the objects when asked) and, in simulation, the
/// scorer: the learner calls it, and never reads anything back but the re-scatter's log line.
class TableAttendant {
 public:
  TableAttendant() = default;
  TableAttendant(const TableAttendant&) = delete;
  TableAttendant& operator=(const TableAttendant&) = delete;
  TableAttendant(TableAttendant&&) = delete;
  TableAttendant& operator=(TableAttendant&&) = delete;
  virtual ~TableAttendant() = default;

  /// Re-scatters the objects before round `round` (>= 1); returns a line for the log.
  virtual std::string rescatter(int round) = 0;
  /// (a)/(d): the learner chose blob `blob` of `view` to learn as class `round`.
  virtual void chose(int /*round*/, const planning::PlanningView& /*view*/, int /*blob*/) {}
  /// Before and after each executed push (after: `executed` false when the robot refused).
  virtual void before_push(const PushIntent& /*intent*/) {}
  virtual void after_push(const PushIntent& /*intent*/, bool /*executed*/) {}
  /// (b) ended: `view` is the look then, `blob` the chosen object in it (-1: lost).
  virtual void cleared(int /*round*/, const planning::PlanningView& /*view*/, int /*blob*/) {}
  /// A learn push gave `views` training views of class `round`; `last_mask` (CV_8U, image
  /// size) is the learner's mask of the object in the push's last view frame (empty: none).
  virtual void views_taken(const PushIntent& /*intent*/, int /*views*/,
                           const cv::Mat& /*last_mask*/) {}
  /// One training view of the push `intent` (called before views_taken, once per view, in the
  /// order the views enter TrainingViews): frame `frame` of the push's episode `episode`, or
  /// (empty episode, frame -1) the look after the push; `mask` (CV_8U, image size, not grown)
  /// is the learner's mask of the object in it. For scoring (the oracle ladder) only.
  virtual void view_taken(const PushIntent& /*intent*/, const std::filesystem::path& /*episode*/,
                          int /*frame*/, const cv::Mat& /*mask*/) {}
};

/// One training view: its document's theta and its class (the round that took it).
struct TrainingViews {
  Eigen::MatrixXd theta;    ///< views x T, E[theta] of each view's document
  std::vector<int> labels;  ///< class of each view (0..C-1)
  std::vector<int> push;    ///< the push of its round that took it
  std::vector<int> tokens;  ///< its document's length
  /// Each view's document (its words, the same rows as theta): the pooled words classifier's
  /// training data (SelfSupervisionOptions::mot_classifier, pooled_score).
  topics::Corpus words;
  /// SelfSupervisionOptions::own_model_rungs: each view's descriptors (the same rows as theta;
  /// empty otherwise), from which the ladder's own-model rungs build their vocabulary.
  std::vector<cv::Mat> descriptors;
};

/// A plan as the decision log lists it (the path and its cost only when it was planned).
struct LoggedPlan {
  planning::PlanOutcome outcome = planning::PlanOutcome::kNoObjects;
  std::string message;
  int blob = -1;
  Eigen::Vector2d start = Eigen::Vector2d::Zero();  ///< table m
  Eigen::Vector2d end = Eigen::Vector2d::Zero();
  Eigen::Vector2d target = Eigen::Vector2d::Zero();
  double cost = 0;

  [[nodiscard]] static LoggedPlan of(const planning::PushPlan& p) {
    return {p.outcome, p.message, p.object, p.push.start, p.push.end, p.target, p.cost};
  }

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v.choice(self.outcome, {"outcome", "How planning ended"}, planning::kPlanOutcomeNames);
    v(self.message, {"message", "What the planner said"});
    v(self.blob, {"blob", "The blob pushed"});
    if (self.outcome != planning::PlanOutcome::kPlanned) return;
    v(xy(self.start), {"start", "The pusher's start, table m"});
    v(xy(self.end), {"end", "The pusher's end, table m"});
    v(xy(self.target), {"target", "The object's target, table m"});
    v(self.cost, {"cost", "Feature density along the path (eq 7.5)"});
  }
};

/// (d)'s score of a blob: its best log score under the classes learned so far.
struct BlobScore {
  int blob = 0;
  double best_log_score = 0;
  std::optional<double> nearest = {};     ///< kLooks: Hellinger distance to the nearest class
  std::optional<int> nearest_class = {};  ///< kLooks: that class (0..C-1)
  std::optional<int> claimed_by = {};     ///< kLooks: the class that claimed it, -1 none
  /// kLooks, a diagnostic: the class claiming it by another claim signal than the one in use
  /// (claims_by; the views' words when claims are by looks, else the looks' thetas), -1 none;
  /// absent when that signal has no class yet.
  std::optional<int> other_claimed_by = {};

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.blob, {"blob", "The blob"});
    v(self.best_log_score, {"best_log_score", "max over c of log Dir(theta | omega_c) + log p(c)"});
    v(self.nearest, {"nearest", "Hellinger distance to the nearest class's looks"});
    v(self.nearest_class, {"nearest_class", "That class"});
    v(self.claimed_by, {"claimed_by", "The class that claimed the blob (-1 none)"});
    v(self.other_claimed_by,
      {"other_claimed_by", "The class claiming it by another claim signal (-1 none)"});
  }
};

/// One line of the decision log (decisions.jsonl): an event and the fields it has (the others are
/// left out). Events: start, rescatter, look, choose, singulated, plan, push, motion, replan,
/// refound, colours (moved_colours), views, fault, judge, distance, merge, recheck, end.
struct SelfSupervisionDecision {
  std::string event = {};
  std::optional<int> round = {};          ///< the round (class) it belongs to
  std::optional<std::string> phase = {};  ///< "choose", "clear" (7.2 b) or "learn" (7.2 c)
  std::optional<int> index = {};          ///< push of the round
  std::optional<int> blob = {};           ///< the blob chosen, planned or pushed
  std::optional<int> chosen = {};         ///< look: the chosen object's blob
  std::optional<int> too_near = {};       ///< look: blobs nearer than the clearance
  std::optional<int> clear_pushes = {};   ///< singulated: pushes it took
  std::optional<double> gap = {};         ///< plan (clear): the blob's gap to the chosen one, m
  std::optional<LoggedPlan> plan = {};
  std::optional<std::string> then = {};  ///< plan (learn): what comes next
  std::optional<bool> executed = {};     ///< push: the robot executed it
  std::optional<std::string> message = {};
  std::optional<std::string> episode = {};  ///< push: its episode (a name under episodes/), or ""
  std::optional<std::string> why = {};
  std::optional<std::vector<BlobScore>> scores = {};  ///< choose (7.2 d)
  std::optional<std::string> what = {};               ///< rescatter: the attendant's line
  std::optional<std::string> fault = {};              ///< fault: its kind
  std::optional<double> extra_approach = {};          ///< replan: the approaches' growth, m
  std::optional<std::vector<PutativeObjectRecord>> blobs = {};  ///< look: the putative objects
  std::optional<std::string> source = {};        ///< views: "motion", "blob" or "both"
  std::optional<std::string> segmentation = {};  ///< views (motion): the segmentation's message
  std::optional<int> frames = {};                ///< views (motion): frames of the episode
  std::optional<int> first_touch = {};           ///< views (motion): first frame used
  /// views (motion): views taken (both: with the look before's copies); end: all training views
  std::optional<int> views = {};
  std::optional<int> too_few_features = {};  ///< views (motion): frames left out
  std::optional<int> push = {};              ///< views: the learn push of the round
  std::optional<int> taken = {};             ///< views: training views it gave
  std::optional<int> classes = {};           ///< start: C; judge: the distinct objects judged
  std::optional<int> topics = {};            ///< start: the LDA model's T
  std::optional<int> words = {};             ///< start: the vocabulary's size
  std::optional<std::vector<double>> work_centre = {};  ///< start; hub (free_space): table m
  std::optional<int> pushes_clear = {};                 ///< end
  std::optional<int> pushes_learn = {};                 ///< end
  std::optional<int> faults = {};                       ///< end
  std::optional<double> seconds = {};                   ///< end: wall clock, s
  std::optional<double> offset = {};  ///< push (learn): the turning offset, m (turning_push)
  /// motion (learn): per blob of the look before the push, the share of its features that
  /// changed (push_motion)
  std::optional<std::vector<double>> shares = {};
  std::optional<int> moved_most = {};   ///< motion: the blob that moved most (-1: none moved)
  std::optional<int> merged_with = {};  ///< motion: the blob of the look before it merged with
  std::optional<double> lack = {};      ///< plan (learn): the corridor's lack of clearance, m
  /// merge: the two groups' distance; distance: the two rounds', by the judgement's signal
  /// (same_object_by: nats a word, or Hellinger of the looks' colours)
  std::optional<double> distance = {};
  std::optional<std::vector<int>> merged = {};  ///< merge, distance: the rounds (0-based)
  /// distance (a diagnostic beside the judgement's): the two rounds' views' words
  /// (round_distance, nats a word), their views' colour words alone (round_distance on the
  /// documents' colour words; colour words on) and their looks' colours (colour_round_distance;
  /// when the looks keep colours)
  std::optional<double> word_distance = {};
  std::optional<double> view_colour_distance = {};
  std::optional<double> look_colour_distance = {};
  /// colours (moved_colours): the pixels the push moved (moved_pixels, in the blob before and the
  /// blob after it), whose colours were added to the round's colours
  std::optional<int> moved_pixels = {};

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.event, {"event", "What happened"});
    v(self.round, {"round", "The round (class)"});
    v(self.phase, {"phase", "choose, clear or learn"});
    v(self.index, {"index", "Push of the round"});
    v(self.blob, {"blob", "The blob"});
    v(self.chosen, {"chosen", "The chosen object's blob"});
    v(self.too_near, {"too_near", "Blobs nearer than the clearance"});
    v(self.clear_pushes, {"clear_pushes", "Pushes the clearing took"});
    v(self.gap, {"gap", "Gap to the chosen object, m"});
    v(self.plan, {"plan", "The plan"});
    v(self.then, {"then", "What comes next"});
    v(self.executed, {"executed", "The robot executed the push"});
    v(self.message, {"message", "What happened, in words"});
    v(self.episode, {"episode", "The push's episode"});
    v(self.why, {"why", "Why"});
    v(self.scores, {"scores", "Each scored blob"});
    v(self.what, {"what", "The re-scatter"});
    v(self.fault, {"fault", "The fault's kind"});
    v(self.extra_approach, {"extra_approach", "Growth of the approaches, m"});
    v(self.blobs, {"blobs", "The putative objects"});
    v(self.source, {"source", "Where the views came from"});
    v(self.segmentation, {"segmentation", "The segmentation's message"});
    v(self.frames, {"frames", "Frames of the episode"});
    v(self.first_touch, {"first_touch", "First frame used"});
    v(self.views, {"views", "Views"});
    v(self.too_few_features, {"too_few_features", "Frames with too few features"});
    v(self.push, {"push", "The learn push of the round"});
    v(self.taken, {"taken", "Training views taken"});
    v(self.classes, {"classes", "Classes C"});
    v(self.topics, {"topics", "Topics T"});
    v(self.words, {"words", "Vocabulary size"});
    v(self.work_centre, {"work_centre", "Centre of the work area, table m"});
    v(self.pushes_clear, {"pushes_clear", "Executed pushes in (b)"});
    v(self.pushes_learn, {"pushes_learn", "Executed pushes in (c)"});
    v(self.faults, {"faults", "Logged faults"});
    v(self.seconds, {"seconds", "Wall clock, s"});
    v(self.offset, {"offset", "Turning offset of the push, m"});
    v(self.shares, {"shares", "Per blob, the share of its features that changed"});
    v(self.moved_most, {"moved_most", "The blob that moved most (-1: none)"});
    v(self.merged_with, {"merged_with", "The blob the pushed one merged with"});
    v(self.lack, {"lack", "The corridor's lack of clearance from other blobs, m"});
    v(self.distance, {"distance", "The merged groups' distance by the judgement's signal"});
    v(self.merged, {"merged", "The rounds merged into one class"});
    v(self.word_distance, {"word_distance", "The two rounds' views' words' distance, nats"});
    v(self.view_colour_distance,
      {"view_colour_distance", "The two rounds' views' colour words' distance, nats"});
    v(self.look_colour_distance,
      {"look_colour_distance", "The two rounds' looks' colours' Hellinger distance"});
    v(self.moved_pixels,
      {"moved_pixels", "The pixels the push moved, added to the round's colours"});
  }
};

/// What the learner did and learned.
// NOLINTNEXTLINE(bugprone-exception-escape)
struct Learning {
  int classes = 0;                       ///< C
  std::vector<std::string> class_names;  ///< object_1 .. object_C
  TrainingViews views;
  std::vector<int> views_per_class;
  topics::MotModel model;  ///< the self-supervised Mixture of Topics (classes with >= 2 views)
  std::vector<int> model_class;  ///< the class of each model object
  int pushes_clear = 0;          ///< executed pushes in (b)
  int pushes_learn = 0;          ///< executed pushes in (c)
  int faults = 0;                ///< logged faults (not planned, refused, moved nothing, lost)
  std::vector<std::string> stop_reasons;  ///< per round: why it ended early ("" when it did not)
  /// Per round run: the class its views became (SelfSupervisionOptions::rounds; -1: a round
  /// without views). With C rounds: 0..C-1, each round its own class.
  std::vector<int> round_class;
  /// Per round run: the pixel colour-word counts of its looks' blobs that claims by colour and
  /// refind_colour used (features::colour_word_counts; colour_first_look: its first look's
  /// only). Empty when neither is in use.
  std::vector<Eigen::VectorXd> round_colours;
  std::vector<SelfSupervisionDecision> log;  ///< the decision log (decisions.jsonl's lines)
  double seconds = 0;
};

/// The self-supervision loop (7.2 a-d) on `robot` with the LDA `model` and `vocabulary`: the
/// learner's side of run_self_supervision. `classes` is C; `episodes` is where each push's episode
/// goes (created; required for ViewSource::kMotion); `log_path`, when not empty, gets each log
/// line as it is made. Throws Error for bad options, a vocabulary of another size than the
/// model's words, or C < 1; everything the world does is a logged outcome.
Learning learn_by_pushing(robot::Robot& robot, TableAttendant& attendant, int classes,
                          const topics::LdaModel& model, const features::Vocabulary& vocabulary,
                          const SelfSupervisionOptions& options,
                          const std::filesystem::path& episodes,
                          const std::filesystem::path& log_path = {}, bool progress = false);

/// (d)'s choice of the next object to learn (7.2 d: "the object least likely under the models
/// learned so far"), made in the look's own terms. Each learned class keeps the topic
/// proportions (theta, rows summing to 1) of its object's blob in the looks of its learn round
/// (the robot looking between pushes: the same camera, arm parked, whole-blob masks, as the
/// candidates now, and from as many sides as the pushes turned it). A candidate blob's distance
/// to a class is its least Hellinger distance to the class's looks (0..1). Every learned class
/// then claims one blob, the one-to-one matching of classes to blobs of least total distance
/// (an object is one class); of the blobs left unclaimed the one farthest from every class is
/// chosen (ties: the first). Without the matching a learned object whose look had drifted from
/// its class was chosen again while an object that looked like some class was never chosen
/// (docs/results/selfsupervision-history.md, 2026-12-03).
struct NextChoice {
  int blob = -1;                   ///< the blob chosen (-1: no blob could be scored)
  std::vector<int> claimed_by;     ///< per blob: the class that claimed it, -1 none
  std::vector<double> nearest;     ///< per blob: its distance to the nearest class (-1: unscored)
  std::vector<int> nearest_class;  ///< per blob: that class (-1: unscored or no class)
};

/// The choice above. `blobs`: one theta per blob (empty: the blob has too few features to be
/// scored; it is neither claimed nor chosen); `class_looks[c]`: class c's look thetas (a class
/// with none takes no part). Thetas must all have the same length. Classes that outnumber the
/// scored blobs claim as many as there are; when every scored blob is claimed the farthest of
/// all is chosen (the learner then learns an object twice, which the log says). Brute force
/// over the matchings: at most 8 classes and 8 blobs take part (more: a greedy matching).
NextChoice choose_unlearned(const std::vector<Eigen::VectorXd>& blobs,
                            const std::vector<std::vector<Eigen::VectorXd>>& class_looks);

/// The choice above by the classes' views (SelfSupervisionOptions::claims_by kViewWords).
/// `blobs`: each blob's words (empty: unscored); `class_counts[c]`: class c's word counts over
/// its views (all zero: no views, it takes no part); every count vector as long as the
/// vocabulary (`words`) and every word below it. The background p0 is the scored blobs' words
/// pooled (add-one); class c's multinomial is its counts with `words` pseudo-counts spread as
/// p0: p_c = (n_c + V p0) / (N_c + V). A blob's distance to class c is minus the mean over its
/// words of log(p_c(w) / p0(w)): negative when c explains its words better than the look as a
/// whole. The matching and the choice are choose_unlearned's. Throws on a word out of range or
/// a count vector of another length.
NextChoice choose_unlearned_by_words(const std::vector<std::vector<std::int32_t>>& blobs,
                                     const std::vector<Eigen::VectorXd>& class_counts, int words);

/// The choice above by SIFT descriptors (SelfSupervisionOptions::claims_by kDescriptors).
/// `blobs`: each blob's descriptors (N x 128 CV_32F; empty: unscored); `class_descriptors[c]`:
/// class c's (empty: it takes no part). For each descriptor of blob b, OpenCV's brute-force
/// matcher (L2) gives its nearest distance in every class and in every other scored blob of the
/// look; it matches class c when c is its nearest and that distance is below `ratio` times the
/// nearest of every other object (the other classes and the other blobs: Lowe's ratio test with
/// the second neighbour from another object). The blob's distance to c is minus the share of its
/// descriptors that match c (-1..0). A class claims a blob (the matching of choose_unlearned)
/// only when at least `min_share` of its descriptors match; a pair below it counts as no claim
/// (cost -min_share) in the matching. Throws on a descriptor matrix that is not N x 128 CV_32F,
/// a ratio outside (0, 1] or a min_share outside [0, 1].
NextChoice choose_unlearned_by_descriptors(const std::vector<cv::Mat>& blobs,
                                           const std::vector<cv::Mat>& class_descriptors,
                                           double ratio, double min_share);

/// (b) -> (c) (SelfSupervisionOptions::recheck_tries): should the round choose again? `claims`:
/// choose_unlearned on the look after (b); `chosen`: the chosen object's blob in that look.
/// True when a learned class claims `chosen` and some scored blob is left unclaimed (choosing
/// again then chooses an object no class claims; when every blob is claimed it could only
/// choose a learned object, and the round goes on with its own). Throws when `chosen` is not a
/// blob of `claims`.
bool recheck_claimed(const NextChoice& claims, int chosen);

/// (c) before a new class (SelfSupervisionOptions::repeat_tries): is a round's first views'
/// object one the robot has learned already? `model`: the Mixture of Topics of the earlier
/// rounds' views; `known` (rows theta) and `known_labels` (the model's class of each row, -1:
/// none): the views it was fitted on; `fresh`: the new views' theta. Class c's floor is the
/// lower quartile (kRepeatQuantile) of its own views' log Dir(theta | omega_c) + log p(c); a
/// fresh view is explained by c when c is its most likely class and its score under c is at
/// least c's floor (as likely as three quarters of the views c learned from). The class that
/// explains the largest share of the fresh views, when that share is at least `share`, is the
/// answer (ties: the lower class). Only what the robot sees is used (never the ground truth).
struct RepeatTest {
  int cls = -1;                ///< the model's class (index into model.objects); -1: none
  std::vector<double> shares;  ///< per model class: the share of the fresh views it explains
  std::vector<double> floors;  ///< per model class: its floor (-inf: no views of its own)
};
inline constexpr double kRepeatQuantile = 0.25;

/// The test above. Throws Error when the shapes disagree, a label is out of range or `share` is
/// outside (0, 1].
RepeatTest explained_by(const topics::MotModel& model, const Eigen::MatrixXd& known,
                        const std::vector<int>& known_labels, const Eigen::MatrixXd& fresh,
                        double share);

/// SelfSupervisionOptions::rounds: the distance between two round classes, from their views'
/// word counts `a` and `b` (one entry a vocabulary word, non-negative): the symmetric excess
/// cross-entropy d = 1/2 [H(a, phi_b) - H(a, phi_a) + H(b, phi_a) - H(b, phi_b)], nats a word,
/// H(x, phi) = -sum_w x_w log phi_w / sum_w x_w, phi_x = (x + kRoundSmoothing) normalised (each
/// round's word multinomial, a symmetric Dirichlet's posterior mean). 0 for equal counts, larger
/// the less each round's views are explained by the other's multinomial. Throws Error when the
/// lengths differ or either has no word.
double round_distance(const Eigen::VectorXd& a, const Eigen::VectorXd& b);
inline constexpr double kRoundSmoothing = 0.5;

/// SelfSupervisionOptions::same_object_by colour: the distance between two round classes from
/// their looks' pooled colour counts `a` and `b` (features::colour_word_counts bins,
/// non-negative): the Hellinger distance of the two normalised histograms, in [0, 1]; 0 for
/// proportional counts. Throws Error when the lengths differ or either has no pixel.
double colour_round_distance(const Eigen::VectorXd& a, const Eigen::VectorXd& b);

/// The least share of the pixels outside the blobs a table colour word holds (table_colour_words).
inline constexpr double kTableColourShare = 0.2;

/// SelfSupervisionOptions::table_colours_out: which colour words (features::colour_word_counts's,
/// `colour`'s grid) are the table's in `image` (8-bit BGR or grey): those of at least `share` of
/// the pixels outside every blob of `view` (the table round the objects, and the arm where it is
/// in view, whose few words stay under `share`). One flag a colour word; none when no pixel lies
/// outside the blobs. Throws Error as colour_word_counts, and when `share` is not in (0, 1].
std::vector<bool> table_colour_words(const cv::Mat& image, const planning::PlanningView& view,
                                     const features::ColourWordOptions& colour,
                                     double share = kTableColourShare);

/// A blob's pixel colour counts (features::colour_word_counts) without the table's words
/// (table_colour_words): those counts set to 0; `counts` unchanged when that leaves no pixel (a
/// blob of the table's colour only) or `table` flags none. Throws Error when the lengths differ.
Eigen::VectorXd without_table_colours(const Eigen::VectorXd& counts,
                                      const std::vector<bool>& table);

/// SelfSupervisionOptions::moved_colours: the pixels of `region` (8-bit, nonzero: in; the images'
/// size) whose colour differs between `before` and `after` (8-bit BGR or grey, both alike) by more
/// than `levels` in at least one channel: what a push moved there. An 8-bit mask (255: moved).
/// Throws Error on empty images, other types, sizes that differ or levels outside [0, 255).
cv::Mat moved_pixels(const cv::Mat& before, const cv::Mat& after, const cv::Mat& region,
                     int levels);
/// The change in a channel, of 255, above which moved_colours counts a pixel as moved: well above
/// the renderer's noise (none) and JPEG-free images' shading, below a textured object's contrast.
inline constexpr int kMovedLevels = 24;

/// A distance between two groups' pooled counts (round_distance or colour_round_distance).
using RoundDistance = double (*)(const Eigen::VectorXd&, const Eigen::VectorXd&);

/// One merge of merge_rounds: the two groups (their rounds, 0-based) and their distance.
struct RoundMergeStep {
  std::vector<int> a;
  std::vector<int> b;
  double distance = 0;
  bool same = false;  ///< below same_object: judged one object
};

/// SelfSupervisionOptions::rounds: the round classes merged by the robot's own similarity.
struct RoundMerge {
  /// Per round: its class, 0..classes-1 numbered by each class's first round (-1: no words).
  /// The rounds with words merged, nearest first, until at most `classes` groups are left.
  std::vector<int> class_of_round;
  /// Per round: its group when only merges below same_object are made (the robot's judgement of
  /// which rounds learned one object; -1: no words), numbered as class_of_round.
  std::vector<int> judged;
  int distinct = 0;  ///< groups of `judged`: the distinct objects the robot judges it learned
  std::vector<RoundMergeStep> steps;  ///< every merge made for class_of_round or judged, in order
};

/// Agglomerative merging of round classes: `counts[r]` is round r's views' word counts (all of
/// one length; all zero: a round without views, left out). The two nearest groups (`distance`
/// of their pooled counts, round_distance by default; ties: the lower rounds) are merged while
/// more than `classes` groups are left (class_of_round) and while they are nearer than
/// `same_object` (judged). Throws Error when `classes` < 1 or the lengths differ.
RoundMerge merge_rounds(const std::vector<Eigen::VectorXd>& counts, int classes, double same_object,
                        RoundDistance distance = round_distance);

/// Most sideways offset of a turning push, m (SelfSupervisionOptions::turn_offset).
inline constexpr double kMaxTurnOffset = 0.03;

/// (c) A push that turns the object (thesis 7.2 c: pushed "from several sides so that it turns
/// and shows different views"): the planner's push of `plan` (through the object's centre p_c
/// along n) shifted sideways to the left of n (l = n turned +90 degrees) by
/// e = min(fraction x w, kMaxTurnOffset), w the hull's extent from p_c toward l (table m). The
/// pusher meets the object e off its centre line, a torque of e (l x n) = -e about z: seen from
/// above it turns the object clockwise, the same way from whichever side it comes, so the turns
/// of a round's pushes add up. The start keeps `plan.approach` behind the hull's edge along the
/// shifted line: p_c + e l - (d_e + approach) n, d_e the hull's depth behind p_c + e l (Algorithm
/// 4's walk, planning::distance_to_hull_edge); the end is shifted by e l. fraction 0 (or a hull
/// of fewer than 3 points) returns plan.push unchanged; `offset` is e, m.
struct TurningPush {
  robot::TablePush push;
  double offset = 0;
};
TurningPush turning_push(const planning::PushPlan& plan, const std::vector<Eigen::Vector2d>& hull,
                         double fraction);

/// (c) The learn pushes round `round` (0..classes-1) may spend: `pushes` plus what the rounds
/// before it left unspent of theirs (`spent`: learn pushes executed so far), at most twice
/// `pushes` and at least 0 (SelfSupervisionOptions::carry_budget).
int round_budget(int round, int pushes, int spent);

/// (c) refind_colour: which blob of a look is the round's object when none is where it was left.
/// `blobs`: per blob of the look, its pixels' colour-word counts (features::colour_word_counts;
/// empty or all zero: unscored); `own`: the round's looks' pooled counts; `others`: the other
/// rounds' (empty ones take no part). Each count vector is normalised; distances are Hellinger.
/// A blob nearer some other round's looks than the round's own is never taken. `nearest`: the
/// remaining blob nearest the own looks (-1: none), `distance` its distance; `blob` is it when
/// that distance is below `max_distance`, else -1 (as with no own looks or max_distance <= 0).
struct ColourRefind {
  int blob = -1;
  int nearest = -1;
  double distance = -1;
};
ColourRefind refind_by_colours(const std::vector<Eigen::VectorXd>& blobs,
                               const Eigen::VectorXd& own,
                               const std::vector<Eigen::VectorXd>& others, double max_distance);

/// refind_colour: the `others` of refind_by_colours for round `round`: every other round's colour
/// counts (`colours`, per round), except, with rounds (SelfSupervisionOptions::rounds), those of
/// the rounds the robot judges the same object as `round` (`judged`: per round its group, -1 or
/// missing: none; empty: no judgement). A round's own object seen in an earlier round does not
/// veto finding it again.
std::vector<Eigen::VectorXd> refind_vetoes(int round, const std::vector<Eigen::VectorXd>& colours,
                                           const std::vector<int>& judged);

/// (c) Which blob after a learn push is the round's object. `blobs`: per blob of the look after
/// the push, its theta (empty: too few features); `own`: the thetas of the round's object in its
/// earlier looks; `others`: the other learned classes' looks; `tracked`: the blob that moved
/// (planning::find_pushed_object), -1 none. Distances are least Hellinger distances to a set of
/// looks. The tracked blob stays the object unless another scored blob is nearer the round's own
/// looks by more than `margin` and nearer them than any other class's looks: then that blob (a
/// re-find: the push moved a neighbour, or the object was two touching ones; session 15's logs
/// had the object pushed most in a round not the chosen one in 6 of 20 rounds). With no tracked
/// blob the nearest is taken on the same terms; -1 when none qualifies. margin 0 or no own
/// looks: `tracked`.
struct Followed {
  int blob = -1;
  bool refound = false;          ///< another blob than `tracked` was taken
  double tracked_distance = -1;  ///< the tracked blob's distance to the own looks (-1: unscored)
  double distance = -1;          ///< the taken blob's (-1: unscored)
};
Followed follow_by_looks(const std::vector<Eigen::VectorXd>& blobs,
                         const std::vector<Eigen::VectorXd>& own,
                         const std::vector<std::vector<Eigen::VectorXd>>& others, int tracked,
                         double margin);

/// (c) A shorter learn push, m: tried from every side when no kSidePush-long one keeps clear of
/// the neighbours (SelfSupervisionOptions::learn_clearance).
inline constexpr double kShortLearnPush = 0.04;

/// (c) The fallback goals of a learn push whose first goal could not be planned (table m): from
/// `chosen` (the object's centre), `length` m along the directions `a0` + k 2 pi / `sides`,
/// k = 1..sides-1. With `inward` (SelfSupervisionOptions::inward_sides) they are sorted by their
/// distance to `centre` (the work centre; nearest first) and those that end farther from it than
/// both `chosen` and `radius` (the circle of learn targets) are left out: session 18, seed 4,
/// the fallback sides carried an object 0.31 -> 0.55 m from the base, out of the arm's reach.
/// Without, all in the order of k.
std::vector<Eigen::Vector2d> fallback_goals(const Eigen::Vector2d& chosen,
                                            const Eigen::Vector2d& centre, double a0, double length,
                                            int sides, double radius, bool inward);

/// (b) Most pushes of the chosen object into free space per round
/// (SelfSupervisionOptions::free_space).
inline constexpr int kFreeMoves = 2;
/// (b) A free-space push carries the chosen object at most this far, m.
inline constexpr double kMaxFreePush = 0.15;

/// Merged blobs split (split_merged_blobs): a blob needs this many times min_features points.
inline constexpr int kSplitLeast = 2;

/// (a)-(c) Merged blobs split (session 20): while `view` holds fewer putative objects than
/// `classes` (C, the objects the robot is told are on the table), the blob with the most feature
/// points (of those not yet tried, and with at least kSplitLeast x `min_features`) is split in
/// two by k-means (cv::kmeans, k = 2) on its feature points' image positions and their colours
/// (CIE Lab of `image`, 8-bit BGR of the view's size, averaged over 5 x 5 px), each standardised
/// over the blob, the colours weighted by `colour_weight` (0: positions only); the start is the
/// blob's two halves across its principal axis, so the split is deterministic. Each half's
/// region is the blob's mask pixels nearest one of its points; planning::split_putative_objects
/// makes the two parts (each needs `min_features` points, else the blob is left as it was).
/// Returns the indices (into view.objects before the split) of the blobs split, in order.
std::vector<int> split_merged_blobs(planning::PlanningView& view, const cv::Mat& image, int classes,
                                    int min_features, double colour_weight,
                                    const planning::TableRegion& region,
                                    const planning::PushPlanOptions& options);

/// (b) A place the chosen object could be pushed to: `point` (table m, its centre there) and the
/// least gap (hull_gap) its footprint hull, carried there, would leave to every other blob.
struct FreeSpot {
  Eigen::Vector2d point = Eigen::Vector2d::Zero();
  double gap = 0;
};
/// (b) The places for blob `blob` of `view` on a grid of `step` m within `radius` m of `centre`
/// (the work centre) and at most `reach` m from the blob's centre, best first: largest gap, then
/// (gaps in whole mm) nearest the blob. No other blob: its own place alone (gap infinite).
std::vector<FreeSpot> free_spots(const planning::PlanningView& view, int blob,
                                 const Eigen::Vector2d& centre, double radius, double reach,
                                 double step);

/// (c) How much a learn push of blob `blob` of `view` toward `target` (table m) lacks of
/// `clearance` (m): planning::path_clearance of the corridor the blob's footprint hull sweeps
/// from its centre to `target` against every other blob's hull (the pusher's own path not
/// counted). 0: it keeps clear (or `clearance` <= 0, or no other blob).
double learn_push_lack(const planning::PlanningView& view, int blob, const Eigen::Vector2d& target,
                       double clearance);

/// (c) Which blobs of the look before a push moved in it: the motion of the push between the two
/// looks (arm parked out of view; `before`, `after`: their 8-bit images of one size), per blob of
/// `view` (the look before) the share of its feature points whose neighbourhood changed
/// (planning::moved_share). A blob moved when its share is at least `threshold`. The share
/// saturates (a blob pushed a few cm changes all its features): the pushed blob `pushed` (-1:
/// none) is the one that moved most when it moved and its share is within kShareTie of the
/// largest, so a push that moved its object and a neighbour as much is two moving, not a drift.
struct PushMotion {
  std::vector<double> share;  ///< per blob of `view`, 0-1
  std::vector<int> moved;     ///< the blobs that moved, in order of their index
  /// The blob of largest share among those that moved (ties: `pushed`, else the first); -1 none.
  int most = -1;
  /// `blob` moved and no other one did.
  [[nodiscard]] bool alone(int blob) const { return moved.size() == 1 && moved.front() == blob; }
};
PushMotion push_motion(const cv::Mat& before, const cv::Mat& after,
                       const planning::PlanningView& view, double threshold, int pushed = -1);
/// Shares this close count as a tie in push_motion.
inline constexpr double kShareTie = 0.05;

/// (c) Which putative object of `view` (the look after a push, split by the push's mask) is the
/// pushed one: of those with at least `min_features` feature points inside `mask` (8-bit, the
/// view's image size: what moved with the arm at the push's end), the one whose centre is nearest
/// `target` (the push's target, table m); -1 when none.
int pushed_part(const planning::PlanningView& view, const cv::Mat& mask,
                const Eigen::Vector2d& target, int min_features);

/// (c) What a learn push moved, judged from its own dense motion (the episode) on blobs split
/// into objects, not from the looks' blobs (session 18: of 136 pushes the looks called "alone",
/// 94 moved a neighbour that sat inside the pushed blob).
/// 1. `view` (the look before the push) is split in place by `touch` (8-bit, the view's image
///    size: the push's motion segmentation at its first touch, the arm cut out; thesis 8.1.1,
///    what moved with the arm is one object; planning::split_putative_objects with
///    `min_features`, `region`, `options`); the putative object holding it is the pushed one,
///    else `pushed` (the planned blob).
/// 2. The pushed object's share is that of its feature points whose neighbourhood changed
///    between the episode's frames `first` (before the touch) and `last` (the push's end; 8-bit,
///    the view's image size; planning::moved_share). Every other object's share counts only its
///    points the push's own motion does not explain: those outside `explained` (8-bit, non-zero
///    where a frame's segmentation put the pushed object or the arm was); an object with no point
///    left has share 0.
/// Returns push_motion's verdict (threshold, ties to the pushed object) over the split view's
/// objects and the pushed object's index in it.
struct EpisodeMotion {
  PushMotion motion;
  int pushed = -1;  ///< index into the split view's objects
};
EpisodeMotion episode_motion(planning::PlanningView& view, int pushed, const cv::Mat& touch,
                             const cv::Mat& explained, const cv::Mat& first, const cv::Mat& last,
                             double threshold, int min_features,
                             const planning::TableRegion& region,
                             const planning::PushPlanOptions& options);

/// (c) Whether blob `now` of the look `after` a push holds another object of the look `before`:
/// the index of the first blob of `before` other than `pushed` whose centre lies inside `now`'s
/// footprint hull (table m), -1 when none (the pushed blob merged with a neighbour into one blob).
int merged_blob(const planning::PlanningView& before, int pushed,
                const planning::PlanningView& after, int now);

/// (c) Whether the look `after` a push shows the pushed blob `pushed` of the look `before`
/// merged with a neighbour, from the looks alone (SelfSupervisionOptions::merge_ratio):
/// `after` has fewer blobs than `before`, and its blob `now` (the pushed object found again)
/// holds at least `ratio` times as many feature points as `pushed` did. False when `now` or
/// `pushed` is not a blob of its look, or `pushed` has no feature point. Throws Error unless
/// `ratio` is finite and above 1.
bool merged_by_growth(const planning::PlanningView& before, int pushed,
                      const planning::PlanningView& after, int now, double ratio);

/// Hellinger distance between two distributions (non-negative, each summing to 1): 0..1.
double hellinger(const Eigen::VectorXd& p, const Eigen::VectorXd& q);

/// The descriptors (one CV_32F row a feature; empty: none) of `image`'s features inside `mask`
/// (CV_8U, grown by `dilate` px). With `exclude` (CV_8U of the image's size, or empty for none)
/// a feature whose patch (the dense SIFT support, options.dense.size px square round its grid
/// point) reaches a non-zero pixel of `exclude` is left out: its descriptor would describe what
/// lies there (the arm beside the object, SelfSupervisionOptions::arm_patches_out), not the
/// object.
cv::Mat masked_descriptors(const cv::Mat& image, const cv::Mat& mask,
                           const features::ExtractOptions& options, int dilate,
                           const cv::Mat& exclude = {});

/// The features whose descriptors masked_descriptors gives (keypoints and descriptors).
features::Features masked_features(const cv::Mat& image, const cv::Mat& mask,
                                   const features::ExtractOptions& options, int dilate,
                                   const cv::Mat& exclude = {});

/// The visual-word document of masked_features(image, mask, options, dilate, exclude), with
/// colour words when `colour` is given (features::document_words).
std::vector<std::int32_t> masked_document(
    const cv::Mat& image, const cv::Mat& mask, const features::Vocabulary& vocabulary,
    const features::ExtractOptions& options, int dilate, const cv::Mat& exclude = {},
    const std::optional<features::ColourWordOptions>& colour = std::nullopt);

/// The table distance between two convex polygons (m): 0 when they overlap.
double hull_gap(const std::vector<Eigen::Vector2d>& a, const std::vector<Eigen::Vector2d>& b);

}  // namespace proprio::loop
