// proprio learn's options: defaults from the issue, --quick, and bad input (the sim run itself
// is exercised by tests/app/learn_cli_test.cpp).
#include "proprio/loop/learn.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <opencv2/imgproc.hpp>
#include <set>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "../support/table_views.hpp"
#include "../support/temp_dir.hpp"
#include "proprio/core/error.hpp"
#include "proprio/core/json_io.hpp"
#include "proprio/core/random.hpp"
#include "proprio/features/colour_words.hpp"
#include "proprio/features/kmeans.hpp"
#include "proprio/features/vocabulary.hpp"
#include "proprio/loop/view_model.hpp"
#include "proprio/recognition/mot.hpp"
#include "proprio/sim/object_catalogue.hpp"
#include "proprio/sim/simulated_robot.hpp"
#include "proprio/topics/batch_lda.hpp"
#include "proprio/topics/lda_model_io.hpp"

namespace proprio::loop {
namespace {

TEST(Learn, DefaultsAreTheIssuesWorld) {
  const LearnOptions o;
  EXPECT_EQ(o.objects, "book,bottle,cd,giraffe");
  EXPECT_EQ(o.clutter, "mug,rabbit,calculator");  // 3 more catalogue objects
  EXPECT_EQ(o.background, "moving");              // people walking behind
  EXPECT_EQ(o.distractors, -1);                   // 2 with the moving backdrop
  EXPECT_EQ(o.seed, 1U);
  EXPECT_NO_THROW(o.validate());
  EXPECT_EQ(o.resolved().pushes, o.pushes);  // not quick: unchanged
  // The dense segmentation takes the baseline's touch cut as evidence (issue 20), as
  // MlOptions's default (docs/results/learn-history.md, "Session 24").
  EXPECT_DOUBLE_EQ(o.dense.touch_fm, 1.0);
  // The motion views and the look before each push (session 40's third rule).
  EXPECT_EQ(o.views, LearnViews::kBoth);
}

TEST(Learn, QuickMakesTheRunSmall) {
  LearnOptions o;
  o.quick = true;
  const LearnOptions q = o.resolved();
  EXPECT_LT(q.width, o.width);
  EXPECT_LT(q.words, o.words);
  EXPECT_EQ(q.pushes, 6);  // quick_pushes' default (session 39's third rule; 3 before)
  o.quick_pushes = 9;      // session 35: more pushes a turn at quick's size
  EXPECT_EQ(o.resolved().pushes, 9);
  EXPECT_EQ(o.resolved().width, q.width);  // the rest stays quick
  o.quick = false;
  EXPECT_EQ(o.resolved().pushes, o.pushes);  // not quick: quick_pushes unused
  o.quick = true;
  o.pushes = 5;  // given explicitly: kept
  EXPECT_EQ(o.resolved().pushes, 5);
  o = LearnOptions();
  o.quick_pushes = 0;
  EXPECT_THROW(o.validate(), Error);
  o.quick_pushes = 1001;
  EXPECT_THROW(o.validate(), Error);
}

TEST(Learn, DepthGivesTheRobotAnRgbdCamera) {
  // `proprio learn --depth`: the simulated table's camera is an RGB-D one (Look::depth), so the
  // planner measures the blobs' footprints and heights from depth, as selfsupervise --depth.
  LearnOptions o;
  o.quick = true;
  EXPECT_TRUE(learn_table(o.resolved()).depth);  // the default depth candidates need it
  o.candidates = LearnCandidates::kBlobs;
  const LearnOptions q = o.resolved();
  EXPECT_FALSE(learn_table(q).depth);
  EXPECT_EQ(learn_table(q).objects, (std::vector<std::string>{"book", "bottle", "cd", "giraffe"}));
  EXPECT_EQ(learn_table(q).clutter, q.clutter);
  EXPECT_EQ(learn_table(q).width, q.width);
  o.depth = true;
  const sim::TableOptions t = learn_table(o.resolved());
  EXPECT_TRUE(t.depth);
  const sim::ObjectCatalogue catalogue = sim::ObjectCatalogue::load_default();  // outlives it
  sim::SimulatedRobot robot(t, catalogue);
  const robot::Look l = robot.look();
  EXPECT_FALSE(l.depth.empty());
  EXPECT_EQ(l.depth.size(), l.image.size());
}

TEST(Learn, BadOptionsThrow) {
  LearnOptions o;
  o.background = "stripes";
  EXPECT_THROW(o.validate(), Error);
  o = LearnOptions();
  EXPECT_TRUE(o.colour_words);  // the default since session 38
  EXPECT_NO_THROW(o.validate());
  o.oracle_ladder = true;  // the rungs' documents are SIFT words only
  EXPECT_THROW(o.validate(), Error);
  o.colour_words = false;
  EXPECT_NO_THROW(o.validate());
  o = LearnOptions();
  o.colour.grey_levels = 0;
  EXPECT_THROW(o.validate(), Error);
  o = LearnOptions();
  o.distractors = 5;
  EXPECT_THROW(o.validate(), Error);
  o = LearnOptions();
  o.clutter = "book";
  EXPECT_THROW(o.validate(), Error);
  o = LearnOptions();
  o.pushes = 0;
  EXPECT_THROW(o.validate(), Error);
  o = LearnOptions();
  o.objects = "book,,cd";
  EXPECT_THROW(o.validate(), Error);
  o = LearnOptions();
  o.match_ratio = 0;
  EXPECT_THROW(o.validate(), Error);
  o.match_ratio = 1.5;
  EXPECT_THROW(o.validate(), Error);
  o = LearnOptions();
  o.match_known = -0.1;
  EXPECT_THROW(o.validate(), Error);
  o.match_known = 1.1;
  EXPECT_THROW(o.validate(), Error);
  o = LearnOptions();
  EXPECT_DOUBLE_EQ(o.identity_margin, -1.0);  // off by default
  o.identity_margin = -1.5;
  EXPECT_THROW(o.validate(), Error);
  o.identity_margin = 1000.5;
  EXPECT_THROW(o.validate(), Error);
  o = LearnOptions();
  o.candidate_height = 0;
  EXPECT_THROW(o.validate(), Error);
  o = LearnOptions();
  o.candidate_step = 0.6;
  EXPECT_THROW(o.validate(), Error);
  o = LearnOptions();
  o.start_clearance = -0.01;
  EXPECT_THROW(o.validate(), Error);
  o.start_clearance = 0.3;
  EXPECT_THROW(o.validate(), Error);
  o = LearnOptions();
  EXPECT_FALSE(o.mot_word_per_view);  // session 32: the pooled counts
  // Session 39's third rule: the colour words alone with colour words (the default), the pooled
  // classifier without them (session 32's rule; the MoT before).
  EXPECT_EQ(o.headline, LearnHeadline::kAuto);
  EXPECT_EQ(o.resolved().headline, LearnHeadline::kColour);
  o.colour_words = false;
  EXPECT_EQ(o.resolved().headline, LearnHeadline::kPooled);
  EXPECT_NO_THROW(o.resolved().validate());
  o.headline = LearnHeadline::kMot;  // a headline given is kept
  EXPECT_EQ(o.resolved().headline, LearnHeadline::kMot);
  o = LearnOptions();
  EXPECT_DOUBLE_EQ(o.mot_word_weight, 0.25);
  o.mot_word_weight = -0.01;
  EXPECT_THROW(o.validate(), Error);
  o.mot_word_weight = 1.01;
  EXPECT_THROW(o.validate(), Error);
  o = LearnOptions();
  o.dense.touch_fm = -0.1;
  EXPECT_THROW(o.validate(), Error);
  o.dense.touch_fm = 1.1;
  EXPECT_THROW(o.validate(), Error);
  o = LearnOptions();
  EXPECT_DOUBLE_EQ(o.region_agree, 0.08);  // session 39's third rule (off before)
  o.region_agree = -0.01;
  EXPECT_THROW(o.validate(), Error);
  o.region_agree = 0.51;
  EXPECT_THROW(o.validate(), Error);
  o = LearnOptions();
  EXPECT_FALSE(o.lost_rechoose);  // off by default (session 34, second round)
  o.lost_rechoose = true;         // acts on region_agree's lost object only
  EXPECT_NO_THROW(o.validate());  // region_agree 0.08 by default (session 39)
  o.region_agree = 0;
  EXPECT_THROW(o.validate(), Error);
  o = LearnOptions();
  EXPECT_DOUBLE_EQ(o.moving_wait, 0.0);  // off by default (session 37)
  for (const double bad : {-0.1, 5.01, std::nan(""), HUGE_VAL}) {
    o.moving_wait = bad;
    EXPECT_THROW(o.validate(), Error) << bad;
  }
  o.moving_wait = 0.3;
  EXPECT_NO_THROW(o.validate());
  o.candidates = LearnCandidates::kBlobs;  // compares depth: needs the depth image
  EXPECT_THROW(o.validate(), Error);
  o.depth = true;
  EXPECT_NO_THROW(o.validate());
  o = LearnOptions();
  o.clutter = "";
  EXPECT_NO_THROW(o.validate());
}

TEST(Learn, MovedFractionsTellABlobThatShiftedFromOneThatStayed) {
  // Two looks' depth (m) of a table 1 m away: a still box (2 cm nearer) and a moving one that
  // slid 12 px to the right between the looks. The still box's mask: nothing moved; the moving
  // one's (where it was in the first look): its left part now sees the table, 12 of 20 columns.
  cv::Mat1f before(60, 80, 1.0F);
  cv::Mat1f after(60, 80, 1.0F);
  before(cv::Rect(5, 10, 20, 20)) = 0.98F;
  after(cv::Rect(5, 10, 20, 20)) = 0.98F;
  before(cv::Rect(40, 10, 20, 20)) = 0.95F;
  after(cv::Rect(52, 10, 20, 20)) = 0.95F;
  cv::Mat1b still(60, 80, uchar{0});
  cv::Mat1b moving(60, 80, uchar{0});
  still(cv::Rect(5, 10, 20, 20)) = 255;
  moving(cv::Rect(40, 10, 20, 20)) = 255;
  std::vector<double> f = moved_fractions(before, after, {still, moving});
  ASSERT_EQ(f.size(), 2U);
  EXPECT_DOUBLE_EQ(f[0], 0.0);
  EXPECT_NEAR(f[1], 12.0 / 20.0, 1e-9);
  EXPECT_LT(f[0], kMovingFraction);  // kept
  EXPECT_GE(f[1], kMovingFraction);  // left out
  // A change below kMovingDepth is no motion (sensor noise); a pixel no longer measured is.
  after(cv::Rect(5, 10, 20, 20)) = 0.985F;
  after(cv::Rect(5, 10, 10, 20)) = 0.0F;
  f = moved_fractions(before, after, {still});
  EXPECT_NEAR(f[0], 0.5, 1e-9);
  // Pixels unmeasured in the first look do not count; a mask with none gives 0.
  before(cv::Rect(5, 10, 20, 20)) = 0.0F;
  EXPECT_DOUBLE_EQ(moved_fractions(before, after, {still})[0], 0.0);
  // Bad input throws.
  EXPECT_THROW(moved_fractions(before, cv::Mat1f(10, 10, 1.0F), {still}), Error);
  EXPECT_THROW(moved_fractions(before, after, {cv::Mat1b(10, 10, uchar{0})}), Error);
  EXPECT_THROW(moved_fractions(before, after, {still}, 0.0), Error);
}

// Documents of 30 words drawn from words [first, first + 5) of a 10-word vocabulary.
void add_documents(topics::Corpus& corpus, int docs, int first, std::uint64_t seed) {
  core::Rng rng(seed);
  for (int d = 0; d < docs; ++d) {
    std::vector<std::int32_t> tokens;
    tokens.reserve(30);
    for (int n = 0; n < 30; ++n) tokens.push_back(first + static_cast<int>(rng.index(5)));
    corpus.add_tokens(tokens);
  }
}

TEST(Learn, LadderPooledScoresTheLaddersRungsByThePooledWordsClassifier) {
  LearnOptions o;
  EXPECT_FALSE(o.ladder_pooled);  // the default: the rungs by theta only
  EXPECT_FALSE(learn_score_options(o.resolved()).pooled_score);
  o.ladder_pooled = true;
  EXPECT_THROW(o.validate(), Error);  // it scores the ladder: not without it
  o.oracle_ladder = true;
  EXPECT_THROW(o.validate(), Error);  // the rungs are SIFT documents: not with colour words
  o.colour_words = false;
  EXPECT_NO_THROW(o.validate());
  const SelfSupervisionOptions on = learn_score_options(o.resolved());
  EXPECT_TRUE(on.oracle_ladder);
  EXPECT_TRUE(on.pooled_score);
  o.ladder_pooled = false;
  const SelfSupervisionOptions off = learn_score_options(o.resolved());
  EXPECT_TRUE(off.oracle_ladder);
  EXPECT_FALSE(off.pooled_score);
  // Otherwise the scoring is learn's own, as before.
  o.quick = true;
  const LearnOptions r = o.resolved();
  const SelfSupervisionOptions q = learn_score_options(r);
  EXPECT_EQ(q.objects, r.objects);
  EXPECT_EQ(q.seed, r.seed);
  EXPECT_EQ(q.width, r.width);
  EXPECT_EQ(q.height, r.height);
  EXPECT_EQ(q.held_out, r.held_out);
  EXPECT_EQ(q.dilate, r.dilate);
  EXPECT_EQ(q.min_features, r.min_features);
}

TEST(Learn, ScoreByWordsKnowsWhichObjectEachHeldOutViewShows) {
  // Two objects of disjoint words (0-4 and 5-9): the robot's views of each are one class; the
  // held-out views of each are classified as their own object by theta, by words and pooled.
  topics::Corpus training(10);
  add_documents(training, 12, 0, 1);
  add_documents(training, 12, 5, 2);
  std::vector<int> labels(24, 0);
  for (int d = 12; d < 24; ++d) labels[static_cast<std::size_t>(d)] = 1;
  labels[0] = -1;  // a view whose class was left out of the model
  topics::BatchLdaOptions bo;
  bo.num_topics = 2;
  bo.seed = 3;
  const topics::LdaModel lda = topics::train_batch_lda(training, bo).model;
  const Eigen::MatrixXd theta = recognition::document_theta(lda, training).theta;
  std::vector<int> fit_labels = labels;
  fit_labels[0] = 0;
  const topics::MotModel model = topics::fit_mot(theta, fit_labels, {"c0", "c1"}, {}).model;
  std::vector<topics::Corpus> held(3, topics::Corpus(10));
  add_documents(held[0], 7, 0, 4);
  add_documents(held[1], 5, 5, 5);  // held[2]: an object without a view with features
  const std::vector<std::string> objects{"book", "cd", "giraffe"};
  const LearnWordScore s =
      score_by_words(model, lda, training, labels, held, objects, {"book", "cd"}, 0.25);
  EXPECT_DOUBLE_EQ(s.weight, 0.25);
  EXPECT_DOUBLE_EQ(s.theta, 1.0);
  EXPECT_DOUBLE_EQ(s.words, 1.0);
  EXPECT_DOUBLE_EQ(s.pooled, 1.0);
  ASSERT_EQ(s.word_weights.size(), std::size(kLearnWordWeights));
  ASSERT_EQ(s.grid.size(), s.word_weights.size());
  for (double g : s.grid) EXPECT_DOUBLE_EQ(g, 1.0);
  ASSERT_EQ(s.objects.size(), 3U);
  EXPECT_EQ(s.objects[0].name, "book");
  EXPECT_EQ(s.objects[0].held_out, 7);
  EXPECT_EQ(s.objects[1].held_out, 5);
  EXPECT_EQ(s.objects[2].held_out, 0);
  EXPECT_DOUBLE_EQ(s.objects[2].pooled, 0.0);
  EXPECT_EQ(s.objects[2].grid.size(), s.word_weights.size());
  // The classes named the other way round: every view wrong; a class named after no held-out
  // object: its views wrong, the other object's right (5 of 12).
  const LearnWordScore swapped =
      score_by_words(model, lda, training, labels, held, objects, {"cd", "book"}, 1.0);
  EXPECT_DOUBLE_EQ(swapped.theta, 0.0);
  EXPECT_DOUBLE_EQ(swapped.words, 0.0);
  EXPECT_DOUBLE_EQ(swapped.pooled, 0.0);
  const LearnWordScore one =
      score_by_words(model, lda, training, labels, held, objects, {"mug", "cd"}, 0.0);
  EXPECT_DOUBLE_EQ(one.theta, 5.0 / 12);
  EXPECT_DOUBLE_EQ(one.words, 5.0 / 12);
  EXPECT_DOUBLE_EQ(one.objects[0].words, 0.0);
  EXPECT_DOUBLE_EQ(one.objects[1].words, 1.0);
  // Weight 0 is the Mixture of Topics by words alone; the pooled figure is the grid's at its
  // weight.
  EXPECT_DOUBLE_EQ(one.pooled, one.words);
  EXPECT_DOUBLE_EQ(one.grid[0], one.words);
  EXPECT_DOUBLE_EQ(s.grid[2], s.pooled);
  // Bad input.
  EXPECT_THROW((void)score_by_words(model, lda, training, labels, held, {"book"}, {"a", "b"}, 0.25),
               Error);
  EXPECT_THROW((void)score_by_words(model, lda, training, labels, held, objects, {"a"}, 0.25),
               Error);
  EXPECT_THROW((void)score_by_words(model, lda, training, labels, held, objects, {"a", "b"}, 1.5),
               Error);
  EXPECT_THROW((void)score_by_words(model, lda, training, labels, held, objects, {"a", "b"}, -0.1),
               Error);
  EXPECT_THROW((void)score_by_words(model, lda, training, {0, 1}, held, objects, {"a", "b"}, 0.25),
               Error);
  EXPECT_THROW(
      (void)score_by_words(topics::MotModel(), lda, training, labels, held, objects, {}, 0.25),
      Error);
}

// A 2-topic LDA of `training` and a Mixture of Topics of classes c0 and c1 on its theta.
std::pair<topics::LdaModel, topics::MotModel> two_class_model(const topics::Corpus& training,
                                                              const std::vector<int>& labels) {
  topics::BatchLdaOptions bo;
  bo.num_topics = 2;
  bo.seed = 3;
  topics::LdaModel lda = topics::train_batch_lda(training, bo).model;
  const Eigen::MatrixXd theta = recognition::document_theta(lda, training).theta;
  topics::MotModel model = topics::fit_mot(theta, labels, {"c0", "c1"}, {}).model;
  return {std::move(lda), std::move(model)};
}

TEST(Learn, ScoreByWordsScoresTheColourWordsAlone) {
  // Words 0-9 are SIFT words, 10-13 colour words. The two objects' training views share their
  // SIFT words (0-4) but not their colours (10 for the first, 12 for the second); the held-out
  // views' SIFT words (5-9) are new and say nothing. The colour words alone name every held-out
  // view; a held-out view without colour words gets the prior's class.
  topics::Corpus training(14);
  const auto view = [](topics::Corpus& c, int sift, int colour, int n) {
    std::vector<std::int32_t> tokens;
    for (int i = 0; i < n; ++i) {
      tokens.push_back(sift + (i % 5));
      if (colour >= 0) tokens.push_back(colour);
    }
    c.add_tokens(tokens);
  };
  for (int d = 0; d < 6; ++d) view(training, 0, 10, 20);
  for (int d = 0; d < 6; ++d) view(training, 0, 12, 20);
  const std::vector<int> labels{0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 1, 1};
  const auto [lda, model] = two_class_model(training, labels);
  std::vector<topics::Corpus> held(2, topics::Corpus(14));
  for (int d = 0; d < 4; ++d) view(held[0], 5, 10, 10);
  for (int d = 0; d < 3; ++d) view(held[1], 5, 12, 10);
  const std::vector<std::string> objects{"book", "cd"};
  const LearnWordScore s =
      score_by_words(model, lda, training, labels, held, objects, {"book", "cd"}, 0.25, false, 10);
  ASSERT_TRUE(s.colour.has_value());
  EXPECT_DOUBLE_EQ(*s.colour, 1.0);
  ASSERT_TRUE(s.objects[0].colour.has_value());
  EXPECT_DOUBLE_EQ(*s.objects[0].colour, 1.0);
  EXPECT_DOUBLE_EQ(*s.objects[1].colour, 1.0);
  // Named the other way round: all wrong. Without colour words (-1): no colour figure.
  const LearnWordScore swapped =
      score_by_words(model, lda, training, labels, held, objects, {"cd", "book"}, 0.25, false, 10);
  EXPECT_DOUBLE_EQ(*swapped.colour, 0.0);
  const LearnWordScore none =
      score_by_words(model, lda, training, labels, held, objects, {"book", "cd"}, 0.25);
  EXPECT_FALSE(none.colour.has_value());
  EXPECT_FALSE(none.objects[0].colour.has_value());
  // Colour words from past the documents' words: Error.
  EXPECT_THROW((void)score_by_words(model, lda, training, labels, held, objects, {"book", "cd"},
                                    0.25, false, 14),
               Error);
  // The headline by colour: its figure and per object; none without colour figures.
  const auto h = learn_headline(LearnHeadline::kColour, std::nullopt, s);
  ASSERT_TRUE(h.has_value());
  EXPECT_EQ(h->classifier, "colour");
  EXPECT_DOUBLE_EQ(h->accuracy, 1.0);
  EXPECT_EQ(h->per_object, (std::vector<double>{1.0, 1.0}));
  EXPECT_FALSE(learn_headline(LearnHeadline::kColour, std::nullopt, none).has_value());
  // --headline colour needs colour words.
  LearnOptions o;
  o.out = "unused";
  o.headline = LearnHeadline::kColour;
  EXPECT_NO_THROW(o.validate());
  o.colour_words = false;
  EXPECT_THROW(o.validate(), Error);
}

// A document of `count` tokens of each word of `words`.
void add_document(topics::Corpus& corpus, const std::vector<std::pair<int, int>>& words) {
  std::vector<std::int32_t> tokens;
  for (const auto& [w, count] : words)
    tokens.insert(tokens.end(), static_cast<std::size_t>(count), w);
  corpus.add_tokens(tokens);
}

TEST(Learn, ScoreByWordsWeighsEveryViewAlikeInThePerViewMultinomials) {
  // Three words. The book's views: one of 200 tokens of word 0 (a wide mask) and one of 10 of
  // word 1; the cd's: two of 10 x word 1 + 20 x word 2. Pooled counts (add-one): the book's
  // p(word 1) = 11 / 213, the cd's 21 / 63, so a held-out book of word 1 alone is called cd.
  // Every view alike (each scaled to the mean view's 67.5 tokens): the book's p(word 1) =
  // 68.5 / 138, the cd's 46 / 138: it is called book. A held-out cd of word 2 is cd both ways.
  // At weight 1 the pooled classifier is multinomial naive Bayes (the MoT by words left out).
  topics::Corpus training(3);
  add_document(training, {{0, 200}});
  add_document(training, {{1, 10}});
  add_document(training, {{1, 10}, {2, 20}});
  add_document(training, {{1, 10}, {2, 20}});
  const std::vector<int> labels{0, 0, 1, 1};
  const auto [lda, model] = two_class_model(training, labels);
  std::vector<topics::Corpus> held(2, topics::Corpus(3));
  add_document(held[0], {{1, 10}});
  add_document(held[1], {{2, 10}});
  const std::vector<std::string> objects{"book", "cd"};
  for (const bool per_view : {false, true}) {
    const LearnWordScore s =
        score_by_words(model, lda, training, labels, held, objects, {"book", "cd"}, 1.0, per_view);
    EXPECT_EQ(s.per_view, per_view);
    EXPECT_DOUBLE_EQ(s.pooled, 0.5);  // the book wrong, the cd right
    EXPECT_DOUBLE_EQ(s.pooled_per_view, 1.0);
    ASSERT_EQ(s.objects.size(), 2U);
    EXPECT_DOUBLE_EQ(s.objects[0].pooled, 0.0);
    EXPECT_DOUBLE_EQ(s.objects[0].pooled_per_view, 1.0);
    EXPECT_DOUBLE_EQ(s.objects[1].pooled, 1.0);
    EXPECT_DOUBLE_EQ(s.objects[1].pooled_per_view, 1.0);
    ASSERT_EQ(s.grid_per_view.size(), std::size(kLearnWordWeights));
    EXPECT_DOUBLE_EQ(s.grid.back(), s.pooled);  // kLearnWordWeights ends at 1
    EXPECT_DOUBLE_EQ(s.grid_per_view.back(), s.pooled_per_view);
    ASSERT_EQ(s.objects[0].grid_per_view.size(), std::size(kLearnWordWeights));
    EXPECT_DOUBLE_EQ(s.objects[0].grid_per_view.back(), 1.0);
    EXPECT_DOUBLE_EQ(s.objects[0].grid.back(), 0.0);
    // The headline "pooled" is the pooled classifier of per_view; "mot" needs the ground truth.
    const auto h = learn_headline(LearnHeadline::kPooled, std::nullopt, s);
    ASSERT_TRUE(h.has_value());
    EXPECT_EQ(h->classifier, per_view ? "pooled_per_view" : "pooled");
    EXPECT_DOUBLE_EQ(h->accuracy, per_view ? 1.0 : 0.5);
    EXPECT_EQ(h->names, objects);
    EXPECT_EQ(h->held_out, (std::vector<int>{1, 1}));
    EXPECT_DOUBLE_EQ(h->per_object[0], per_view ? 1.0 : 0.0);
    EXPECT_FALSE(learn_headline(LearnHeadline::kMot, std::nullopt, s).has_value());
    // The JSON: both figures, per object too, and which is learn's.
    const core::Json j = core::fields_to_json(s);
    EXPECT_EQ(j.at("per_view"), per_view);
    EXPECT_DOUBLE_EQ(j.at("pooled").get<double>(), 0.5);
    EXPECT_DOUBLE_EQ(j.at("pooled_per_view").get<double>(), 1.0);
    EXPECT_EQ(j.at("grid_per_view").size(), std::size(kLearnWordWeights));
    EXPECT_DOUBLE_EQ(j.at("objects").at(0).at("pooled_per_view").get<double>(), 1.0);
    EXPECT_EQ(j.at("objects").at(0).at("grid_per_view").size(), std::size(kLearnWordWeights));
  }
  // By default learn's pooled classifier is the pooled counts.
  EXPECT_FALSE(
      score_by_words(model, lda, training, labels, held, objects, {"book", "cd"}, 1.0).per_view);
}

TEST(Learn, HeadlineFromTheGroundTruthScore) {
  SelfSupervisionScore score;
  score.mot_accuracy = 0.25;
  score.argmax_accuracy = 0.75;
  ObjectScore o;
  o.name = "book";
  o.held_out = 20;
  o.mot_accuracy = 0.25;
  o.argmax_accuracy = 0.75;
  score.objects.push_back(o);
  const auto mot = learn_headline(LearnHeadline::kMot, score, std::nullopt);
  ASSERT_TRUE(mot.has_value());
  EXPECT_EQ(mot->classifier, "mot");
  EXPECT_DOUBLE_EQ(mot->accuracy, 0.25);
  EXPECT_EQ(mot->held_out, std::vector<int>{20});
  const auto argmax = learn_headline(LearnHeadline::kArgmax, score, std::nullopt);
  ASSERT_TRUE(argmax.has_value());
  EXPECT_EQ(argmax->classifier, "argmax");
  EXPECT_DOUBLE_EQ(argmax->per_object.at(0), 0.75);
  EXPECT_FALSE(learn_headline(LearnHeadline::kPooled, score, std::nullopt).has_value());
}

TEST(Learn, HeadlineFromTheWordsScoreTakesTheWordMultinomialsItWasScoredWith) {
  LearnWordScore words;
  words.weight = 0.25;
  words.pooled = 0.5;
  words.pooled_per_view = 0.125;
  for (const auto& [name, counts, per_view] :
       {std::tuple{"book", 0.5, 0.25}, std::tuple{"cd", 0.5, 0.0}}) {
    LearnWordObject o;
    o.name = name;
    o.held_out = 20;
    o.pooled = counts;
    o.pooled_per_view = per_view;
    words.objects.push_back(o);
  }
  const auto counts = learn_headline(LearnHeadline::kPooled, std::nullopt, words);
  ASSERT_TRUE(counts.has_value());
  EXPECT_EQ(counts->classifier, "pooled");
  EXPECT_DOUBLE_EQ(counts->accuracy, 0.5);
  EXPECT_EQ(counts->names, (std::vector<std::string>{"book", "cd"}));
  EXPECT_EQ(counts->held_out, (std::vector<int>{20, 20}));
  EXPECT_EQ(counts->per_object, (std::vector<double>{0.5, 0.5}));
  words.per_view = true;
  const auto per_view = learn_headline(LearnHeadline::kPooled, std::nullopt, words);
  ASSERT_TRUE(per_view.has_value());
  EXPECT_EQ(per_view->classifier, "pooled_per_view");
  EXPECT_DOUBLE_EQ(per_view->accuracy, 0.125);
  EXPECT_EQ(per_view->per_object, (std::vector<double>{0.25, 0.0}));
  // The MoT's figures need the ground-truth score.
  EXPECT_FALSE(learn_headline(LearnHeadline::kMot, std::nullopt, words).has_value());
}

TEST(Learn, DescriptorMatchFractionCountsDescriptorsNearerTheKnownThanTheRest) {
  // Unit vectors e0..e3 (4-D): query = {e0, e1, e2, e3 * 0.9 + e2 * 0.1}; known = {e0, e1};
  // rest = {e2, e3}. e0 and e1 match (distance 0 to known); e2 is nearer the rest; the last is
  // nearer the rest too. So 2 of 4.
  cv::Mat q = (cv::Mat_<float>(4, 4) << 1, 0, 0, 0,  //
               0, 1, 0, 0,                           //
               0, 0, 1, 0,                           //
               0, 0, 0.1F, 0.9F);
  cv::Mat known = (cv::Mat_<float>(2, 4) << 1, 0, 0, 0, 0, 1, 0, 0);
  cv::Mat rest = (cv::Mat_<float>(2, 4) << 0, 0, 1, 0, 0, 0, 0, 1);
  EXPECT_DOUBLE_EQ(descriptor_match_fraction(q, known, rest, 0.8), 0.5);
  // Known = the rest: nothing is nearer the known than ratio x the rest.
  EXPECT_DOUBLE_EQ(descriptor_match_fraction(q, rest, rest, 0.8), 0.0);
  // No rest: every descriptor with a neighbour in the known matches.
  EXPECT_DOUBLE_EQ(descriptor_match_fraction(q, known, cv::Mat(), 0.8), 1.0);
  // Nothing to match, or nothing known.
  EXPECT_DOUBLE_EQ(descriptor_match_fraction(cv::Mat(), known, rest, 0.8), 0.0);
  EXPECT_DOUBLE_EQ(descriptor_match_fraction(q, cv::Mat(), rest, 0.8), 0.0);
  // The ratio: e0 + 0.5 e2 (normalised) lies 0.46 from e0 and 1.05 from e2 (0.44 times):
  // matched at 0.5, not at 0.4.
  cv::Mat near = (cv::Mat_<float>(1, 4) << 0.894F, 0, 0.447F, 0);
  EXPECT_DOUBLE_EQ(descriptor_match_fraction(near, known, rest, 0.5), 1.0);
  EXPECT_DOUBLE_EQ(descriptor_match_fraction(near, known, rest, 0.4), 0.0);
  // Bad input.
  EXPECT_THROW((void)descriptor_match_fraction(q, known, rest, 0.0), Error);
  EXPECT_THROW((void)descriptor_match_fraction(q, known, rest, 1.5), Error);
  cv::Mat wide(2, 5, CV_32F, cv::Scalar(0));
  EXPECT_THROW((void)descriptor_match_fraction(q, wide, rest, 0.8), Error);
  cv::Mat doubles;
  known.convertTo(doubles, CV_64F);
  EXPECT_THROW((void)descriptor_match_fraction(q, doubles, rest, 0.8), Error);
}

TEST(Learn, TheVocabularyIsKmeansOverEveryDescriptorOfTheViews) {
  // learn's vocabulary (views_vocabulary with sample 0, all cores): k-means over every
  // descriptor of the views, as build_vocabulary over them with the seed; the clutter
  // experiment's sample (here 5 of 11 descriptors) would cap it at 5 words.
  cv::Mat a(6, 128, CV_32F);
  cv::Mat b(5, 128, CV_32F);
  cv::randu(a, 0.0F, 1.0F);
  cv::randu(b, 0.5F, 2.0F);
  const std::vector<cv::Mat> views{a, b};
  cv::Mat stacked;
  cv::vconcat(views, stacked);
  features::KmeansOptions ko;
  ko.words = 4;
  ko.seed = 9;
  const features::Vocabulary w = features::build_vocabulary(stacked, ko).vocabulary;
  const features::Vocabulary v = views_vocabulary(views, 4, 9, 0, 0);
  EXPECT_EQ(features::bag_of_words(v, stacked), features::bag_of_words(w, stacked));
  EXPECT_EQ(views_vocabulary(views, 50, 9, 0, 0).size(), 11);  // every descriptor
  EXPECT_EQ(views_vocabulary(views, 50, 9, 5, 0).size(), 5);   // a sample of 5
  // The threads change no word.
  EXPECT_EQ(features::bag_of_words(views_vocabulary(views, 4, 9, 0, 1), stacked),
            features::bag_of_words(v, stacked));
  EXPECT_THROW((void)views_vocabulary(views, 4, 9, -1, 0), Error);
  EXPECT_THROW((void)views_vocabulary(views, 4, 9, 0, -1), Error);
}

TEST(Learn, AnExistingOutIsRefusedWithoutOverwrite) {
  namespace fs = std::filesystem;
  const test::TempDir dir("proprio_learn_test_");
  const fs::path& d = dir.path();
  LearnOptions o;
  o.out = d;
  o.progress = false;
  try {
    (void)run_learn(o, core::Provenance::current({"learn_test"}, 1));
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("already exists"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(fs::exists(d));
}

// A robot that sees and refuses every push (as a real arm's driver would a path it cannot
// follow); with `blind`, every look is a blank image; with `offset`, it pushes that far (m) beside
// where it was asked, in the air over the empty table: the push moves nothing.
class FaultyRobot final : public robot::Robot {
 public:
  FaultyRobot(sim::SimulatedRobot& inner, bool blind, bool refuse, Eigen::Vector2d offset)
      : inner_(inner), blind_(blind), refuse_(refuse), offset_(std::move(offset)) {}
  robot::Look look() override {
    robot::Look l = inner_.look();
    if (blind_) l.image.setTo(cv::Scalar(128, 128, 128));
    return l;
  }
  [[nodiscard]] geometry::Camera camera() const override { return inner_.camera(); }
  [[nodiscard]] const robot::Arm& arm() const override { return inner_.arm(); }
  [[nodiscard]] robot::JointVector joints() const override { return inner_.joints(); }
  void hold_still(double seconds) override { inner_.hold_still(seconds); }
  robot::PushReport push(const robot::TablePush& push,
                         const robot::PushRecording& recording) override {
    if (refuse_ && asked_++ >= allow) {
      ++refused;
      throw Error("push: the arm's driver refused the path");
    }
    robot::TablePush p = push;
    p.start += offset_;
    p.end += offset_;
    return inner_.push(p, recording);
  }
  int refused = 0;
  int allow = 0;  ///< with `refuse`: the first `allow` pushes are done all the same

 private:
  int asked_ = 0;
  sim::SimulatedRobot& inner_;
  bool blind_;
  bool refuse_;
  Eigen::Vector2d offset_;
};

class NullAttendant final : public TableAttendant {
 public:
  std::string rescatter(int /*round*/) override { return {}; }
};

std::string events_of(const std::filesystem::path& log) {
  std::ifstream in(log);
  std::string all;
  std::string line;
  while (std::getline(in, line)) {
    const core::Json j = core::Json::parse(line);
    all += j.value("event", std::string()) + ":" + j.value("fault", std::string()) + " ";
  }
  return all;
}

TEST(Learn, FaultsAreLoggedAndTheRunStillCompletes) {
  namespace fs = std::filesystem;
  const test::TempDir dir("proprio_learn_faults_");
  const fs::path& d = dir.path();
  LearnOptions o;
  o.objects = "book";
  o.clutter = "bottle";
  o.pushes = 2;
  o.width = 200;
  o.height = 150;
  o.progress = false;
  o.overwrite = true;
  const sim::ObjectCatalogue catalogue = sim::ObjectCatalogue::load_default();
  sim::TableOptions table;
  table.objects = {"book", "bottle"};
  table.seed = 2;
  table.width = o.width;
  table.height = o.height;
  sim::SimulatedRobot sim_robot(table, catalogue);
  const auto prov = core::Provenance::current({"learn_test"}, 1);
  {
    FaultyRobot robot(sim_robot, false, true, Eigen::Vector2d::Zero());
    NullAttendant attendant;
    o.out = d / "refused";
    const LearnResult r = run_learn(o, robot, attendant, 1, prov);
    EXPECT_GT(robot.refused, 0);
    EXPECT_EQ(r.summary.views, 0);
    const std::string ev = events_of(o.out / "decisions.jsonl");
    EXPECT_NE(ev.find("fault:robot-refused"), std::string::npos) << ev;
    EXPECT_NE(ev.find("rechoose:"), std::string::npos) << ev;
    EXPECT_NE(ev.find("no-views:"), std::string::npos) << ev;
    const core::Json j = core::read_json(o.out / "learn.json");
    EXPECT_TRUE(j["complete"].get<bool>());
    EXPECT_FALSE(fs::exists(o.out / "INCOMPLETE"));
    for (const auto& p : j["pushes"]) EXPECT_FALSE(p["executed"].get<bool>());
  }
  {
    // The first push is done, then every one refused: after kMaxFailures refusals in a row the
    // learner moves on with what it has (logged "stuck"), not trying the same object again and
    // again.
    FaultyRobot robot(sim_robot, false, true, Eigen::Vector2d::Zero());
    robot.allow = 1;
    NullAttendant attendant;
    LearnOptions s = o;
    s.pushes = 6;
    s.out = d / "stuck";
    const LearnResult r = run_learn(s, robot, attendant, 1, prov);
    const std::string ev = events_of(s.out / "decisions.jsonl");
    EXPECT_NE(ev.find("fault:stuck"), std::string::npos) << ev;
    EXPECT_LE(robot.refused, 3) << ev;
    EXPECT_EQ(r.summary.pushes_executed, 1);
  }
  {
    FaultyRobot robot(sim_robot, true, false, Eigen::Vector2d::Zero());
    NullAttendant attendant;
    o.out = d / "blind";
    (void)run_learn(o, robot, attendant, 1, prov);
    EXPECT_NE(events_of(o.out / "decisions.jsonl").find("fault:no-blobs"), std::string::npos);
  }
  {
    // Pushes 12 cm beside the object (toward the robot): they move nothing.
    FaultyRobot robot(sim_robot, false, false, Eigen::Vector2d(-0.12, 0.0));
    NullAttendant attendant;
    o.out = d / "missed";
    (void)run_learn(o, robot, attendant, 1, prov);
    const std::string ev = events_of(o.out / "decisions.jsonl");
    EXPECT_NE(ev.find("fault:moved-nothing"), std::string::npos) << ev;
  }
}

int count_of(const std::string& all, const std::string& what) {
  int n = 0;
  for (auto at = all.find(what); at != std::string::npos; at = all.find(what, at + 1)) ++n;
  return n;
}

// A small table (book and bottle, 200 x 150) and options for the turn tests below.
struct SmallTable {
  SmallTable() {
    o.objects = "book";
    o.clutter = "bottle";
    o.pushes = 1;
    o.width = 200;
    o.height = 150;
    o.progress = false;
    o.overwrite = true;
    table.objects = {"book", "bottle"};
    table.seed = 2;
    table.width = o.width;
    table.height = o.height;
  }
  LearnOptions o;
  sim::TableOptions table;
  const sim::ObjectCatalogue catalogue = sim::ObjectCatalogue::load_default();

  // One run of learn on this table (a fresh robot, no attendant) with `o` changed by `set`, its
  // output in `out`, for `classes` classes: each setting a test compares starts from the same
  // table.
  template <class Set>
  LearnResult run(const std::filesystem::path& out, int classes, Set set) const {
    sim::SimulatedRobot robot(table, catalogue);
    NullAttendant attendant;
    LearnOptions opts = o;
    set(opts);
    opts.out = out;
    return run_learn(opts, robot, attendant, classes, core::Provenance::current({"learn_test"}, 1));
  }
};

TEST(Learn, AMaskOverMuchOfTheImageGivesNoViews) {
  // The same pushes with and without the cap: at 0.2 % of the image every push's mask is "the
  // scene" (the book alone fills more), logged and without views; at 1 (off) they give views.
  namespace fs = std::filesystem;
  const test::TempDir dir("proprio_learn_scene_");
  const SmallTable t;
  const LearnResult off = t.run(dir.path() / "off", 1, [](LearnOptions& o) { o.pushes = 2; });
  EXPECT_GT(off.summary.views, 0);
  EXPECT_EQ(count_of(events_of(dir.path() / "off" / "decisions.jsonl"), "fault:mask-is-the-scene"),
            0);
  const LearnResult tiny = t.run(dir.path() / "tiny", 1, [](LearnOptions& o) {
    o.pushes = 2;
    o.max_mask_share = 0.002;
  });
  EXPECT_EQ(tiny.summary.views, 0);
  const std::string ev = events_of(dir.path() / "tiny" / "decisions.jsonl");
  EXPECT_GT(count_of(ev, "fault:mask-is-the-scene"), 0) << ev;
  const core::Json j = core::read_json(dir.path() / "tiny" / "learn.json");
  bool said = false;
  for (const auto& p : j["pushes"]) {
    said = said || p["outcome"].get<std::string>().find("not one object") != std::string::npos;
  }
  EXPECT_TRUE(said);
  LearnOptions bad;
  bad.max_mask_share = 0;
  EXPECT_THROW(bad.validate(), Error);
}

TEST(Learn, ViewsFromTheLooksAfterOrBeforeThePush) {
  // views blob: a push gives one view, the look after it cut out by its object's blob; a push
  // whose object has no blob there gives its motion views instead. Either way every executed
  // push that gave views says which, and the views are the class's.
  const test::TempDir dir("proprio_learn_blob_views_");
  const SmallTable t;
  const LearnResult r = t.run(dir.path() / "blob", 1, [](LearnOptions& o) {
    o.pushes = 3;
    o.views = LearnViews::kAfter;
  });
  EXPECT_GT(r.summary.views, 0);
  const core::Json j = core::read_json(dir.path() / "blob" / "learn.json");
  int after = 0;
  int views = 0;
  for (const auto& p : j["pushes"]) {
    const int n = p["views"].get<int>();
    views += n;
    if (n == 0) continue;
    const std::string outcome = p["outcome"].get<std::string>();
    if (outcome.find("the look after the push") != std::string::npos) {
      EXPECT_EQ(n, 1) << outcome;
      ++after;
    } else {
      EXPECT_NE(outcome.find("its motion's"), std::string::npos) << outcome;
    }
  }
  EXPECT_GT(after, 0);
  EXPECT_EQ(views, r.summary.views);
  // The motion views of the same table: more views a push.
  const LearnResult m = t.run(dir.path() / "motion", 1, [](LearnOptions& o) {
    o.pushes = 3;
    o.views = LearnViews::kMotion;
  });
  EXPECT_GT(m.summary.views, r.summary.views);
  // views before: one view a push that moved something, the look before it; the pushes are
  // the motion run's (the views do not steer the robot): as many executed, no more views than
  // pushes.
  const LearnResult b = t.run(dir.path() / "before", 1, [](LearnOptions& o) {
    o.pushes = 3;
    o.views = LearnViews::kBefore;
  });
  EXPECT_GT(b.summary.views, 0);
  EXPECT_LE(b.summary.views, b.summary.pushes_executed);
  EXPECT_EQ(b.summary.pushes_executed, m.summary.pushes_executed);
  // The document held by name: a range over a temporary's member would outlive it.
  const core::Json jb = core::read_json(dir.path() / "before" / "learn.json");
  for (const auto& p : jb["pushes"]) {
    if (p["views"].get<int>() == 0) continue;
    EXPECT_EQ(p["views"].get<int>(), 1);
    EXPECT_NE(p["outcome"].get<std::string>().find("the look before the push"), std::string::npos);
  }
  // views both: motion's views and the before view entered as many times: a push that gave n
  // motion views gives 2n (n without a before view), the same pushes.
  const LearnResult w = t.run(dir.path() / "both", 1, [](LearnOptions& o) {
    o.pushes = 3;
    o.views = LearnViews::kBoth;
  });
  EXPECT_EQ(w.summary.pushes_executed, m.summary.pushes_executed);
  const core::Json pm = core::read_json(dir.path() / "motion" / "learn.json")["pushes"];
  const core::Json pw = core::read_json(dir.path() / "both" / "learn.json")["pushes"];
  ASSERT_EQ(pm.size(), pw.size());
  int doubled = 0;
  for (std::size_t i = 0; i < pm.size(); ++i) {
    const int n = pm[i]["views"].get<int>();
    const int k = pw[i]["views"].get<int>();
    EXPECT_TRUE(k == 2 * n || k == n) << pw[i]["outcome"];
    if (n > 0 && k == 2 * n) {
      ++doubled;
      EXPECT_NE(pw[i]["outcome"].get<std::string>().find("weighing as many"), std::string::npos);
    }
  }
  EXPECT_GT(doubled, 0);
  EXPECT_GT(w.summary.views, m.summary.views);
}

TEST(Learn, ATurnThatGaveNoViewsIsRetriedButNotOnTheBlobsItTried) {
  // Every push refused: the class gets no views. With --rounds 3 the class is tried again on
  // later turns (logged "retry"), but not on the blobs an earlier turn tried: no more pushes
  // are asked for than with one turn.
  namespace fs = std::filesystem;
  const test::TempDir dir("proprio_learn_rounds_");
  SmallTable t;
  const auto prov = core::Provenance::current({"learn_test"}, 1);
  int asked[2] = {0, 0};
  std::string events[2];
  for (int i = 0; i < 2; ++i) {
    sim::SimulatedRobot sim_robot(t.table, t.catalogue);
    FaultyRobot robot(sim_robot, false, true, Eigen::Vector2d::Zero());
    NullAttendant attendant;
    LearnOptions o = t.o;
    o.rounds = i == 0 ? 0 : 3;
    o.out = dir.path() / (i == 0 ? "one" : "three");
    const LearnResult r = run_learn(o, robot, attendant, 1, prov);
    EXPECT_EQ(r.summary.views, 0);
    asked[i] = robot.refused;
    events[i] = events_of(o.out / "decisions.jsonl");
  }
  EXPECT_EQ(count_of(events[0], "retry:"), 0) << events[0];
  EXPECT_EQ(count_of(events[1], "retry:"), 2) << events[1];
  EXPECT_GT(asked[0], 0);
  EXPECT_EQ(asked[1], asked[0]) << events[1];
}

TEST(Learn, TurnsStopOnceEveryClassHasViews) {
  const test::TempDir dir("proprio_learn_rounds_done_");
  const SmallTable t;
  const std::filesystem::path out = dir.path() / "run";
  const LearnResult r = t.run(out, 1, [](LearnOptions& o) { o.rounds = 4; });
  ASSERT_GT(r.summary.views, 0) << events_of(out / "decisions.jsonl");
  const std::string ev = events_of(out / "decisions.jsonl");
  EXPECT_EQ(count_of(ev, "retry:"), 0) << ev;
  EXPECT_EQ(count_of(ev, "choose:"), 1) << ev;
}

TEST(Learn, TheTouchCutOptionIsRecordedAndBothSettingsRun) {
  // --seg-touch-fm (LearnOptions::dense.touch_fm, passed to segment_ml with the push's other
  // dense options; its effect on a map is tested in ml_segmentation_test): a run with it off
  // and one with it on both segment their first push, and learn.json records the setting. (On
  // this small plain table the first push's map is the same either way.)
  namespace fs = std::filesystem;
  const test::TempDir dir("proprio_learn_touch_fm_");
  const SmallTable t;
  for (int i = 0; i < 2; ++i) {
    const double touch_fm = i == 0 ? 0.0 : 1.0;
    const fs::path out = dir.path() / (i == 0 ? "off" : "on");
    (void)t.run(out, 1, [&](LearnOptions& o) { o.dense.touch_fm = touch_fm; });
    const core::Json j = core::read_json(out / "learn.json");
    EXPECT_DOUBLE_EQ(j["options"]["seg_touch_fm"].get<double>(), touch_fm);
    ASSERT_FALSE(j["pushes"].empty());
    ASSERT_TRUE(j["pushes"][0]["executed"].get<bool>());
    EXPECT_TRUE(fs::exists(out / j["pushes"][0]["dir"].get<std::string>() / "map.png"));
  }
}

TEST(Learn, ColourWordsFollowTheSiftWordsInEveryViewsDocument) {
  // --colour-words: LDA is trained over the vocabulary's words and the 28 colour words after
  // them (every feature gives one of each); off, the model has the vocabulary's words only.
  namespace fs = std::filesystem;
  const test::TempDir dir("proprio_learn_colour_");
  const SmallTable t;
  for (const bool colour : {false, true}) {
    const fs::path out = dir.path() / (colour ? "on" : "off");
    const LearnResult r = t.run(out, 1, [&](LearnOptions& o) {
      o.colour_words = colour;
      o.colour_weight = 1;  // each colour word once: half the tokens
    });
    ASSERT_GT(r.summary.views, 0);
    const int v = features::read_vocabulary(out / "vocabulary.vocab").size();
    const topics::LdaModel lda = topics::load_lda_model(out / "lda.model");
    const int k = features::ColourWordOptions{}.count();
    ASSERT_EQ(lda.num_words(), colour ? v + k : v);
    EXPECT_EQ(core::read_json(out / "learn.json")["options"]["colour_words"].get<bool>(), colour);
    if (!colour) continue;
    // topics x words, rows sum to 1. On this small table the views fill one topic; the others
    // are the prior's (every word alike: the colour words' share is k / (v + k)). The views'
    // topic holds about half colour, as every feature gives one word of each.
    const Eigen::VectorXd colour_mass = lda.topic_word().rightCols(k).rowwise().sum();
    EXPECT_GT(colour_mass.maxCoeff(), 0.35);
    EXPECT_LT(colour_mass.maxCoeff(), 0.65);
    EXPECT_GT(colour_mass.minCoeff(), 0.9 * k / static_cast<double>(v + k));
  }
}

TEST(Learn, ColourWeightMakesTheTopicsFollowTheColourWords) {
  // --colour-weight 8: the same pushes and views (the loop does not read the topic model); the
  // topic model's documents count each colour word 8 times, so the views' topic holds about 8/9
  // colour (about half with weight 1); recorded in learn.json.
  namespace fs = std::filesystem;
  const test::TempDir dir("proprio_learn_colour_weight_");
  const SmallTable t;
  const int k = features::ColourWordOptions{}.count();
  std::vector<double> mass;
  std::vector<int> views;
  for (const int weight : {1, 8}) {
    const fs::path out = dir.path() / std::to_string(weight);
    const LearnResult r = t.run(out, 1, [&](LearnOptions& o) { o.colour_weight = weight; });
    ASSERT_GT(r.summary.views, 0);
    views.push_back(r.summary.views);
    const topics::LdaModel lda = topics::load_lda_model(out / "lda.model");
    mass.push_back(lda.topic_word().rightCols(k).rowwise().sum().maxCoeff());
    // The model records the weights (lda-model format 2), so its readers weigh alike.
    EXPECT_EQ(lda.word_weights,
              weight == 1 ? std::vector<std::int32_t>{}
                          : topics::weights_from(lda.num_words(), lda.num_words() - k, weight));
    EXPECT_EQ(core::read_json(out / "learn.json")["options"]["colour_weight"].get<int>(), weight);
  }
  EXPECT_EQ(views[0], views[1]);
  EXPECT_LT(mass[0], 0.65);
  EXPECT_GT(mass[1], 0.8);
  LearnOptions o;
  EXPECT_EQ(o.colour_weight, 128);  // the default since session 46
  o.colour_words = false;           // the weight then has nothing to weigh, and is not refused
  EXPECT_NO_THROW(o.validate());
  o.colour_weight = 0;
  EXPECT_THROW(o.validate(), Error);
}

TEST(Learn, ABlobThatTheWordsSayIsAKnownObjectIsNotANewClass) {
  // Two classes, one push each. With known_margin huge every blob is within it of the first
  // object's own views: the second turn finds only known objects (by their words) and learns
  // nothing; off (the default), it chooses the least likely blob. The choice's scores name the
  // object whose model gives each blob's best score.
  const test::TempDir dir("proprio_learn_known_");
  const SmallTable t;
  for (const double margin : {-1.0, 1000.0}) {
    const std::filesystem::path out = dir.path() / (margin < 0 ? "off" : "on");
    const LearnResult r = t.run(out, 2, [&](LearnOptions& o) { o.known_margin = margin; });
    ASSERT_GT(r.summary.views, 0);
    std::ifstream in(out / "decisions.jsonl");
    std::string line;
    int second_choice = -2;
    bool by_words = false;
    while (std::getline(in, line)) {
      const core::Json j = core::Json::parse(line);
      if (j.value("object", -1) != 1) continue;
      if (j["event"] == "choose") {
        second_choice = j["blob"].get<int>();
        for (const auto& s : j["scores"]) EXPECT_EQ(s["best_object"].get<int>(), 0) << line;
      }
      if (j.value("fault", std::string()) == "only-known-objects") by_words = true;
    }
    if (margin < 0) {
      EXPECT_GE(second_choice, 0);
      EXPECT_FALSE(by_words);
    } else {
      EXPECT_EQ(second_choice, -2);
      EXPECT_TRUE(by_words);
      EXPECT_EQ(r.objects.at(1).views, 0);
    }
  }
}

TEST(Learn, AnIdentityCheckMergesAFirstPushOfAKnownObjectAndTheTurnChoosesAgain) {
  // Two classes, one push each. The second turn's first push that gave views is checked against
  // the first object (decisions.jsonl "identity", its scores against object 0). With
  // identity_margin huge every object is within it of object 0: the push is merged into object
  // 0 (its views counted there) and the turn chooses again: a "rechoose" by identity, or, with
  // both objects of this table known, the only-known-objects fault; off (the default) the check
  // is logged only and the second class keeps its views.
  const test::TempDir dir("proprio_learn_identity_");
  const SmallTable t;
  for (const double margin : {-1.0, 1000.0}) {
    const std::filesystem::path out = dir.path() / (margin < 0 ? "off" : "on");
    const LearnResult r = t.run(out, 2, [&](LearnOptions& o) {
      o.identity_margin = margin;
      o.pushes =
          2;  // the second turn's first push on this table moves nothing: its second has views
    });
    ASSERT_GT(r.summary.views, 0) << events_of(out / "decisions.jsonl");
    std::ifstream in(out / "decisions.jsonl");
    std::string line;
    int checks = 0;
    int merged = 0;
    int rechosen = 0;
    int only_known = 0;
    while (std::getline(in, line)) {
      const core::Json j = core::Json::parse(line);
      if (j.value("fault", std::string()) == "only-known-objects") ++only_known;
      if (j["event"] == "identity") {
        ++checks;
        EXPECT_EQ(j["object"].get<int>(), 1) << line;
        ASSERT_FALSE(j["scores"].empty()) << line;
        EXPECT_EQ(j["scores"][0]["best_object"].get<int>(), 0) << line;
        if (j.contains("why")) ++merged;
      }
      if (j["event"] == "rechoose" && j.value("why", std::string()).rfind("identity", 0) == 0) {
        ++rechosen;
      }
    }
    const core::Json rec = core::read_json(out / "learn.json");
    EXPECT_DOUBLE_EQ(rec["options"]["identity_margin"].get<double>(), margin);
    if (margin < 0) {
      EXPECT_GE(checks, 1);
      EXPECT_EQ(merged, 0);
      EXPECT_EQ(rechosen, 0);
      EXPECT_EQ(only_known, 0);
      EXPECT_GT(r.objects.at(1).views, 0);
    } else {
      ASSERT_GE(merged, 1) << events_of(out / "decisions.jsonl");
      EXPECT_LE(merged, 2);  // at most twice a turn
      EXPECT_GE(rechosen + only_known, 1);
      // The merged pushes' views are object 0's: the first class has more views than its own
      // push gave.
      int views_of_0 = 0;
      for (const LearnPush& p : r.pushes) views_of_0 += p.object == 0 ? p.views : 0;
      EXPECT_GT(r.objects.at(0).views, views_of_0);
    }
  }
}

TEST(Learn, HoldTargetAimsTheNextPushAtTheBlobWhereThePushMeantToLandTheObject) {
  // One class, three pushes. With hold_target, a push that landed its object within 0.05 m of
  // the plan's target holds it there: the turn's next push is located "held" (the blob nearest
  // that target), not by the segmented region; off (the default) no push is located "held".
  const test::TempDir dir("proprio_learn_hold_");
  const SmallTable t;
  for (const bool hold : {false, true}) {
    const std::filesystem::path out = dir.path() / (hold ? "on" : "off");
    const LearnResult r = t.run(out, 1, [&](LearnOptions& o) {
      o.pushes = 3;
      o.hold_target = hold;
      o.region_agree = 0;  // its own hold comes first (the default since session 39)
    });
    ASSERT_GT(r.summary.views, 0) << events_of(out / "decisions.jsonl");
    const core::Json rec = core::read_json(out / "learn.json");
    EXPECT_EQ(rec["options"]["hold_target"].get<bool>(), hold);
    int held = 0;
    for (std::size_t i = 0; i < r.pushes.size(); ++i) {
      if (r.pushes[i].located != "held") continue;
      ++held;
      EXPECT_GT(i, 0U);  // never the turn's first push (that one is "chosen")
    }
    if (hold) {
      EXPECT_GE(held, 1) << events_of(out / "decisions.jsonl");
    } else {
      EXPECT_EQ(held, 0);
    }
  }
}

TEST(Learn, RegionAgreeNamesNoCandidateFarFromWhereThePushMeantToPutTheObject) {
  // One class, three pushes. Off (the default), the turn's later pushes are located by the last
  // push's segmented region ("segmented"). With region_agree at 1 mm no blob's centre lies that
  // near a push's target: the region names no candidate (logged: "region-agree" events, or the
  // look's "candidates" event with depth candidates), so no push is located "segmented" (and
  // the turn ends: the object is lost); at 0.5 m every candidate is near enough and the region
  // names the same candidates as off.
  const test::TempDir dir("proprio_learn_agree_");
  const SmallTable t;
  for (const double agree : {0.0, 0.001, 0.5}) {
    const std::filesystem::path out = dir.path() / std::to_string(agree);
    const LearnResult r = t.run(out, 1, [&](LearnOptions& o) {
      o.pushes = 3;
      o.region_agree = agree;
    });
    ASSERT_GT(r.summary.views, 0) << events_of(out / "decisions.jsonl");
    const core::Json rec = core::read_json(out / "learn.json");
    EXPECT_DOUBLE_EQ(rec["options"]["region_agree"].get<double>(), agree);
    int segmented = 0;
    for (const LearnPush& p : r.pushes) segmented += p.located == "segmented" ? 1 : 0;
    int moved = 0;  // candidates events whose region was moved off a candidate by region_agree
    std::ifstream in(out / "decisions.jsonl");
    std::string line;
    while (std::getline(in, line)) {
      const core::Json j = core::Json::parse(line);
      if (j["event"] == "region-agree" ||
          (j["event"] == "candidates" &&
           j.value("by", std::string()).find("'s region: candidate") != std::string::npos)) {
        ++moved;
      }
    }
    int executed = 0;
    for (const LearnPush& p : r.pushes) executed += p.executed ? 1 : 0;
    if (agree == 0.001) {
      EXPECT_EQ(segmented, 0) << events_of(out / "decisions.jsonl");
      EXPECT_GE(moved, 1) << events_of(out / "decisions.jsonl");
      // ... and no blob lies within 1 mm of the first push's target: the object is lost there,
      // the turn ends after its first executed push (no push aimed at whatever lies nearest).
      EXPECT_EQ(executed, 1) << events_of(out / "decisions.jsonl");
      EXPECT_NE(events_of(out / "decisions.jsonl").find("fault:lost"), std::string::npos);
    } else {
      EXPECT_GE(segmented, 1) << events_of(out / "decisions.jsonl");
      EXPECT_EQ(moved, 0) << events_of(out / "decisions.jsonl");
    }
  }
}

TEST(Learn, LostRechooseChoosesAgainInsteadOfEndingTheTurn) {
  // One class, three pushes, region_agree at 1 mm: no blob lies that near a push's target, so
  // the object is lost after every executed push. Without lost_rechoose the turn ends after its
  // first executed push; with it the turn chooses a blob again (a "rechoose" event naming
  // region_agree) and its remaining pushes are made: more than one executed push.
  const test::TempDir dir("proprio_learn_lost_");
  const SmallTable t;
  for (const bool again : {false, true}) {
    const std::filesystem::path out = dir.path() / (again ? "on" : "off");
    const LearnResult r = t.run(out, 1, [&](LearnOptions& o) {
      o.pushes = 3;
      o.region_agree = 0.001;
      o.lost_rechoose = again;
    });
    ASSERT_GT(r.summary.views, 0) << events_of(out / "decisions.jsonl");
    const core::Json rec = core::read_json(out / "learn.json");
    EXPECT_EQ(rec["options"]["lost_rechoose"].get<bool>(), again);
    int executed = 0;
    for (const LearnPush& p : r.pushes) executed += p.executed ? 1 : 0;
    int rechosen = 0;  // rechoose events after a lost object
    std::ifstream in(out / "decisions.jsonl");
    std::string line;
    while (std::getline(in, line)) {
      const core::Json j = core::Json::parse(line);
      if (j["event"] == "rechoose" &&
          j.value("why", std::string()).find("region_agree: lost") != std::string::npos) {
        ++rechosen;
      }
    }
    const std::string events = events_of(out / "decisions.jsonl");
    EXPECT_NE(events.find("fault:lost"), std::string::npos) << events;
    if (again) {
      EXPECT_GE(rechosen, 1) << events;
      EXPECT_GT(executed, 1) << events;
    } else {
      EXPECT_EQ(rechosen, 0) << events;
      EXPECT_EQ(executed, 1) << events;
    }
  }
}

TEST(Learn, ASecondPassPushesEachLearnedObjectAgainWhereItWasLeft) {
  // One class, two pushes a turn. With passes 2 the class's object is looked for again after
  // the turns (a "revisit" event: where, how located), pushed again with its views going to the
  // same class (pushes marked pass 2, no second choice): more executed pushes and views than
  // with one pass. With region_agree at 1 mm the turn's object is lost after its first push
  // (no blob that near its target) and the revisit finds no blob there: skipped, the reason
  // logged, no push more than with one pass.
  const test::TempDir dir("proprio_learn_passes_");
  const SmallTable t;
  struct Got {
    int executed = 0;
    int second = 0;  // pushes of pass 2
    int views = 0;
    std::vector<core::Json> revisits;
    std::string events;
  };
  const auto run = [&](const std::string& name, int passes, double agree, bool td = false) {
    const std::filesystem::path out = dir.path() / name;
    const LearnResult r = t.run(out, 1, [&](LearnOptions& o) {
      o.pushes = 2;
      o.passes = passes;
      o.region_agree = agree;
      o.revisit_top_down = td;
    });
    Got g;
    g.views = r.summary.views;
    const core::Json rec = core::read_json(out / "learn.json");
    EXPECT_EQ(rec["options"]["passes"].get<int>(), passes);
    for (const auto& p : rec["pushes"]) {
      g.executed += p["executed"].get<bool>() ? 1 : 0;
      if (p.contains("pass")) {
        EXPECT_EQ(p["pass"].get<int>(), 2);
        EXPECT_EQ(p["class"], rec["pushes"][0]["class"]);  // the same class
        ++g.second;
      }
    }
    std::ifstream in(out / "decisions.jsonl");
    std::string line;
    while (std::getline(in, line)) {
      const core::Json j = core::Json::parse(line);
      if (j["event"] == "revisit") g.revisits.push_back(j);
    }
    g.events = events_of(out / "decisions.jsonl");
    return g;
  };
  const Got one = run("one", 1, 0.0);
  const Got two = run("two", 2, 0.0);
  ASSERT_GT(one.views, 0) << one.events;
  EXPECT_TRUE(one.revisits.empty()) << one.events;
  EXPECT_EQ(one.second, 0);
  ASSERT_EQ(two.revisits.size(), 1U) << two.events;
  const core::Json& rv = two.revisits.front();
  EXPECT_EQ(rv["pass"].get<int>(), 2);
  EXPECT_EQ(rv["object"].get<int>(), 0);
  EXPECT_EQ(rv["at"].size(), 2U);
  EXPECT_FALSE(rv.value("located", std::string()).empty()) << rv.dump();
  EXPECT_FALSE(rv.contains("why")) << rv.dump();
  EXPECT_GE(two.second, 1) << two.events;
  EXPECT_GT(two.executed, one.executed) << two.events;
  EXPECT_GT(two.views, one.views) << two.events;
  EXPECT_EQ(count_of(two.events, "choose:"), 1) << two.events;  // no second choice
  // Lost where its last push meant to put it: the revisit finds nothing there and is skipped.
  const Got lost_one = run("lost1", 1, 0.001);
  const Got lost = run("lost2", 2, 0.001);
  ASSERT_EQ(lost.revisits.size(), 1U) << lost.events;
  EXPECT_NE(lost.revisits.front().value("why", std::string()).find("no blob within"),
            std::string::npos)
      << lost.revisits.front().dump();
  EXPECT_FALSE(lost.revisits.front().contains("located"));
  EXPECT_EQ(lost.second, 0) << lost.events;
  EXPECT_EQ(lost.executed, lost_one.executed) << lost.events;
  // revisit_top_down: not near its last target, the revisit looks for it top-down (a
  // "recognise" event of the class during the revisit); found, the pass pushes it, else the
  // reason says so. Without it, no recognition is tried.
  const Got td = run("lost2td", 2, 0.001, true);
  ASSERT_EQ(td.revisits.size(), 1U) << td.events;
  const auto recognised = [](const std::string& ev) {
    return count_of(ev.substr(ev.find("move-on:")), "recognise:");
  };
  EXPECT_EQ(recognised(lost.events), 0) << lost.events;
  EXPECT_EQ(recognised(td.events), 1) << td.events;
  const core::Json& t2 = td.revisits.front();
  if (t2.contains("why")) {
    EXPECT_NE(t2["why"].get<std::string>().find("top-down"), std::string::npos) << t2.dump();
    EXPECT_EQ(td.second, 0) << td.events;
  } else {
    EXPECT_EQ(t2.value("located", std::string()), "top-down") << t2.dump();
    EXPECT_GE(td.second, 1) << td.events;
  }
}

TEST(Learn, PassesAreValidated) {
  LearnOptions o;
  EXPECT_EQ(o.passes, 1);  // off by default (session 35, second round)
  o.passes = 0;
  EXPECT_THROW(o.validate(), Error);
  o.passes = 101;
  EXPECT_THROW(o.validate(), Error);
  o.passes = 2;
  EXPECT_NO_THROW(o.validate());
  o.revisit_top_down = true;  // needs region_agree > 0 and passes > 1
  o.region_agree = 0;
  EXPECT_THROW(o.validate(), Error);
  o.region_agree = 0.08;  // the default since session 39
  EXPECT_NO_THROW(o.validate());
  o.passes = 1;
  EXPECT_THROW(o.validate(), Error);
}

TEST(Learn, KeepInReachKeepsEveryPushTargetInsideTheAreaTheArmCanPushAgain) {
  // One object pushed 8 times. With keep_in_reach every planned push's target lies inside the
  // area the arm can push it again (within 0.36 m of the base axis, beyond 0.16 m, at least
  // 0.12 m in front of the base; the planner samples targets within 0.01 m of the given one);
  // off, the turn's pushes carry it further out.
  const test::TempDir dir("proprio_learn_reach_");
  const SmallTable t;
  int outside[2] = {0, 0};
  double furthest[2] = {0, 0};
  for (const bool keep : {false, true}) {
    const std::filesystem::path out = dir.path() / (keep ? "on" : "off");
    const LearnResult r = t.run(out, 1, [&](LearnOptions& o) {
      o.learn_clutter = false;
      o.pushes = 8;
      o.keep_in_reach = keep;
      o.region_agree = 0;  // as measured (session 27); a lost object would end the turn
    });
    ASSERT_GT(r.summary.views, 0) << events_of(out / "decisions.jsonl");
    const core::Json rec = core::read_json(out / "learn.json");
    EXPECT_EQ(rec["options"]["keep_in_reach"].get<bool>(), keep);
    for (const LearnPush& p : r.pushes) {
      const double n = p.plan.target.norm();
      furthest[keep ? 1 : 0] = std::max(furthest[keep ? 1 : 0], n);
      if (n > 0.36 + 0.011 || n < 0.16 - 0.011 || p.plan.target.x() < 0.12 - 0.011) {
        ++outside[keep ? 1 : 0];
      }
    }
  }
  EXPECT_EQ(outside[1], 0) << "furthest target " << furthest[1] << " m";
  EXPECT_GT(outside[0], 0) << "furthest target " << furthest[0] << " m";
}

TEST(Learn, CarryRegionFindsTheObjectWhereItWasOrMovedWithThePush) {
  // A 40 x 40 image, the object's region the square [5, 15)^2, the push's motion (+20, 0) px.
  // The look's features: 4 at (8..11, 10) and 4 at (28..31, 10); the object's views hold e0.
  // Where the features that are e0 lie says where the object is.
  cv::Mat region(40, 40, CV_8U, cv::Scalar(0));
  region(cv::Rect(5, 5, 10, 10)).setTo(255);
  const cv::Point2d shift(20, 0);
  std::vector<cv::Point2f> points;
  points.reserve(8);
  for (int i = 0; i < 4; ++i) points.emplace_back(8.0F + i, 10.0F);
  for (int i = 0; i < 4; ++i) points.emplace_back(28.0F + i, 10.0F);
  const cv::Mat pool = (cv::Mat_<float>(1, 4) << 1, 0, 0, 0);
  const auto look = [](bool object_left, bool object_right) {
    cv::Mat d(8, 4, CV_32F, cv::Scalar(0));
    for (int i = 0; i < 8; ++i) {
      const bool object = i < 4 ? object_left : object_right;
      d.at<float>(i, object ? 0 : 1 + (i % 3)) = 1;
    }
    return d;
  };
  cv::Mat out;
  EXPECT_EQ(carry_region(region, shift, points, look(false, true), pool, 0.8, 0.1, out),
            RegionFate::kCarried);
  ASSERT_FALSE(out.empty());
  EXPECT_EQ(out.at<uchar>(10, 30), 255);  // moved with the push
  EXPECT_EQ(out.at<uchar>(10, 10), 0);
  EXPECT_EQ(carry_region(region, shift, points, look(true, false), pool, 0.8, 0.1, out),
            RegionFate::kStayed);
  EXPECT_EQ(out.at<uchar>(10, 10), 255);
  EXPECT_EQ(out.at<uchar>(10, 30), 0);
  // Its appearance is nowhere: lost (forgotten), no region.
  EXPECT_EQ(carry_region(region, shift, points, look(false, false), pool, 0.8, 0.1, out),
            RegionFate::kLost);
  EXPECT_TRUE(out.empty());
  // Bad input.
  EXPECT_THROW((void)carry_region(cv::Mat(), shift, points, look(true, true), pool, 0.8, 0.1, out),
               Error);
  EXPECT_THROW((void)carry_region(region, shift, {}, look(true, true), pool, 0.8, 0.1, out), Error);
}

TEST(Learn, CarryRegionsLogsTheRegionsCarriedOnlyWhenOn) {
  // --carry-regions adds "carried" to every region line of the log; off, the log is as before.
  const test::TempDir dir("proprio_learn_carry_");
  const SmallTable t;
  for (const bool carry : {false, true}) {
    const std::filesystem::path out = dir.path() / (carry ? "on" : "off");
    (void)t.run(out, 2, [&](LearnOptions& o) { o.carry_regions = carry; });
    std::ifstream in(out / "decisions.jsonl");
    std::string line;
    int regions = 0;
    while (std::getline(in, line)) {
      const core::Json j = core::Json::parse(line);
      if (j["event"] != "region") continue;
      ++regions;
      EXPECT_EQ(j.contains("carried"), carry) << line;
    }
    EXPECT_GT(regions, 0);
  }
}

// The second turn's choices (object 1) in the run's decisions.jsonl.
std::vector<core::Json> second_choices(const std::filesystem::path& out) {
  std::ifstream in(out / "decisions.jsonl");
  std::string line;
  std::vector<core::Json> out_choices;
  while (std::getline(in, line)) {
    core::Json j = core::Json::parse(line);
    if (j["event"] == "choose" && j.value("object", -1) == 1) out_choices.push_back(std::move(j));
  }
  return out_choices;
}

// Each of the second turn's choices names `why` in its why, every score's `key` lies in [lo, hi]
// and names class 0 (the only one so far) by `object_key`, and the blob chosen is the one of
// least `key`. Returns how many choices there were.
int check_least_chosen(const std::filesystem::path& out, const std::string& key,
                       const std::string& object_key, double lo, double hi,
                       const std::string& why) {
  const std::vector<core::Json> choices = second_choices(out);
  for (const core::Json& j : choices) {
    const std::string line = j.dump();
    EXPECT_NE(j["why"].get<std::string>().find(why), std::string::npos) << line;
    EXPECT_FALSE(j["scores"].empty()) << line;
    double least = std::numeric_limits<double>::infinity();
    int least_blob = -1;
    for (const auto& s : j["scores"]) {
      const double f = s[key].get<double>();
      EXPECT_GE(f, lo) << line;
      EXPECT_LE(f, hi) << line;
      EXPECT_EQ(s[object_key].get<int>(), 0) << line;
      if (f < least) {
        least = f;
        least_blob = s["blob"].get<int>();
      }
    }
    EXPECT_EQ(j["blob"].get<int>(), least_blob) << line;
  }
  return static_cast<int>(choices.size());
}

TEST(Learn, MatchChoosesTheBlobLeastMatchedToTheObjectsSoFar) {
  // new_object "match": the second turn scores each open blob by the fraction of its
  // descriptors matched to the first object's views and chooses the least matched; "words"
  // (the default) logs no match fractions.
  const test::TempDir dir("proprio_learn_match_");
  const SmallTable t;
  for (const NewObjectScore how : {NewObjectScore::kWords, NewObjectScore::kMatch}) {
    const std::filesystem::path out =
        dir.path() / (how == NewObjectScore::kMatch ? "match" : "words");
    const LearnResult r = t.run(out, 2, [&](LearnOptions& o) { o.new_object = how; });
    ASSERT_GT(r.objects.at(0).views, 0);
    if (how == NewObjectScore::kMatch) {
      EXPECT_EQ(check_least_chosen(out, "matched", "matched_object", 0, 1, "matched"), 1);
      continue;
    }
    const std::vector<core::Json> choices = second_choices(out);
    EXPECT_EQ(choices.size(), 1U);
    for (const core::Json& j : choices) {
      ASSERT_FALSE(j["scores"].empty()) << j.dump();
      for (const auto& s : j["scores"]) EXPECT_FALSE(s.contains("matched")) << j.dump();
    }
  }
}

TEST(Learn, ColourChoosesTheBlobWhoseColoursTheClassesExplainLeast) {
  // new_object "colour": the second turn scores each open blob by the mean log p of its colour
  // words under the first class's colours (28 add-one smoothed words: below 0, far above -20)
  // and chooses the least; with --known-margin (a words likelihood) it is refused.
  const test::TempDir dir("proprio_learn_colour_choice_");
  const SmallTable t;
  const LearnResult r = t.run(dir.path() / "run", 2,
                              [&](LearnOptions& o) { o.new_object = NewObjectScore::kColour; });
  ASSERT_GT(r.objects.at(0).views, 0);
  EXPECT_EQ(core::read_json(dir.path() / "run" / "learn.json")["options"]["new_object"], "colour");
  EXPECT_EQ(
      check_least_chosen(dir.path() / "run", "best_mean_log_p", "best_object", -20, 0, "colour"),
      1);
  LearnOptions bad;
  bad.new_object = NewObjectScore::kColour;
  bad.known_margin = 1;
  EXPECT_THROW(bad.validate(), Error);
}

TEST(Learn, PixelsChooseTheBlobWhosePixelColoursAreFarthestFromTheClasses) {
  // new_object "pixels" (session 41): the second turn scores each open blob by minus the
  // Hellinger distance (in [-1, 0]) between its pixels' colour words and the first class's, from
  // the pushed blob in the look before each of its pushes, and chooses the farthest; it needs the
  // views before (both, the default, or before) and is refused with --known-margin.
  const test::TempDir dir("proprio_learn_pixels_");
  const SmallTable t;
  const LearnResult r = t.run(dir.path() / "run", 2,
                              [&](LearnOptions& o) { o.new_object = NewObjectScore::kPixels; });
  ASSERT_GT(r.objects.at(0).views, 0);
  EXPECT_EQ(core::read_json(dir.path() / "run" / "learn.json")["options"]["new_object"], "pixels");
  EXPECT_EQ(check_least_chosen(dir.path() / "run", "best_mean_log_p", "best_object", -1, 0,
                               "pixel colours"),
            1);
  LearnOptions bad;
  bad.new_object = NewObjectScore::kPixels;
  EXPECT_NO_THROW(bad.validate());
  bad.views = LearnViews::kMotion;
  EXPECT_THROW(bad.validate(), Error);
  bad.views = LearnViews::kBefore;
  EXPECT_NO_THROW(bad.validate());
  bad.known_margin = 1;
  EXPECT_THROW(bad.validate(), Error);
}

TEST(Learn, ABlobThatTheDescriptorsSayIsAKnownObjectIsNotANewClass) {
  // new_object "match" with match_known 0: every blob has at least no descriptors matched to
  // the first object's views, so every blob is that object: the second turn finds only known
  // objects (by their descriptors) and learns nothing. With 1 (off) it chooses.
  const test::TempDir dir("proprio_learn_match_known_");
  const SmallTable t;
  for (const double known : {1.0, 0.0}) {
    const std::filesystem::path out = dir.path() / (known < 1 ? "on" : "off");
    const LearnResult r = t.run(out, 2, [&](LearnOptions& o) {
      o.new_object = NewObjectScore::kMatch;
      o.match_known = known;
    });
    ASSERT_GT(r.objects.at(0).views, 0);
    const std::string ev = events_of(out / "decisions.jsonl");
    std::ifstream in(out / "decisions.jsonl");
    const std::string raw((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const bool by_descriptors = raw.find("(by its descriptors)") != std::string::npos;
    if (known < 1) {
      EXPECT_TRUE(by_descriptors) << ev;
      EXPECT_EQ(count_of(ev, "choose:"), 1) << ev;
      EXPECT_EQ(r.objects.at(1).views, 0);
    } else {
      EXPECT_FALSE(by_descriptors) << ev;
      EXPECT_EQ(count_of(ev, "choose:"), 2) << ev;
    }
  }
}

// A depth image of the test camera (1 m above (0.25, 0), looking down) seeing the table and
// boxes (table x, y ranges and top height, m): depth = 1 - height along the optical axis.
struct DepthBox {
  double x0, x1, y0, y1, h;
};
cv::Mat depth_of_boxes(const geometry::Camera& cam, const std::vector<DepthBox>& boxes) {
  cv::Mat depth(cam.height, cam.width, CV_32FC1, cv::Scalar(1.0));
  for (int v = 0; v < cam.height; ++v) {
    for (int u = 0; u < cam.width; ++u) {
      double top = 0;
      for (const DepthBox& b : boxes) {
        // The point of pixel (u, v) at the box's top: X = C + d R^T K^-1 (u, v, 1), d = 1 - h.
        const double d = 1.0 - b.h;
        const double x = 0.25 + d * (u - 320.0) / 600.0;
        const double y = -d * (v - 240.0) / 600.0;
        if (x >= b.x0 && x <= b.x1 && y >= b.y0 && y <= b.y1) top = std::max(top, b.h);
      }
      depth.at<float>(v, u) = static_cast<float>(1.0 - top);
    }
  }
  return depth;
}

// The table point (m) of a mask's centroid seen at height h.
Eigen::Vector2d centroid_on_table(const cv::Mat& mask, double h) {
  const cv::Moments m = cv::moments(mask, true);
  const double d = 1.0 - h;
  return {0.25 + d * (m.m10 / m.m00 - 320.0) / 600.0, -d * (m.m01 / m.m00 - 240.0) / 600.0};
}

TEST(Learn, DepthCandidatesAreTheObjectsStandingOutOfTheTable) {
  const geometry::Camera cam = test::down_camera();
  // Two touching boxes of different heights (a book against a cd): two candidates, each on its
  // box, largest first; the table is none.
  const DepthBox a{0.20, 0.25, -0.03, 0.03, 0.04};
  const DepthBox b{0.25, 0.28, -0.03, 0.03, 0.02};
  const cv::Mat depth = depth_of_boxes(cam, {a, b});
  const std::vector<cv::Mat> c = depth_candidates(depth, cam, 0.003, 0.01, 50);
  ASSERT_EQ(c.size(), 2U);
  EXPECT_EQ(c[0].type(), CV_8U);
  EXPECT_EQ(c[0].size(), depth.size());
  EXPECT_GT(cv::countNonZero(c[0]), cv::countNonZero(c[1]));
  const Eigen::Vector2d ca = centroid_on_table(c[0], a.h);
  const Eigen::Vector2d cb = centroid_on_table(c[1], b.h);
  EXPECT_NEAR(ca.x(), 0.225, 0.004);
  EXPECT_NEAR(ca.y(), 0.0, 0.004);
  EXPECT_NEAR(cb.x(), 0.265, 0.004);
  EXPECT_NEAR(cb.y(), 0.0, 0.004);
  // Apart on the table: two candidates as well.
  EXPECT_EQ(depth_candidates(depth_of_boxes(cam, {a, {0.30, 0.33, 0.05, 0.08, 0.02}}), cam, 0.003,
                             0.01, 50)
                .size(),
            2U);
  // Lower than min_height: the table (the 2 cm box is table for a 3 cm least height).
  EXPECT_EQ(depth_candidates(depth, cam, 0.03, 0.01, 50).size(), 1U);
  // Two touching boxes of one height: no depth step between them, one candidate (the limit).
  EXPECT_EQ(depth_candidates(depth_of_boxes(cam, {a, {0.25, 0.28, -0.03, 0.03, 0.04}}), cam, 0.003,
                             0.01, 50)
                .size(),
            1U);
  // Smaller than min_pixels: none; ignored pixels (the arm) are no object; no measurement
  // (depth 0) is none either.
  EXPECT_TRUE(depth_candidates(depth, cam, 0.003, 0.01, 1000000).empty());
  cv::Mat ignore(depth.size(), CV_8U, cv::Scalar(255));
  EXPECT_TRUE(depth_candidates(depth, cam, 0.003, 0.01, 50, ignore).empty());
  EXPECT_TRUE(depth_candidates(cv::Mat(depth.size(), CV_32FC1, cv::Scalar(0)), cam, 0.003, 0.01, 50)
                  .empty());
  EXPECT_TRUE(
      depth_candidates(cv::Mat(depth.size(), CV_32FC1, cv::Scalar(1.0)), cam, 0.003, 0.01, 50)
          .empty());
  // Bad input.
  EXPECT_THROW((void)depth_candidates(cv::Mat(10, 10, CV_32FC1), cam, 0.003, 0.01, 50), Error);
  EXPECT_THROW((void)depth_candidates(cv::Mat(depth.size(), CV_8U), cam, 0.003, 0.01, 50), Error);
  EXPECT_THROW((void)depth_candidates(depth, cam, 0, 0.01, 50), Error);
  EXPECT_THROW((void)depth_candidates(depth, cam, 0.003, 0, 50), Error);
  EXPECT_THROW((void)depth_candidates(depth, cam, 0.003, 0.01, 0), Error);
  EXPECT_THROW((void)depth_candidates(depth, cam, 0.003, 0.01, 50, cv::Mat(5, 5, CV_8U)), Error);
}

TEST(Learn, AKnownObjectIsTheCandidateWhereItsPushLeftIt) {
  const cv::Size s(40, 20);
  const auto rect = [&](int x, int y, int w, int h) {
    cv::Mat m(s, CV_8U, cv::Scalar(0));
    m(cv::Rect(x, y, w, h)).setTo(255);
    return m;
  };
  // Three candidates side by side; object 0 was left mostly on candidate 1 (and a little on 0:
  // it lies against it), object 1 on candidate 2, object 2's place is unknown.
  const std::vector<cv::Mat> cands{rect(0, 0, 10, 20), rect(12, 0, 10, 20), rect(24, 0, 10, 20)};
  const std::vector<cv::Mat> regions{rect(8, 0, 14, 20), rect(26, 5, 6, 6), cv::Mat()};
  EXPECT_EQ(known_candidates(regions, cands), (std::vector<int>{1, 2, -1}));
  // One candidate per known object: two objects left on candidate 1, the one overlapping it
  // more is it; the other is the candidate it overlaps next (0), not candidate 1 again.
  const std::vector<cv::Mat> both{rect(12, 0, 10, 20), rect(6, 0, 10, 20)};
  EXPECT_EQ(known_candidates(both, cands), (std::vector<int>{1, 0}));
  // A region over the whole image (a failed segmentation): every candidate lies inside it; the
  // one nearest where the pusher ended is the object, not the largest.
  const std::vector<cv::Mat> wide{cands[0], cands[1], rect(24, 0, 16, 20)};
  const cv::Mat all(s, CV_8U, cv::Scalar(255));
  EXPECT_EQ(known_candidates({all}, wide, {cv::Point2d(16, 10)}), (std::vector<int>{1}));
  EXPECT_EQ(known_candidates({all}, wide), (std::vector<int>{2}));
  EXPECT_EQ(known_candidates({all}, wide, {std::nullopt}), (std::vector<int>{2}));
  // Most of a small candidate inside beats a little of a large one.
  EXPECT_EQ(known_candidates({rect(0, 0, 14, 20)}, {rect(0, 0, 30, 20), rect(2, 2, 8, 8)}),
            (std::vector<int>{1}));
  EXPECT_THROW((void)known_candidates({all}, wide, {std::nullopt, std::nullopt}), Error);
  // Overlapping nothing: -1; no candidates: -1.
  EXPECT_EQ(known_candidates({rect(35, 0, 5, 5)}, cands), (std::vector<int>{-1}));
  EXPECT_EQ(known_candidates({rect(0, 0, 5, 5)}, {}), (std::vector<int>{-1}));
  // Bad input.
  EXPECT_THROW((void)known_candidates({cv::Mat(s, CV_32F, cv::Scalar(1))}, cands), Error);
  EXPECT_THROW((void)known_candidates({cv::Mat(10, 10, CV_8U, cv::Scalar(0))}, cands), Error);
}

TEST(Learn, CoverageCountsTheTurnsThatPushedEachNamedObject) {
  const auto push = [](int cls, bool executed, const std::string& intended, bool moved) {
    LearnPush p;
    p.object = cls;
    p.executed = executed;
    p.truth = LearnPushTruth{intended, {}, moved, false};
    return p;
  };
  std::vector<LearnPush> pushes{
      push(0, true, "cd", true),       push(0, true, "cd", true),  // one turn, two pushes
      push(1, true, "cd", true),                                   // a second turn
      push(2, true, "book", false),                                // it did not move
      push(3, false, "giraffe", true),                             // not executed
      push(4, true, "mug", true),                                  // not a named object
  };
  LearnPush unknown;
  unknown.executed = true;  // no ground truth: counts for nothing
  pushes.push_back(unknown);
  const std::vector<LearnCoverage> c = learn_coverage({"book", "cd", "giraffe"}, pushes);
  ASSERT_EQ(c.size(), 3U);
  EXPECT_EQ(c[0].name, "book");
  EXPECT_EQ(c[0].turns, 0);
  EXPECT_EQ(c[0].pushes, 0);
  EXPECT_EQ(c[1].name, "cd");
  EXPECT_EQ(c[1].turns, 2);
  EXPECT_EQ(c[1].pushes, 3);
  EXPECT_EQ(c[2].turns, 0);
  EXPECT_TRUE(learn_coverage({}, pushes).empty());
}

TEST(Learn, DepthCandidatesAreLoggedAndTurnOnTheDepthCamera) {
  LearnOptions o;
  o.candidates = LearnCandidates::kDepth;
  EXPECT_TRUE(o.resolved().depth);
  EXPECT_TRUE(learn_table(o.resolved()).depth);
  EXPECT_EQ(LearnOptions().candidates, LearnCandidates::kDepth);  // the default
  o.candidates = LearnCandidates::kBlobs;
  EXPECT_FALSE(o.resolved().depth);
  // A run with depth candidates logs them each look; with blobs it logs none.
  const test::TempDir dir("proprio_learn_candidates_");
  SmallTable t;
  const auto prov = core::Provenance::current({"learn_test"}, 1);
  for (const bool by_depth : {false, true}) {
    sim::TableOptions table = t.table;
    table.depth = by_depth;
    sim::SimulatedRobot robot(table, t.catalogue);
    NullAttendant attendant;
    LearnOptions lo = t.o;
    lo.candidates = by_depth ? LearnCandidates::kDepth : LearnCandidates::kBlobs;
    lo.out = dir.path() / (by_depth ? "depth" : "blobs");
    (void)run_learn(lo, robot, attendant, 2, prov);
    std::ifstream in(lo.out / "decisions.jsonl");
    std::string line;
    int candidates = 0;
    while (std::getline(in, line)) {
      const core::Json j = core::Json::parse(line);
      if (j["event"] == "candidates") ++candidates;
    }
    EXPECT_EQ(candidates > 0, by_depth);
    EXPECT_EQ(std::filesystem::exists(lo.out / "candidates.png"), by_depth);
  }
}

TEST(Learn, DepthPointsAreWhatStandsAboveTheTable) {
  const geometry::Camera cam = test::down_camera();
  const DepthBox tall{0.20, 0.25, -0.03, 0.03, 0.10};
  const DepthBox low{0.35, 0.38, -0.03, 0.03, 0.02};
  const cv::Mat depth = depth_of_boxes(cam, {tall, low});
  const std::vector<Eigen::Vector3d> p = depth_points(depth, cam, 0.008);
  ASSERT_FALSE(p.empty());
  int on_tall = 0;
  for (const Eigen::Vector3d& x : p) {
    const bool in_tall = x.x() > 0.199 && x.x() < 0.251 && std::abs(x.y()) < 0.031;
    const bool in_low = x.x() > 0.349 && x.x() < 0.381 && std::abs(x.y()) < 0.031;
    EXPECT_TRUE(in_tall || in_low) << x.transpose();
    EXPECT_NEAR(x.z(), in_tall ? 0.10 : 0.02, 1e-4);
    on_tall += in_tall ? 1 : 0;
  }
  EXPECT_GT(on_tall, 0);
  EXPECT_LT(on_tall, static_cast<int>(p.size()));
  // Every other pixel: about a quarter; above 5 cm only the tall box; the arm's pixels none.
  const auto n2 = static_cast<double>(depth_points(depth, cam, 0.008, 2).size());
  EXPECT_NEAR(n2 / static_cast<double>(p.size()), 0.25, 0.05);
  EXPECT_EQ(depth_points(depth, cam, 0.05).size(), static_cast<std::size_t>(on_tall));
  EXPECT_TRUE(
      depth_points(depth, cam, 0.008, 1, cv::Mat(depth.size(), CV_8U, cv::Scalar(255))).empty());
  EXPECT_THROW((void)depth_points(cv::Mat(10, 10, CV_32FC1), cam, 0.008), Error);
  EXPECT_THROW((void)depth_points(depth, cam, -0.01), Error);
  EXPECT_THROW((void)depth_points(depth, cam, 0.008, 0), Error);
  EXPECT_THROW((void)depth_points(depth, cam, 0.008, 1, cv::Mat(5, 5, CV_8U)), Error);
}

TEST(Learn, TheHandMeetsWhatStandsAroundThePushStart) {
  const geometry::Camera cam = test::down_camera();
  const DepthBox tall{0.20, 0.25, -0.03, 0.03, 0.10};
  const DepthBox low{0.35, 0.38, -0.03, 0.03, 0.02};
  const std::vector<Eigen::Vector3d> p =
      depth_points(depth_of_boxes(cam, {tall, low}), cam, HandClearance{}.pusher_height);
  const HandClearance hc;  // pusher 2 cm above 8 mm, fingers 4.5 cm above 3.5 cm
  // On the tall box; 3 cm from it (the fingers come down on it); 6 cm away: clear.
  EXPECT_GT(hand_meets(p, {0.225, 0.0}, hc), 0);
  EXPECT_GT(hand_meets(p, {0.225, 0.06}, hc), 0);
  EXPECT_EQ(hand_meets(p, {0.225, 0.09}, hc), 0);
  // 1 cm from the low box: the pusher meets it; 3 cm: the fingers pass above it.
  EXPECT_GT(hand_meets(p, {0.365, 0.04}, hc), 0);
  EXPECT_EQ(hand_meets(p, {0.365, 0.06}, hc), 0);
  HandClearance narrow = hc;
  narrow.hand = 0.02;  // fingers within 2 cm only: 3 cm from the tall box is clear
  EXPECT_EQ(hand_meets(p, {0.225, 0.06}, narrow), 0);
  EXPECT_EQ(hand_meets({}, {0.225, 0.0}, hc), 0);
  HandClearance bad = hc;
  bad.pusher = -0.01;
  EXPECT_THROW((void)hand_meets(p, {0.2, 0.0}, bad), Error);
  bad = hc;
  bad.hand_height = std::numeric_limits<double>::infinity();
  EXPECT_THROW((void)hand_meets(p, {0.2, 0.0}, bad), Error);
}

TEST(Learn, MovingWaitLeavesOutTheDistractorsAndNoObjectOnTheTable) {
  // The moving backdrop's two distractors slide behind the table. With moving_wait the robot
  // holds still before each choice and leaves out the candidates whose depth moved: by ground
  // truth (the attendant: the object under each blob of the view chosen from) every candidate
  // left out as `moving` is a distractor (or nothing), none is a table object, and no choice is
  // a distractor. Off, no `moving` event is logged, nothing is skipped as moving, and on this
  // table (seed 1) a turn chooses a distractor.
  const test::TempDir dir("proprio_learn_moving_");
  SmallTable t;
  t.o.background = "moving";
  t.o.seed = 1;  // a distractor comes within reach (`proprio learn --seed 1` on this table)
  t.table.seed = 1;
  t.table.background = sim::Background::kMoving;
  t.table.depth = true;
  const auto prov = core::Provenance::current({"learn_test"}, 1);
  for (const double wait : {0.0, 0.3}) {
    sim::SimulatedRobot robot(t.table, t.catalogue);
    std::set<std::string> distractors;
    for (const sim::ObjectTruth& o : robot.ground_truth()) {
      if (o.role == sim::TableRole::kDistractor) distractors.insert(o.name);
    }
    ASSERT_EQ(distractors.size(), 2U);
    GroundTruthAttendant attendant(robot, t.table.seed);
    LearnOptions lo = t.o;
    lo.moving_wait = wait;
    lo.out = dir.path() / (wait > 0 ? "on" : "off");
    const LearnResult r = run_learn(lo, robot, attendant, 2, prov);
    const std::string events = events_of(lo.out / "decisions.jsonl");
    const core::Json rec = core::read_json(lo.out / "learn.json");
    EXPECT_DOUBLE_EQ(rec["options"]["moving_wait"].get<double>(), wait);
    int left_out = 0;
    std::map<std::size_t, core::Json> last_choice;  // the attendant keeps a turn's last choice
    std::ifstream in(lo.out / "decisions.jsonl");
    std::string line;
    while (std::getline(in, line)) {
      const core::Json j = core::Json::parse(line);
      if (j.value("event", std::string()) == "choose") {
        last_choice[j["object"].get<std::size_t>()] = j;
      }
    }
    for (const auto& [object, j] : last_choice) {
      const RoundTruth& truth = attendant.rounds().at(object);
      for (const auto& k : j.value("skipped", core::Json::array())) {
        if (k.value("reason", std::string()) != "moving") continue;
        ++left_out;
        const std::string under = truth.blobs.at(k["blob"].get<std::size_t>());
        EXPECT_TRUE(under.empty() || distractors.count(under) > 0) << under << ": " << j.dump();
      }
    }
    int chose_distractor = 0;
    for (const RoundTruth& round : attendant.rounds()) {
      chose_distractor += static_cast<int>(distractors.count(round.chosen));
    }
    // Off, this table shows the defect: a turn chooses a distractor; on, none does.
    EXPECT_EQ(chose_distractor > 0, wait == 0) << events;
    if (wait > 0) {
      EXPECT_NE(events.find("moving:"), std::string::npos) << events;
      EXPECT_GE(left_out, 1) << events;  // the distractors are in reach on this table
    } else {
      EXPECT_EQ(events.find("moving:"), std::string::npos) << events;
      EXPECT_EQ(left_out, 0);
    }
    (void)r;
  }
}

TEST(Learn, EverySkippedCandidateHasAReasonAndTheRunCountsThem) {
  const test::TempDir dir("proprio_learn_skipped_");
  SmallTable t;
  const auto prov = core::Provenance::current({"learn_test"}, 1);
  for (const bool prefer : {false, true}) {
    sim::TableOptions table = t.table;
    table.depth = true;
    sim::SimulatedRobot robot(table, t.catalogue);
    NullAttendant attendant;
    LearnOptions lo = t.o;
    lo.candidates = LearnCandidates::kDepth;
    lo.prefer_pushable = prefer;
    lo.candidate_footprint = prefer;
    lo.start_clearance = prefer ? 0.045 : 0.0;
    lo.out = dir.path() / (prefer ? "prefer" : "plain");
    const LearnResult r = run_learn(lo, robot, attendant, 2, prov);
    std::ifstream in(lo.out / "decisions.jsonl");
    std::string line;
    std::map<std::string, int> counted;
    int chooses = 0;
    while (std::getline(in, line)) {
      const core::Json j = core::Json::parse(line);
      if (j["event"] != "choose" && j["event"] != "rechoose" && j["event"] != "none-chosen") {
        continue;
      }
      if (j["event"] == "choose") {
        ++chooses;
        ASSERT_TRUE(j.contains("skipped")) << line;
      }
      if (!j.contains("skipped")) continue;
      std::set<int> seen;
      for (const auto& k : j["skipped"]) {
        const std::string reason = k["reason"].get<std::string>();
        const int b = k["blob"].get<int>();
        EXPECT_FALSE(reason.empty());
        ++counted[reason];
        if (b < 0) {
          EXPECT_EQ(reason, "out-of-reach");
          continue;
        }
        if (j["event"] == "choose") {
          EXPECT_NE(b, j["blob"].get<int>()) << "the chosen blob is not skipped: " << line;
          EXPECT_TRUE(seen.insert(b).second) << "one reason a blob: " << line;
        }
        // Without prefer_pushable no push is planned before the choice.
        if (!prefer && j["event"] == "choose") {
          EXPECT_NE(reason, "no-push-path");
          EXPECT_NE(reason, "start-blocked");
        }
      }
    }
    EXPECT_GT(chooses, 0);
    // learn.json's counts are the log's.
    std::map<std::string, int> recorded;
    for (const SkipCount& s : r.skipped) recorded[s.reason] = s.count;
    EXPECT_EQ(recorded, counted);
    const core::Json doc = core::read_json(lo.out / "learn.json");
    EXPECT_EQ(doc.contains("skipped"), !counted.empty());
  }
}

}  // namespace
}  // namespace proprio::loop
