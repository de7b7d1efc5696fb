// Self-supervision (thesis 7.2 a-d): the object list, the footprint geometry, the yaw coverage,
// faults as logged outcomes on a robot that refuses every push or sees nothing, and a small run
// on the simulated table (2 objects, blob views, a vocabulary and LDA model made here from the
// robot's first look) scored against the ground truth and on held-out views.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <memory>
#include <numbers>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <set>
#include <vector>

#include "../support/table_views.hpp"
#include "../support/temp_dir.hpp"
#include "proprio/core/error.hpp"
#include "proprio/features/kmeans.hpp"
#include "proprio/features/sift.hpp"
#include "proprio/loop/self_supervision.hpp"
#include "proprio/loop/self_supervision_run.hpp"
#include "proprio/loop/self_supervision_scoring.hpp"
#include "proprio/loop/view_model.hpp"
#include "proprio/planning/push_planner.hpp"
#include "proprio/recognition/mot.hpp"
#include "proprio/sim/simulated_robot.hpp"
#include "proprio/topics/batch_lda.hpp"
#include "proprio/topics/corpus.hpp"
#include "proprio/topics/mixture_of_topics.hpp"

namespace proprio::loop {
namespace {
namespace fs = std::filesystem;

TEST(SelfSupervision, ObjectListIsTrimmedAndChecked) {
  EXPECT_EQ(parse_object_list(" bike, cd ,book"), (std::vector<std::string>{"bike", "cd", "book"}));
  EXPECT_THROW(parse_object_list("bike,,cd"), Error);
  EXPECT_THROW(parse_object_list(""), Error);
  EXPECT_THROW(parse_object_list("bike,cd,bike"), Error);
}

TEST(SelfSupervision, MixtureOfTopicsDefaultsToUpToThreeDirichletsPerObject) {
  // Measured (docs/results/selfsupervision-history.md, session 14): renders of an object from all
  // round are not one Dirichlet in topic space; up to 3 per object raised the a0 rung 71.7%
  // -> 81.8% (mean over three T = 8 LDA models).
  const SelfSupervisionOptions o;
  EXPECT_EQ(o.mot.components, 3);
  EXPECT_FALSE(o.mot.shared_precision);  // not with components > 1
  EXPECT_NO_THROW(o.mot.validate());
}

Eigen::VectorXd dist4(double a, double b, double c, double d) {
  return Eigen::Vector4d(a, b, c, d);
}

TEST(SelfSupervision, HellingerKnownAnswers) {
  EXPECT_NEAR(hellinger(dist4(0.25, 0.25, 0.25, 0.25), dist4(0.25, 0.25, 0.25, 0.25)), 0.0, 1e-12);
  EXPECT_NEAR(hellinger(dist4(1, 0, 0, 0), dist4(0, 1, 0, 0)), 1.0, 1e-12);
  // 1 - sqrt(0.5) under the root.
  EXPECT_NEAR(hellinger(dist4(1, 0, 0, 0), dist4(0.5, 0.5, 0, 0)), std::sqrt(1 - std::sqrt(0.5)),
              1e-12);
  EXPECT_THROW((void)hellinger(dist4(1, 0, 0, 0), Eigen::Vector3d(1, 0, 0)), InternalError);
}

TEST(SelfSupervision, NextObjectIsTheOneNoLearnedClassClaims) {
  // The last round of four objects: A, B and D are learned (their looks below); the calculator
  // is not. A's look has drifted (turned by its pushes, a neighbour in its blob): it is farther
  // from its own class (0.33) than the calculator, plain and grey, is from B's (0.29). The
  // farthest-from-every-class rule (7.2 d as the thesis says it, and what the Dirichlet scores
  // did on the report seeds) chooses A again and starves the calculator; one blob a class
  // chooses the calculator.
  const std::vector<std::vector<Eigen::VectorXd>> looks{
      {dist4(0.7, 0.1, 0.1, 0.1), dist4(0.6, 0.2, 0.1, 0.1)},            // class 0: A
      {dist4(0.1, 0.7, 0.1, 0.1)},                                       // class 1: B
      {dist4(0.1, 0.1, 0.7, 0.1)},                                       // class 2: D
      {}};                                                               // class 3: not learned yet
  const std::vector<Eigen::VectorXd> blobs{dist4(0.4, 0.05, 0.05, 0.5),  // 0: A
                                           dist4(0.12, 0.68, 0.1, 0.1),  // 1: B
                                           dist4(0.05, 0.45, 0.05, 0.45),  // 2: the calculator
                                           dist4(0.1, 0.1, 0.68, 0.12)};   // 3: D
  const NextChoice next = choose_unlearned(blobs, looks);
  EXPECT_EQ(next.blob, 2);
  EXPECT_EQ(next.claimed_by, (std::vector<int>{0, 1, -1, 2}));
  EXPECT_EQ(next.nearest_class, (std::vector<int>{0, 1, 1, 2}));
  // Without the matching the farthest blob is A's: the old choice.
  EXPECT_GT(next.nearest[0], next.nearest[2]);
  int farthest = 0;
  for (int b = 1; b < 4; ++b) {
    if (next.nearest[static_cast<std::size_t>(b)] >
        next.nearest[static_cast<std::size_t>(farthest)]) {
      farthest = b;
    }
  }
  EXPECT_EQ(farthest, 0);

  // An unscored blob (too few features) is neither claimed nor chosen.
  std::vector<Eigen::VectorXd> with_blank = blobs;
  with_blank.insert(with_blank.begin(), Eigen::VectorXd());
  const NextChoice blank = choose_unlearned(with_blank, looks);
  EXPECT_EQ(blank.blob, 3);
  EXPECT_EQ(blank.claimed_by[0], -1);
  EXPECT_EQ(blank.nearest[0], -1.0);

  // Fewer blobs than learned classes (two objects seen as one): every blob is claimed, the
  // farthest of all is chosen.
  const NextChoice merged = choose_unlearned({blobs[0], blobs[1]}, looks);
  EXPECT_EQ(merged.blob, 0);
  EXPECT_GE(merged.claimed_by[0], 0);
  EXPECT_GE(merged.claimed_by[1], 0);

  // No class has looks yet: the first scored blob; no blob scored: none.
  EXPECT_EQ(choose_unlearned(blobs, {{}, {}}).blob, 0);
  EXPECT_EQ(choose_unlearned({Eigen::VectorXd(), Eigen::VectorXd()}, looks).blob, -1);
}

// recheck_tries: after (b) the chosen blob is checked again; a learned class's claim on it makes
// the round choose again, unless every blob is claimed (session 34: a clearing push moved a
// learned neighbour into the chosen object's blob, and the round learned the neighbour again).
TEST(SelfSupervision, RecheckChoosesAgainWhenALearnedClassClaimsTheChosenBlob) {
  const std::vector<std::vector<Eigen::VectorXd>> looks{
      {dist4(0.7, 0.1, 0.1, 0.1), dist4(0.6, 0.2, 0.1, 0.1)},  // class 0: A
      {dist4(0.1, 0.7, 0.1, 0.1)},                             // class 1: B
      {dist4(0.1, 0.1, 0.7, 0.1)},                             // class 2: D
      {}};
  const std::vector<Eigen::VectorXd> blobs{dist4(0.65, 0.15, 0.1, 0.1),    // 0: A with the new one
                                           dist4(0.12, 0.68, 0.1, 0.1),    // 1: B
                                           dist4(0.05, 0.45, 0.05, 0.45),  // 2: unlearned
                                           dist4(0.1, 0.1, 0.68, 0.12)};   // 3: D
  const NextChoice cl = choose_unlearned(blobs, looks);
  ASSERT_EQ(cl.claimed_by, (std::vector<int>{0, 1, -1, 2}));
  // The chosen blob became A's (claimed by class 0) while blob 2 is unclaimed: choose again.
  EXPECT_TRUE(recheck_claimed(cl, 0));
  EXPECT_TRUE(recheck_claimed(cl, 3));
  // The chosen blob is the unclaimed one: (c) starts on it.
  EXPECT_FALSE(recheck_claimed(cl, 2));
  // Every blob claimed (fewer blobs than classes): choosing again could only choose a learned
  // object, so the round goes on with its own.
  const NextChoice all = choose_unlearned({blobs[0], blobs[1]}, looks);
  ASSERT_GE(all.claimed_by[0], 0);
  EXPECT_FALSE(recheck_claimed(all, 0));
  EXPECT_FALSE(recheck_claimed(all, 1));
  // An unscored chosen blob is claimed by no class; no class with looks claims nothing.
  std::vector<Eigen::VectorXd> with_blank = blobs;
  with_blank.insert(with_blank.begin(), Eigen::VectorXd());
  EXPECT_FALSE(recheck_claimed(choose_unlearned(with_blank, looks), 0));
  EXPECT_TRUE(recheck_claimed(choose_unlearned(with_blank, looks), 1));
  EXPECT_FALSE(recheck_claimed(choose_unlearned(blobs, {{}, {}}), 0));
  // Not a blob of the claims.
  EXPECT_THROW((void)recheck_claimed(cl, -1), Error);
  EXPECT_THROW((void)recheck_claimed(cl, 4), Error);
  // The option: off by default, 0..5, only with choice looks.
  SelfSupervisionOptions o;
  EXPECT_EQ(o.recheck_tries, 0);
  o.recheck_tries = 2;
  EXPECT_NO_THROW(o.validate());
  EXPECT_EQ(core::fields_to_json(o).at("recheck_tries"), 2);
  o.recheck_tries = 6;
  EXPECT_THROW(o.validate(), Error);
  o.recheck_tries = -1;
  EXPECT_THROW(o.validate(), Error);
  o.recheck_tries = 1;
  o.choice = NextObjectRule::kDirichlet;
  EXPECT_THROW(o.validate(), Error);
}

// claims_by view-words (session 35): each class claims the blob whose words its views' pooled
// multinomial explains best against the look's blobs pooled; a new object's words are left
// unclaimed and chosen. Known answers on a six-word vocabulary.
TEST(SelfSupervision, ClaimsByViewWordsTellALearnedObjectFromANewOne) {
  constexpr int kWords = 6;
  // Class 0 learned A (words 0, 1), class 1 B (words 2, 3), class 2 nothing yet.
  Eigen::VectorXd a = Eigen::VectorXd::Zero(kWords);
  a << 40, 38, 1, 1, 0, 0;
  Eigen::VectorXd b = Eigen::VectorXd::Zero(kWords);
  b << 1, 0, 30, 45, 2, 0;
  const std::vector<Eigen::VectorXd> counts{a, b, Eigen::VectorXd::Zero(kWords)};
  // Blob 0: A; blob 1: a new object C (words 4, 5); blob 2: B; blob 3: unscored.
  const std::vector<std::vector<std::int32_t>> blobs{
      {0, 1, 0, 1, 1, 0}, {4, 5, 5, 4, 5, 2}, {2, 3, 3, 2, 3}, {}};
  const NextChoice next = choose_unlearned_by_words(blobs, counts, kWords);
  EXPECT_EQ(next.blob, 1);
  EXPECT_EQ(next.claimed_by, (std::vector<int>{0, -1, 1, -1}));
  EXPECT_EQ(next.nearest_class, (std::vector<int>{0, 1, 1, -1}));
  EXPECT_EQ(next.nearest[3], -1.0);
  // Blob 0's distance to class 0, by hand: minus the mean log(p_c / p0) over its words.
  Eigen::VectorXd p0 = Eigen::VectorXd::Ones(kWords);
  for (const auto& d : blobs) {
    for (const int w : d) p0[w] += 1;
  }
  p0 /= p0.sum();
  const Eigen::VectorXd pa = (a + kWords * p0) / (a.sum() + kWords);
  double want = 0;
  for (const int w : blobs[0]) want -= std::log(pa[w] / p0[w]);
  want /= static_cast<double>(blobs[0].size());
  EXPECT_LT(want, 0) << "A's class explains A's words better than the look as a whole";
  EXPECT_NEAR(next.nearest[0], want, 1e-12);
  EXPECT_GT(next.nearest[1], 0) << "the new object's words: better by the look than by a class";
  // Negative distances: the matching is still the least total (class 0 on blob 0, not blob 2).
  const NextChoice two = choose_unlearned_by_words({blobs[2], blobs[0]}, counts, kWords);
  EXPECT_EQ(two.claimed_by, (std::vector<int>{1, 0}));
  EXPECT_GE(two.blob, 0) << "every blob claimed: the farthest of all";
  // No class has views yet: the first scored blob; nothing scored: none.
  const std::vector<Eigen::VectorXd> none(2, Eigen::VectorXd::Zero(kWords));
  EXPECT_EQ(choose_unlearned_by_words(blobs, none, kWords).blob, 0);
  EXPECT_EQ(choose_unlearned_by_words({{}, {}}, counts, kWords).blob, -1);
  // Bad input throws.
  EXPECT_THROW((void)choose_unlearned_by_words({{6}}, counts, kWords), Error);
  EXPECT_THROW((void)choose_unlearned_by_words({{-1}}, counts, kWords), Error);
  EXPECT_THROW((void)choose_unlearned_by_words(blobs, {Eigen::VectorXd::Ones(5)}, kWords), Error);
  EXPECT_THROW((void)choose_unlearned_by_words(blobs, counts, 0), Error);
  // The option: colour by default (session 41), in the JSON; another signal only with choice
  // looks.
  SelfSupervisionOptions o;
  EXPECT_EQ(o.claims_by, ClaimSignal::kColour);
  EXPECT_EQ(core::fields_to_json(o).at("claims_by"), "colour");
  o.choice = NextObjectRule::kDirichlet;
  EXPECT_NO_THROW(o.validate());
  o.claims_by = ClaimSignal::kLooks;
  EXPECT_THROW(o.validate(), Error);
  o.choice = NextObjectRule::kLooks;
  EXPECT_NO_THROW(o.validate());
  o.claims_by = ClaimSignal::kViewWords;
  EXPECT_NO_THROW(o.validate());
  EXPECT_EQ(core::fields_to_json(o).at("claims_by"), "view-words");
  o.claims_by = ClaimSignal::kLookWords;
  EXPECT_NO_THROW(o.validate());
  EXPECT_EQ(core::fields_to_json(o).at("claims_by"), "look-words");
  o.claims_by = ClaimSignal::kFirstLookWords;
  EXPECT_NO_THROW(o.validate());
  EXPECT_EQ(core::fields_to_json(o).at("claims_by"), "first-look-words");
  o.choice = NextObjectRule::kDirichlet;
  EXPECT_THROW(o.validate(), Error);
}

// claims_by descriptors (session 36): SIFT-like descriptors matched with Lowe's ratio test, the
// second neighbour from another object (the other classes and the look's other blobs). Known
// answers on random descriptors: a class's own descriptors with noise claim their blob, a new
// object's blob is left unclaimed and chosen, an ambiguous match (two classes alike) claims
// nothing, and min_share decides whether a weak share claims.
namespace {
cv::Mat random_descriptors(int n, std::uint32_t seed) {
  cv::Mat m(n, 128, CV_32F);
  cv::RNG rng(seed);
  rng.fill(m, cv::RNG::UNIFORM, 0.0, 100.0);
  return m;
}
cv::Mat noisy(const cv::Mat& m, std::uint32_t seed) {
  cv::Mat noise(m.size(), CV_32F);
  cv::RNG rng(seed);
  rng.fill(noise, cv::RNG::UNIFORM, -2.0, 2.0);
  return m + noise;
}
}  // namespace

TEST(SelfSupervision, ClaimsByDescriptorsTellALearnedObjectFromANewOne) {
  const cv::Mat a = random_descriptors(60, 1);
  const cv::Mat b = random_descriptors(50, 2);
  const cv::Mat c = random_descriptors(40, 3);  // a new object
  // Class 0 learned A, class 1 B, class 2 nothing yet.
  const std::vector<cv::Mat> classes{a, b, cv::Mat()};
  // Blob 0: A seen again (noise); blob 1: the new object; blob 2: B; blob 3: unscored.
  const std::vector<cv::Mat> blobs{noisy(a, 11), c, noisy(b, 12), cv::Mat()};
  const NextChoice next = choose_unlearned_by_descriptors(blobs, classes, 0.8, 0.05);
  EXPECT_EQ(next.blob, 1);
  EXPECT_EQ(next.claimed_by, (std::vector<int>{0, -1, 1, -1}));
  EXPECT_EQ(next.nearest_class[0], 0);
  EXPECT_EQ(next.nearest_class[2], 1);
  EXPECT_DOUBLE_EQ(next.nearest[0], -1.0) << "every descriptor of A's blob matches A's class";
  EXPECT_DOUBLE_EQ(next.nearest[2], -1.0);
  EXPECT_GT(next.nearest[1], -0.05) << "the new object's descriptors match no class";
  EXPECT_EQ(next.nearest[3], -1.0) << "unscored";
  // Half the blob is A: minus the share, about -0.5.
  cv::Mat half;
  cv::vconcat(noisy(a.rowRange(0, 30), 13), random_descriptors(30, 4), half);
  const NextChoice shared = choose_unlearned_by_descriptors({half, c}, classes, 0.8, 0.05);
  EXPECT_NEAR(shared.nearest[0], -0.5, 0.05);
  EXPECT_EQ(shared.claimed_by, (std::vector<int>{0, -1}));
  // min_share above the share: the class claims nothing, the blob is chosen (farthest of the
  // unclaimed is the new object's, so compare with the new object out).
  const NextChoice weak = choose_unlearned_by_descriptors({half}, classes, 0.8, 0.6);
  EXPECT_EQ(weak.claimed_by, (std::vector<int>{-1}));
  EXPECT_EQ(weak.blob, 0);
  // The new object alone in its look (only the classes to compare with): a chance match or
  // two, below min_share: no claim. With min_share 0 any match claims.
  const NextChoice alone = choose_unlearned_by_descriptors({c}, classes, 0.8, 0.05);
  EXPECT_EQ(alone.claimed_by, (std::vector<int>{-1}));
  EXPECT_EQ(alone.blob, 0);
  EXPECT_GT(alone.nearest[0], -0.05);
  const NextChoice any = choose_unlearned_by_descriptors({c}, classes, 0.8, 0.0);
  EXPECT_EQ(any.claimed_by[0] >= 0, any.nearest[0] < 0) << "claimed exactly with a match";
  // Ambiguous: two classes hold the same object (A seen twice, each with its own noise, as
  // the blob is): the nearest of the two is hardly nearer than the other, the ratio test
  // rejects the matches and neither claims A's blob.
  const NextChoice twice =
      choose_unlearned_by_descriptors({noisy(a, 14), c}, {noisy(a, 15), noisy(a, 16)}, 0.8, 0.05);
  EXPECT_EQ(twice.claimed_by, (std::vector<int>{-1, -1}));
  EXPECT_GT(twice.nearest[0], -0.05);
  // Ratio 1 accepts any nearest: A's blob is claimed by one of the two classes.
  const NextChoice loose =
      choose_unlearned_by_descriptors({noisy(a, 14), c}, {noisy(a, 15), noisy(a, 16)}, 1.0, 0.05);
  EXPECT_GE(loose.claimed_by[0], 0);
  EXPECT_LT(loose.nearest[0], -0.3);
  // No class yet: the first scored blob; nothing scored: none.
  EXPECT_EQ(choose_unlearned_by_descriptors(blobs, {cv::Mat(), cv::Mat()}, 0.8, 0.05).blob, 0);
  EXPECT_EQ(choose_unlearned_by_descriptors({cv::Mat(), cv::Mat()}, classes, 0.8, 0.05).blob, -1);
  // Bad input throws.
  EXPECT_THROW(
      (void)choose_unlearned_by_descriptors({cv::Mat(3, 64, CV_32F, 1.0)}, classes, 0.8, 0.05),
      Error);
  EXPECT_THROW(
      (void)choose_unlearned_by_descriptors({cv::Mat(3, 128, CV_8U, 1)}, classes, 0.8, 0.05),
      Error);
  EXPECT_THROW((void)choose_unlearned_by_descriptors(blobs, classes, 0.0, 0.05), Error);
  EXPECT_THROW((void)choose_unlearned_by_descriptors(blobs, classes, 1.5, 0.05), Error);
  EXPECT_THROW((void)choose_unlearned_by_descriptors(blobs, classes, 0.8, -0.1), Error);
  // The options: their defaults, JSON names, bounds and needs.
  SelfSupervisionOptions o;
  EXPECT_EQ(o.other_claims_by, ClaimSignal::kNone);
  EXPECT_EQ(core::fields_to_json(o).at("other_claims_by"), "none");
  EXPECT_EQ(core::fields_to_json(o).at("descriptor_ratio"), 0.8);
  EXPECT_EQ(core::fields_to_json(o).at("descriptor_min_share"), 0.05);
  EXPECT_EQ(core::fields_to_json(o).at("descriptor_cap"), 2000);
  EXPECT_EQ(o.descriptor_source, DescriptorSource::kLooks);
  EXPECT_EQ(core::fields_to_json(o).at("descriptor_source"), "looks");
  o.descriptor_source = DescriptorSource::kViews;
  EXPECT_EQ(core::fields_to_json(o).at("descriptor_source"), "views");
  o.descriptor_source = DescriptorSource::kFirstLook;
  EXPECT_EQ(core::fields_to_json(o).at("descriptor_source"), "first-look");
  o.descriptor_source = DescriptorSource::kLooks;
  o.claims_by = ClaimSignal::kDescriptors;
  EXPECT_NO_THROW(o.validate());
  EXPECT_EQ(core::fields_to_json(o).at("claims_by"), "descriptors");
  o.other_claims_by = ClaimSignal::kLooks;
  EXPECT_NO_THROW(o.validate());
  EXPECT_EQ(core::fields_to_json(o).at("other_claims_by"), "looks");
  o.other_claims_by = ClaimSignal::kDescriptors;
  EXPECT_THROW(o.validate(), Error) << "the comparison is another signal";
  o.other_claims_by = ClaimSignal::kNone;
  o.descriptor_ratio = 1.5;
  EXPECT_THROW(o.validate(), Error);
  o.descriptor_ratio = 0.8;
  o.descriptor_cap = 5;
  EXPECT_THROW(o.validate(), Error);
  o.descriptor_cap = 2000;
  o.descriptor_min_share = 1.5;
  EXPECT_THROW(o.validate(), Error);
  o.descriptor_min_share = 0.05;
  o.claims_by = ClaimSignal::kNone;
  EXPECT_THROW(o.validate(), Error);
  o.claims_by = ClaimSignal::kLookWords;
  o.other_claims_by = ClaimSignal::kFirstLookWords;
  EXPECT_THROW(o.validate(), Error) << "they keep the same counts";
  o.claims_by = ClaimSignal::kDescriptors;
  o.other_claims_by = ClaimSignal::kNone;
  o.choice = NextObjectRule::kDirichlet;
  EXPECT_THROW(o.validate(), Error);
}

TEST(SelfSupervision, ExplainedByTellsALearnedObjectFromANewOne) {
  // Two learned classes, A (topic 0) and B (topic 1), 8 views each; a round's first views of A
  // again, of a new object C (topic 2), and of A mixed with C.
  const auto near = [](int topic, int i) {
    Eigen::VectorXd t = Eigen::VectorXd::Constant(4, 0.0);
    const double main = 0.62 + 0.02 * i;
    t(topic) = main;
    const double rest = 1.0 - main;
    t((topic + 1) % 4) = 0.5 * rest;
    t((topic + 2) % 4) = (0.3 - 0.01 * (i % 3)) * rest;
    t((topic + 3) % 4) = rest - t((topic + 1) % 4) - t((topic + 2) % 4);
    return t;
  };
  const int n = 8;
  Eigen::MatrixXd known(2 * n + 1, 4);
  std::vector<int> labels;
  for (int i = 0; i < n; ++i) {
    known.row(i) = near(0, i).transpose();
    known.row(n + i) = near(1, i).transpose();
  }
  labels.assign(static_cast<std::size_t>(n), 0);
  labels.insert(labels.end(), static_cast<std::size_t>(n), 1);
  known.row(2 * n) = near(2, 0).transpose();  // a view of no class the model has (-1)
  labels.push_back(-1);
  topics::MotOptions mo;
  mo.components = 1;
  const topics::MotModel model =
      topics::fit_mot(known.topRows(2 * n), std::span<const int>(labels.data(), 2 * n), {"A", "B"},
                      mo)
          .model;
  Eigen::MatrixXd again(n, 4);
  Eigen::MatrixXd other(n, 4);
  for (int i = 0; i < n; ++i) {
    again.row(i) = near(0, i).transpose();
    other.row(i) = near(2, i).transpose();
  }
  // A's own views again: each scores as it did, so 7 of 8 are at least A's lower quartile
  // (the second least of 8) and none is B's.
  const RepeatTest a = explained_by(model, known, labels, again, 0.5);
  EXPECT_EQ(a.cls, 0);
  ASSERT_EQ(a.shares.size(), 2U);
  EXPECT_DOUBLE_EQ(a.shares[0], 7.0 / 8.0);
  EXPECT_DOUBLE_EQ(a.shares[1], 0.0);
  EXPECT_TRUE(std::isfinite(a.floors[0]));
  EXPECT_TRUE(std::isfinite(a.floors[1]));
  // The share asked for is what decides: 7/8 is enough for 0.85, not for 0.9.
  EXPECT_EQ(explained_by(model, known, labels, again, 0.85).cls, 0);
  EXPECT_EQ(explained_by(model, known, labels, again, 0.9).cls, -1);
  // A new object: no class explains any of its views.
  const RepeatTest c = explained_by(model, known, labels, other, 0.5);
  EXPECT_EQ(c.cls, -1);
  EXPECT_DOUBLE_EQ(c.shares[0], 0.0);
  EXPECT_DOUBLE_EQ(c.shares[1], 0.0);
  // Half A, half the new object: A explains at most half (the first four include A's least).
  Eigen::MatrixXd half(n, 4);
  half.topRows(n / 2) = again.bottomRows(n / 2);
  half.bottomRows(n / 2) = other.topRows(n / 2);
  EXPECT_DOUBLE_EQ(explained_by(model, known, labels, half, 0.5).shares[0], 0.5);
  EXPECT_EQ(explained_by(model, known, labels, half, 0.5).cls, 0);
  EXPECT_EQ(explained_by(model, known, labels, half, 0.6).cls, -1);
  // A class with no views of its own explains nothing (its floor is -inf).
  std::vector<int> no_b = labels;
  for (int i = n; i < 2 * n; ++i) no_b[static_cast<std::size_t>(i)] = -1;
  Eigen::MatrixXd bs(1, 4);
  bs.row(0) = near(1, 3).transpose();
  const RepeatTest b = explained_by(model, known, no_b, bs, 0.5);
  EXPECT_EQ(b.cls, -1);
  EXPECT_FALSE(std::isfinite(b.floors[1]));
  EXPECT_EQ(explained_by(model, known, labels, bs, 0.5).cls, 1);
  // Bad input.
  EXPECT_THROW((void)explained_by(model, known, {0, 1}, again, 0.5), Error);
  std::vector<int> bad = labels;
  bad[0] = 2;
  EXPECT_THROW((void)explained_by(model, known, bad, again, 0.5), Error);
  EXPECT_THROW((void)explained_by(model, known, labels, again, 0.0), Error);
  EXPECT_THROW(
      (void)explained_by(model, known, labels, Eigen::MatrixXd::Constant(2, 3, 1.0 / 3), 0.5),
      Error);
}

TEST(SelfSupervision, RoundDistanceKnownAnswers) {
  const Eigen::VectorXd a = (Eigen::VectorXd(4) << 10, 0, 0, 0).finished();
  const Eigen::VectorXd b = (Eigen::VectorXd(4) << 0, 10, 0, 0).finished();
  EXPECT_NEAR(round_distance(a, a), 0.0, 1e-12);
  EXPECT_NEAR(round_distance(a, b), round_distance(b, a), 1e-12);
  // phi_a = (10.5, .5, .5, .5) / 12: a's words cost log(10.5 / .5) more under phi_b than phi_a.
  EXPECT_NEAR(round_distance(a, b), std::log(21.0), 1e-12);
  // Scale does not matter when the proportions are the same (apart from the smoothing).
  EXPECT_LT(round_distance(a, 10 * a), 0.01);
  EXPECT_THROW((void)round_distance(a, Eigen::VectorXd::Zero(4)), Error);
  EXPECT_THROW((void)round_distance(a, Eigen::VectorXd::Ones(3)), Error);
}

TEST(SelfSupervision, RoundsOfOneObjectMergeAndDifferentObjectsDoNot) {
  // Three objects' word multinomials over 6 words; rounds 0 and 2 both learned object A (their
  // counts differ a little), round 1 B, round 3 C, round 4 nothing (no views).
  const auto v = [](std::initializer_list<double> x) {
    Eigen::VectorXd r(static_cast<Eigen::Index>(x.size()));
    Eigen::Index i = 0;
    for (const double e : x) r[i++] = e;
    return r;
  };
  const std::vector<Eigen::VectorXd> counts = {v({50, 40, 2, 1, 1, 1}), v({1, 2, 50, 40, 1, 1}),
                                               v({45, 46, 1, 2, 1, 0}), v({1, 1, 0, 2, 48, 44}),
                                               v({0, 0, 0, 0, 0, 0})};
  const RoundMerge m = merge_rounds(counts, 3, 0.3);
  EXPECT_EQ(m.class_of_round, (std::vector<int>{0, 1, 0, 2, -1}));
  EXPECT_EQ(m.judged, (std::vector<int>{0, 1, 0, 2, -1}));
  EXPECT_EQ(m.distinct, 3);
  ASSERT_EQ(m.steps.size(), 1U);  // A's two rounds only: B and C stay apart
  EXPECT_EQ(m.steps[0].a, (std::vector<int>{0}));
  EXPECT_EQ(m.steps[0].b, (std::vector<int>{2}));
  EXPECT_TRUE(m.steps[0].same);
  EXPECT_LT(m.steps[0].distance, 0.3);

  // Room for four classes: no merge is needed for the classes, the judgement still finds A twice.
  const RoundMerge four = merge_rounds(counts, 4, 0.3);
  EXPECT_EQ(four.class_of_round, (std::vector<int>{0, 1, 2, 3, -1}));
  EXPECT_EQ(four.judged, (std::vector<int>{0, 1, 0, 2, -1}));
  EXPECT_EQ(four.distinct, 3);

  // Two classes: different objects are merged (the nearest pair) only because C is 2, and the
  // merge says so (not judged the same object).
  const RoundMerge two = merge_rounds(counts, 2, 0.3);
  EXPECT_EQ(two.distinct, 3);
  ASSERT_EQ(two.steps.size(), 2U);
  EXPECT_FALSE(two.steps[1].same);
  EXPECT_GE(two.steps[1].distance, 0.3);
  EXPECT_EQ(two.class_of_round[0], two.class_of_round[2]);
  EXPECT_EQ(*std::max_element(two.class_of_round.begin(), two.class_of_round.end()), 1);

  // A threshold nothing is below: every round its own object, C classes still made.
  const RoundMerge strict = merge_rounds(counts, 3, 0.0);
  EXPECT_EQ(strict.distinct, 4);
  EXPECT_EQ(strict.class_of_round, (std::vector<int>{0, 1, 0, 2, -1}));
  EXPECT_EQ(strict.judged, (std::vector<int>{0, 1, 2, 3, -1}));
  EXPECT_THROW((void)merge_rounds(counts, 0, 0.3), Error);
}

TEST(SelfSupervision, ColourRoundDistanceKnownAnswers) {
  const Eigen::VectorXd a = (Eigen::VectorXd(2) << 1, 0).finished();
  const Eigen::VectorXd b = (Eigen::VectorXd(2) << 1, 1).finished();
  const Eigen::VectorXd c = (Eigen::VectorXd(2) << 0, 3).finished();
  EXPECT_NEAR(colour_round_distance(a, 7 * a), 0.0, 1e-12);  // proportions, not counts
  EXPECT_NEAR(colour_round_distance(a, c), 1.0, 1e-12);      // no colour in common
  // p = (1, 0), q = (1/2, 1/2): Bhattacharyya coefficient sqrt(1/2), d = sqrt(1 - sqrt(1/2)).
  EXPECT_NEAR(colour_round_distance(a, b), std::sqrt(1.0 - std::sqrt(0.5)), 1e-12);
  EXPECT_NEAR(colour_round_distance(a, b), colour_round_distance(b, a), 1e-12);
  EXPECT_THROW((void)colour_round_distance(a, Eigen::VectorXd::Zero(2)), Error);
  EXPECT_THROW((void)colour_round_distance(a, Eigen::VectorXd::Ones(3)), Error);
  EXPECT_THROW((void)colour_round_distance(a, -b), Error);
}

// table_colours_out: a tan table round a blob whose box shows a red square and tan table. The
// table's word is the tan one alone (the blob's red and a small blue "arm" outside it stay under
// the share); taken out of the blob's counts, only the red is left; a blob of tan only keeps its
// counts.
TEST(SelfSupervision, TableColourWordsAreTheTablesAndLeaveTheBlobsOwnColours) {
  const features::ColourWordOptions colour;
  const cv::Scalar tan(110, 170, 215);  // BGR: a light orange-brown
  cv::Mat image(120, 160, CV_8UC3, tan);
  cv::rectangle(image, cv::Rect(60, 40, 20, 20), cv::Scalar(0, 0, 220), cv::FILLED);  // red
  cv::rectangle(image, cv::Rect(0, 0, 12, 12), cv::Scalar(200, 40, 0), cv::FILLED);   // blue arm
  planning::PutativeObject blob;
  blob.box = cv::Rect(50, 30, 40, 40);  // the red square and a 10 px frame of table
  blob.mask = cv::Mat1b(blob.box.size(), 255);
  planning::PlanningView view;
  view.objects.push_back(blob);

  const std::vector<bool> table = table_colour_words(image, view, colour);
  ASSERT_EQ(table.size(), static_cast<std::size_t>(colour.count()));
  const auto word_of = [&](const cv::Scalar& c) {
    const cv::Mat one(1, 1, CV_8UC3, c);
    const std::vector<double> n =
        features::colour_word_counts(one, cv::Mat(1, 1, CV_8U, cv::Scalar(255)), colour);
    return static_cast<int>(std::max_element(n.begin(), n.end()) - n.begin());
  };
  const int tan_word = word_of(tan);
  const int red_word = word_of(cv::Scalar(0, 0, 220));
  ASSERT_NE(tan_word, red_word);
  EXPECT_EQ(std::count(table.begin(), table.end(), true), 1);
  EXPECT_TRUE(table[static_cast<std::size_t>(tan_word)]);

  cv::Mat in_blob = cv::Mat::zeros(image.size(), CV_8U);
  in_blob(blob.box).setTo(255);
  const std::vector<double> raw = features::colour_word_counts(image, in_blob, colour);
  const Eigen::VectorXd counts =
      Eigen::Map<const Eigen::VectorXd>(raw.data(), static_cast<Eigen::Index>(raw.size()));
  ASSERT_GT(counts[tan_word], 0.0);  // the frame of table is in the blob's pixels
  const Eigen::VectorXd own = without_table_colours(counts, table);
  EXPECT_EQ(own[tan_word], 0.0);
  EXPECT_EQ(own[red_word], counts[red_word]);
  EXPECT_DOUBLE_EQ(own.sum(), counts.sum() - counts[tan_word]);
  // A blob of the table's colour only keeps its counts; no flag, no change.
  Eigen::VectorXd tan_only = Eigen::VectorXd::Zero(counts.size());
  tan_only[tan_word] = 50;
  EXPECT_EQ(without_table_colours(tan_only, table), tan_only);
  EXPECT_EQ(without_table_colours(counts, std::vector<bool>(table.size(), false)), counts);
  // A blob over the whole image leaves no table: nothing flagged.
  planning::PlanningView whole;
  whole.objects.push_back(planning::PutativeObject{});
  whole.objects.back().box = cv::Rect(0, 0, image.cols, image.rows);
  whole.objects.back().mask = cv::Mat1b(image.size(), 255);
  const std::vector<bool> none = table_colour_words(image, whole, colour);
  EXPECT_EQ(std::count(none.begin(), none.end(), true), 0);
  EXPECT_THROW((void)table_colour_words(image, view, colour, 0.0), Error);
  EXPECT_THROW((void)without_table_colours(counts, std::vector<bool>(3, false)), Error);
}

// merge_rounds by colour: rounds 0 and 2 saw one object's colours (a little different), round 1
// another's, round 3 none (no views): 0 and 2 are judged one object, 1 another; the word
// distance's threshold means nothing here (0.3 Hellinger bounds the colours).
TEST(SelfSupervision, RoundsOfOneObjectsColoursMergeByColourDistance) {
  const std::vector<Eigen::VectorXd> colours = {(Eigen::VectorXd(4) << 80, 15, 5, 0).finished(),
                                                (Eigen::VectorXd(4) << 2, 3, 60, 35).finished(),
                                                (Eigen::VectorXd(4) << 70, 25, 3, 2).finished(),
                                                Eigen::VectorXd::Zero(4)};
  const RoundMerge m = merge_rounds(colours, 2, 0.3, colour_round_distance);
  EXPECT_EQ(m.judged, (std::vector<int>{0, 1, 0, -1}));
  EXPECT_EQ(m.class_of_round, (std::vector<int>{0, 1, 0, -1}));
  EXPECT_EQ(m.distinct, 2);
  ASSERT_EQ(m.steps.size(), 1U);
  EXPECT_TRUE(m.steps[0].same);
  EXPECT_NEAR(m.steps[0].distance, colour_round_distance(colours[0], colours[2]), 1e-12);
  // A bound below their distance: three objects judged, two classes still made.
  const RoundMerge strict = merge_rounds(colours, 2, 0.05, colour_round_distance);
  EXPECT_EQ(strict.distinct, 3);
  EXPECT_EQ(strict.class_of_round, (std::vector<int>{0, 1, 0, -1}));
  EXPECT_THROW((void)merge_rounds(colours, 2, 0.3, nullptr), Error);
}

// moved_pixels: a square the push moved 4 px right, a neighbour it left where it was, the table
// around both, all inside the region; a pixel whose change is exactly `levels` is not moved, one
// more is. Only the region's pixels count.
TEST(SelfSupervision, MovedPixelsAreTheRegionsPixelsThatChanged) {
  const cv::Vec3b table(200, 200, 200);
  cv::Mat before(20, 30, CV_8UC3, cv::Scalar(table[0], table[1], table[2]));
  cv::Mat after = before.clone();
  before(cv::Rect(2, 5, 6, 6)).setTo(cv::Scalar(0, 0, 255));   // the pushed object, red
  after(cv::Rect(6, 5, 6, 6)).setTo(cv::Scalar(0, 0, 255));    // 4 px to the right
  before(cv::Rect(20, 5, 5, 5)).setTo(cv::Scalar(255, 0, 0));  // the neighbour, blue, still
  after(cv::Rect(20, 5, 5, 5)).setTo(cv::Scalar(255, 0, 0));
  const cv::Mat all(before.size(), CV_8UC1, cv::Scalar(255));
  const cv::Mat moved = moved_pixels(before, after, all, kMovedLevels);
  // Columns 2-5 turned table and 8-11 turned red; 6-7 are red in both.
  cv::Mat expected = cv::Mat::zeros(before.size(), CV_8UC1);
  expected(cv::Rect(2, 5, 4, 6)).setTo(255);
  expected(cv::Rect(8, 5, 4, 6)).setTo(255);
  EXPECT_EQ(cv::countNonZero(moved != expected), 0);
  EXPECT_EQ(cv::countNonZero(moved(cv::Rect(20, 5, 5, 5))), 0);  // the neighbour left out
  // A region: only its pixels.
  cv::Mat left = cv::Mat::zeros(before.size(), CV_8UC1);
  left(cv::Rect(0, 0, 7, 20)).setTo(255);
  EXPECT_EQ(cv::countNonZero(moved_pixels(before, after, left, kMovedLevels)), 4 * 6);
  // The bound: a change of exactly `levels` in one channel is not a move, one more is.
  cv::Mat shaded = before.clone();
  shaded.at<cv::Vec3b>(0, 0) = cv::Vec3b(200, 200, 200 - 10);
  shaded.at<cv::Vec3b>(0, 1) = cv::Vec3b(200, 200 + 11, 200);
  const cv::Mat m10 = moved_pixels(before, shaded, all, 10);
  EXPECT_EQ(m10.at<std::uint8_t>(0, 0), 0);
  EXPECT_EQ(m10.at<std::uint8_t>(0, 1), 255);
  // Grey images work alike.
  cv::Mat gb;
  cv::Mat ga;
  cv::cvtColor(before, gb, cv::COLOR_BGR2GRAY);
  cv::cvtColor(after, ga, cv::COLOR_BGR2GRAY);
  EXPECT_EQ(cv::countNonZero(moved_pixels(gb, ga, all, kMovedLevels) != expected), 0);
  // Bad input.
  EXPECT_THROW((void)moved_pixels(cv::Mat(), after, all, 10), Error);
  EXPECT_THROW((void)moved_pixels(before, ga, all, 10), Error);
  EXPECT_THROW((void)moved_pixels(before, after(cv::Rect(0, 0, 10, 10)), all, 10), Error);
  EXPECT_THROW((void)moved_pixels(before, after, all(cv::Rect(0, 0, 10, 10)), 10), Error);
  EXPECT_THROW((void)moved_pixels(before, after, all, 255), Error);
  EXPECT_THROW((void)moved_pixels(before, after, all, -1), Error);
}

TEST(SelfSupervision, HullGapKnownAnswers) {
  const std::vector<Eigen::Vector2d> a{{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  const auto shifted = [&](const Eigen::Vector2d& by) {
    std::vector<Eigen::Vector2d> out(a.size());
    for (std::size_t i = 0; i < a.size(); ++i) out[i] = a[i] + by;
    return out;
  };
  const std::vector<Eigen::Vector2d> b = shifted({3, 0});
  EXPECT_NEAR(hull_gap(a, b), 2.0, 1e-12);
  EXPECT_NEAR(hull_gap(b, a), 2.0, 1e-12);
  const std::vector<Eigen::Vector2d> c = shifted({0.5, 0.5});  // overlapping, a vertex inside
  EXPECT_EQ(hull_gap(a, c), 0.0);
  // A cross: no vertex of either inside the other, yet they overlap.
  const std::vector<Eigen::Vector2d> h{{-2, -0.1}, {2, -0.1}, {2, 0.1}, {-2, 0.1}};
  const std::vector<Eigen::Vector2d> v{{-0.1, -2}, {0.1, -2}, {0.1, 2}, {-0.1, 2}};
  EXPECT_EQ(hull_gap(h, v), 0.0);
  // Diagonal: corner (1,1) to corner (2,2).
  const std::vector<Eigen::Vector2d> d = shifted({2, 2});
  EXPECT_NEAR(hull_gap(a, d), std::sqrt(2.0), 1e-12);
}

TEST(SelfSupervision, YawCoverageAndFootprintGap) {
  EXPECT_EQ(yaw_coverage_deg({0.3}), 0.0);
  EXPECT_NEAR(yaw_coverage_deg({0.0, std::numbers::pi / 2}), 90.0, 1e-9);
  // Wraps around: -10 and +10 degrees cover 20 degrees, not 340.
  const double ten = 10 * std::numbers::pi / 180;
  EXPECT_NEAR(yaw_coverage_deg({-ten, ten}), 20.0, 1e-9);
  EXPECT_NEAR(yaw_coverage_deg({0, 2.1, 4.2}), 360 - (2.1 * 180 / std::numbers::pi), 1e-9);
  // The turn of a push: wrapped, 0..180 degrees.
  EXPECT_NEAR(turn_deg(-ten, ten), 20.0, 1e-9);
  EXPECT_NEAR(turn_deg(std::numbers::pi - ten, -std::numbers::pi + ten), 20.0, 1e-9);
  EXPECT_NEAR(turn_deg(0.5, 0.5 + 4 * std::numbers::pi), 0.0, 1e-9);
  sim::ObjectTruth a;
  sim::ObjectTruth b;
  a.centre = {0, 0, 0.02};
  b.centre = {0.3, 0.4, 0.05};
  a.footprint_radius = 0.1;
  b.footprint_radius = 0.15;
  EXPECT_NEAR(footprint_gap(a, b), 0.25, 1e-12);
  b.centre = {0.1, 0, 0};
  EXPECT_EQ(footprint_gap(a, b), 0.0);
}

planning::PushPlan straight_plan(const Eigen::Vector2d& centre, double approach) {
  // A push along +x through `centre`, as planning::push_through_centre makes it: the start
  // `approach` behind the hull's back edge (set by the caller), the end 6 cm on.
  planning::PushPlan p;
  p.outcome = planning::PlanOutcome::kPlanned;
  p.centre = centre;
  p.direction = Eigen::Vector2d::UnitX();
  p.approach = approach;
  p.push.end = centre + Eigen::Vector2d(0.06, 0);
  p.push.height = 0.008;
  p.push.speed = 0.05;
  return p;
}

TEST(SelfSupervision, TurningPushMeetsTheObjectOffItsCentreLine) {
  // A 4 cm square about (0.3, 0): half width 2 cm to the left (+y) of the push along +x.
  const Eigen::Vector2d c(0.3, 0);
  const std::vector<Eigen::Vector2d> square{
      c + Eigen::Vector2d(-0.02, -0.02), c + Eigen::Vector2d(0.02, -0.02),
      c + Eigen::Vector2d(0.02, 0.02), c + Eigen::Vector2d(-0.02, 0.02)};
  planning::PushPlan p = straight_plan(c, 0.03);
  p.push.start = c - Eigen::Vector2d(0.05, 0);
  const TurningPush t = turning_push(p, square, 0.5);
  EXPECT_NEAR(t.offset, 0.01, 1e-12);
  EXPECT_NEAR(t.push.start.x(), 0.3 - 0.02 - 0.03, 1e-12);
  EXPECT_NEAR(t.push.start.y(), 0.01, 1e-12);  // left of +x
  EXPECT_NEAR(t.push.end.x(), p.push.end.x(), 1e-12);
  EXPECT_NEAR(t.push.end.y(), 0.01, 1e-12);
  // A diamond: off the centre line its back edge is nearer (2 cm behind, not 4): the start
  // stays `approach` behind the edge the pusher meets, not behind the centre's.
  const std::vector<Eigen::Vector2d> diamond{
      c + Eigen::Vector2d(0, -0.04), c + Eigen::Vector2d(0.04, 0), c + Eigen::Vector2d(0, 0.04),
      c + Eigen::Vector2d(-0.04, 0)};
  const TurningPush d = turning_push(p, diamond, 0.5);
  EXPECT_NEAR(d.offset, 0.02, 1e-12);
  EXPECT_NEAR(d.push.start.x(), 0.3 - 0.02 - 0.03, 1e-9);
  EXPECT_NEAR(d.push.start.y(), 0.02, 1e-12);
  // At most kMaxTurnOffset; fraction 0: the push unchanged.
  std::vector<Eigen::Vector2d> wide = square;
  for (Eigen::Vector2d& v : wide) v.y() = c.y() + 5 * (v.y() - c.y());
  EXPECT_NEAR(turning_push(p, wide, 0.9).offset, kMaxTurnOffset, 1e-12);
  const TurningPush none = turning_push(p, square, 0.0);
  EXPECT_EQ(none.offset, 0.0);
  EXPECT_EQ(none.push.start, p.push.start);
  EXPECT_EQ(none.push.end, p.push.end);
}

TEST(SelfSupervision, TurningPushTurnsTheObjectOnTheSimulatedTable) {
  // The same push of the calculator, through its centre and off it, on identical tables: off
  // the centre line the turn's sense is turning_push's (clockwise for a left offset), so the
  // turns of a round's pushes add up instead of cancelling (session 16, docs/results/).
  sim::TableOptions t;
  t.objects = {"calculator"};
  t.seed = 3;
  t.width = 320;
  t.height = 240;
  const sim::ObjectCatalogue catalogue = sim::ObjectCatalogue::load_default();
  const auto turned = [&](double fraction, double yaw = 0.3, double dir = 1.5707963,
                          const char* name = "calculator") {
    t.objects = {name};
    sim::SimulatedRobot robot(t, catalogue);
    robot.place({{name, Eigen::Vector2d(0.27, 0.0), yaw}});
    planning::PushPlanOptions po;
    po.grid_step = 3;
    po.patch = 6;
    po.blobs.sigma = 3;
    const planning::TableRegion region;
    const planning::PlanningView view = planning::look_for_objects(robot.look(), region, po);
    if (view.objects.empty()) return 0.0;
    // The largest blob (a plain object may show as two).
    int k = 0;
    for (std::size_t i = 0; i < view.objects.size(); ++i) {
      if (view.objects[i].pixels.size() > view.objects[static_cast<std::size_t>(k)].pixels.size()) {
        k = static_cast<int>(i);
      }
    }
    const auto& o = view.objects[static_cast<std::size_t>(k)];
    robot::ArmState arm(robot.arm());
    planning::PushPlan p =
        planning::plan_push(view, k, planning::PushGoal::kTarget,
                            o.centre + 0.08 * Eigen::Vector2d(std::cos(dir), std::sin(dir)), region,
                            arm, robot.joints(), po);
    if (p.outcome != planning::PlanOutcome::kPlanned) return 99.0;
    p.push = turning_push(p, o.hull, fraction).push;
    const double before = robot.ground_truth().at(0).yaw;
    try {
      (void)robot.push(p.push, {});
    } catch (const Error&) {
      return 99.0;
    }
    double d = robot.ground_truth().at(0).yaw - before;
    d = std::remainder(d, 2 * std::numbers::pi);
    return d;
  };
  // Through the centre a push turns it either way (here +12 and +22 degrees); off the centre
  // line to the left clockwise (-27, -33), to the right counter-clockwise (+16, +26).
  constexpr double kDeg = std::numbers::pi / 180;
  for (const auto& [yaw, dir] : {std::pair{0.4, 0.0}, std::pair{1.8, -1.57}}) {
    const double straight = turned(0.0, yaw, dir);
    EXPECT_GT(straight, 5 * kDeg) << yaw;
    EXPECT_LT(turned(0.6, yaw, dir), -10 * kDeg) << yaw;
    EXPECT_GT(turned(-0.6, yaw, dir), 10 * kDeg) << yaw;
  }
}

TEST(SelfSupervision, UnspentLearnPushesGoToLaterRounds) {
  EXPECT_EQ(round_budget(0, 10, 0), 10);
  EXPECT_EQ(round_budget(1, 10, 10), 10);
  EXPECT_EQ(round_budget(1, 10, 3), 17);  // round 0 lost its object after 3 pushes
  EXPECT_EQ(round_budget(2, 10, 3), 20);  // at most twice
  EXPECT_EQ(round_budget(2, 10, 25), 5);  // earlier rounds spent more
  EXPECT_EQ(round_budget(1, 10, 25), 0);
}

TEST(SelfSupervision, FollowByLooksRefindsTheRoundsObjectAfterASwap) {
  // The round's own looks are near (1 0 0 0); another class's near (0 0 1 0).
  const std::vector<Eigen::VectorXd> own{dist4(0.9, 0.05, 0.03, 0.02)};
  const std::vector<std::vector<Eigen::VectorXd>> others{{dist4(0.02, 0.03, 0.9, 0.05)}};
  // The blob that moved (1) looks like the other class; blob 0 like the round's object.
  const std::vector<Eigen::VectorXd> blobs{dist4(0.85, 0.1, 0.03, 0.02),
                                           dist4(0.05, 0.05, 0.85, 0.05), Eigen::VectorXd()};
  const Followed f = follow_by_looks(blobs, own, others, 1, 0.1);
  EXPECT_TRUE(f.refound);
  EXPECT_EQ(f.blob, 0);
  EXPECT_LT(f.distance, f.tracked_distance);
  // Margin 0 (off), or no own looks: the motion's blob.
  EXPECT_EQ(follow_by_looks(blobs, own, others, 1, 0.0).blob, 1);
  EXPECT_FALSE(follow_by_looks(blobs, {}, others, 1, 0.1).refound);
  // The moved blob still matches (within the margin): kept.
  const std::vector<Eigen::VectorXd> close{dist4(0.85, 0.1, 0.03, 0.02),
                                           dist4(0.8, 0.1, 0.05, 0.05)};
  EXPECT_EQ(follow_by_looks(close, own, others, 1, 0.1).blob, 1);
  EXPECT_FALSE(follow_by_looks(close, own, others, 1, 0.1).refound);
  // A blob nearer another class's looks than the round's is never taken.
  const std::vector<std::vector<Eigen::VectorXd>> near_other{{dist4(0.86, 0.1, 0.02, 0.02)}};
  EXPECT_EQ(follow_by_looks(blobs, own, near_other, 1, 0.1).blob, 1);
  // Nothing moved (tracked -1): the blob that matches.
  EXPECT_EQ(follow_by_looks(blobs, own, others, -1, 0.1).blob, 0);
}

// refind_colour (session 43): a round's object lost where it was left is found again by its
// looks' pixel colours; a blob nearer another round's looks is never taken, and max_distance
// bounds how unlike the own looks the blob may be.
TEST(SelfSupervision, RefindByColoursTakesTheBlobOfTheRoundsColours) {
  // Counts, not distributions: each is normalised.
  const Eigen::VectorXd own = 100 * dist4(0.9, 0.05, 0.03, 0.02);
  const std::vector<Eigen::VectorXd> others{40 * dist4(0.02, 0.03, 0.9, 0.05), Eigen::VectorXd()};
  const std::vector<Eigen::VectorXd> blobs{7 * dist4(0.05, 0.05, 0.85, 0.05), Eigen::VectorXd(),
                                           30 * dist4(0.8, 0.1, 0.05, 0.05)};
  const ColourRefind f = refind_by_colours(blobs, own, others, 0.3);
  EXPECT_EQ(f.blob, 2);
  EXPECT_EQ(f.nearest, 2);
  EXPECT_NEAR(f.distance, hellinger(dist4(0.8, 0.1, 0.05, 0.05), dist4(0.9, 0.05, 0.03, 0.02)),
              1e-12);
  EXPECT_GT(f.distance, 0.0);
  // Below the distance asked for only: the nearest is named, not taken.
  const ColourRefind tight = refind_by_colours(blobs, own, others, f.distance / 2);
  EXPECT_EQ(tight.blob, -1);
  EXPECT_EQ(tight.nearest, 2);
  // Off (0), or no own looks: nothing taken.
  EXPECT_EQ(refind_by_colours(blobs, own, others, 0.0).blob, -1);
  EXPECT_EQ(refind_by_colours(blobs, Eigen::VectorXd::Zero(4), others, 0.3).blob, -1);
  // The only blob left looks like another round's object: never taken, whatever the bound.
  const std::vector<Eigen::VectorXd> theirs_only{dist4(0.05, 0.05, 0.85, 0.05)};
  EXPECT_EQ(refind_by_colours(theirs_only, own, others, 1.0).nearest, -1);
  EXPECT_EQ(refind_by_colours(theirs_only, own, others, 1.0).blob, -1);
  // Without other rounds the same blob is the nearest own-coloured one, and is taken.
  EXPECT_EQ(refind_by_colours(theirs_only, own, {}, 1.0).blob, 0);
}

// refind_vetoes (session 46): every other round's colours veto a re-find, but with rounds not
// those of rounds judged the same object (the robot's own earlier sight of it).
TEST(SelfSupervision, RefindVetoesAreTheOtherObjectsRounds) {
  const std::vector<Eigen::VectorXd> colours{
      dist4(0.9, 0.05, 0.03, 0.02), dist4(0.02, 0.03, 0.9, 0.05), dist4(0.8, 0.1, 0.05, 0.05),
      dist4(0.1, 0.8, 0.05, 0.05)};
  const auto same = [](const std::vector<Eigen::VectorXd>& a,
                       const std::vector<Eigen::VectorXd>& b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i) {
      if (a[i] != b[i]) return false;
    }
    return true;
  };
  // No judgement: all others.
  EXPECT_TRUE(same(refind_vetoes(0, colours, {}), {colours[1], colours[2], colours[3]}));
  EXPECT_TRUE(same(refind_vetoes(3, colours, {}), {colours[0], colours[1], colours[2]}));
  // Rounds 0 and 2 judged one object: neither vetoes the other; round 3 without words (-1) vetoes.
  const std::vector<int> judged{0, 1, 0, -1};
  EXPECT_TRUE(same(refind_vetoes(0, colours, judged), {colours[1], colours[3]}));
  EXPECT_TRUE(same(refind_vetoes(2, colours, judged), {colours[1], colours[3]}));
  EXPECT_TRUE(same(refind_vetoes(1, colours, judged), {colours[0], colours[2], colours[3]}));
  // A round without a group is vetoed by all others, grouped or not; a short judgement is -1.
  EXPECT_TRUE(same(refind_vetoes(3, colours, judged), {colours[0], colours[1], colours[2]}));
  EXPECT_TRUE(same(refind_vetoes(2, colours, {0, 1}), {colours[0], colours[1], colours[3]}));
  // The veto decides the re-find: the blob like round 2's colours is round 0's object again.
  const std::vector<Eigen::VectorXd> blobs{dist4(0.8, 0.1, 0.05, 0.05)};
  EXPECT_EQ(refind_by_colours(blobs, colours[0], refind_vetoes(0, colours, {}), 1.0).blob, -1);
  EXPECT_EQ(refind_by_colours(blobs, colours[0], refind_vetoes(0, colours, judged), 1.0).blob, 0);
}

// A putative object: a square footprint of half side `h` about (x, y), table m, and (for the
// motion) feature points on a 4 px grid over the pixel box `px`.
planning::PutativeObject square_blob(double x, double y, double h, cv::Rect px = {}) {
  planning::PutativeObject o;
  o.centre = Eigen::Vector2d(x, y);
  o.hull = {{x - h, y - h}, {x + h, y - h}, {x + h, y + h}, {x - h, y + h}};
  o.box = px;
  for (int v = px.y; v < px.y + px.height; v += 4) {
    for (int u = px.x; u < px.x + px.width; u += 4) o.pixels.emplace_back(u, v);
  }
  return o;
}

TEST(SelfSupervision, LearnPushKeepsItsCorridorClearOfNeighbours) {
  // The object: 4 cm square at the origin; a neighbour 6 cm to its right (its left edge at
  // x = 0.08, 4 cm from the object's right edge).
  planning::PlanningView view;
  view.objects = {square_blob(0, 0, 0.02), square_blob(0.10, 0, 0.02)};
  const double clearance = 0.03;
  // Toward the neighbour, 6 cm: the corridor runs into it.
  EXPECT_GT(learn_push_lack(view, 0, {0.06, 0}, clearance), 0.0);
  // Toward it but shorter (4 cm): the corridor's edge stops 2 cm from it, 1 cm inside the
  // clearance.
  EXPECT_NEAR(learn_push_lack(view, 0, {0.04, 0}, clearance), 0.01, 1e-9);
  // 2 cm: 4 cm are left: clear.
  EXPECT_EQ(learn_push_lack(view, 0, {0.02, 0}, clearance), 0.0);
  // Away from it, or sideways: clear.
  EXPECT_EQ(learn_push_lack(view, 0, {-0.08, 0}, clearance), 0.0);
  EXPECT_EQ(learn_push_lack(view, 0, {0, 0.08}, clearance), 0.0);
  // Off (clearance 0), or no other blob: never a lack.
  EXPECT_EQ(learn_push_lack(view, 0, {0.06, 0}, 0.0), 0.0);
  planning::PlanningView alone;
  alone.objects = {square_blob(0, 0, 0.02)};
  EXPECT_EQ(learn_push_lack(alone, 0, {0.06, 0}, clearance), 0.0);
  // A neighbour nearer than the clearance already (1 cm): pushing away is clear, along it
  // (not nearer) too, toward it not.
  planning::PlanningView crowded;
  crowded.objects = {square_blob(0, 0, 0.02), square_blob(0.05, 0, 0.02)};
  EXPECT_EQ(learn_push_lack(crowded, 0, {-0.06, 0}, clearance), 0.0);
  EXPECT_EQ(learn_push_lack(crowded, 0, {0, -0.06}, clearance), 0.0);
  EXPECT_GT(learn_push_lack(crowded, 0, {0.03, 0}, clearance), 0.0);
  // The neighbour's own pushes are measured against the object the same way.
  EXPECT_GT(learn_push_lack(view, 1, {0.02, 0}, clearance), 0.0);
  EXPECT_THROW((void)learn_push_lack(view, 2, {0, 0}, clearance), InternalError);
}

TEST(SelfSupervision, PushMotionSaysWhichBlobsMoved) {
  // Two textured patches on a plain image; blob 0 over the left one, blob 1 over the right one.
  cv::Mat before(120, 200, CV_8UC1, cv::Scalar(128));
  cv::Mat tex(40, 40, CV_8UC1);
  cv::randu(tex, 0, 255);
  tex.copyTo(before(cv::Rect(20, 40, 40, 40)));
  tex.copyTo(before(cv::Rect(130, 40, 40, 40)));
  planning::PlanningView view;
  view.objects = {square_blob(0, 0, 0.02, cv::Rect(20, 40, 40, 40)),
                  square_blob(0.1, 0, 0.02, cv::Rect(130, 40, 40, 40))};
  // Nothing changed: nothing moved.
  PushMotion m = push_motion(before, before, view, 0.25);
  EXPECT_TRUE(m.moved.empty());
  EXPECT_EQ(m.most, -1);
  EXPECT_FALSE(m.alone(0));
  ASSERT_EQ(m.share.size(), 2U);
  // The left patch moved 12 px right: blob 0 alone.
  cv::Mat after(120, 200, CV_8UC1, cv::Scalar(128));
  tex.copyTo(after(cv::Rect(32, 40, 40, 40)));
  tex.copyTo(after(cv::Rect(130, 40, 40, 40)));
  m = push_motion(before, after, view, 0.25);
  EXPECT_EQ(m.moved, (std::vector<int>{0}));
  EXPECT_EQ(m.most, 0);
  EXPECT_TRUE(m.alone(0));
  EXPECT_FALSE(m.alone(1));
  EXPECT_GT(m.share[0], 0.5);
  EXPECT_LT(m.share[1], 0.25);
  // The right one moved too, but less (its lower half changed): both moved, blob 0 most.
  cv::Mat both = after.clone();
  cv::Mat part(10, 40, CV_8UC1);
  cv::randu(part, 0, 255);
  part.copyTo(both(cv::Rect(130, 70, 40, 10)));
  part.copyTo(both(cv::Rect(130, 60, 40, 10)));
  m = push_motion(before, both, view, 0.25);
  EXPECT_EQ(m.moved, (std::vector<int>{0, 1}));
  EXPECT_EQ(m.most, 0);
  EXPECT_FALSE(m.alone(0));
  // Only the right one moved: blob 1 moved most (a push of blob 0 that drifted).
  cv::Mat other = before.clone();
  tex.copyTo(other(cv::Rect(142, 40, 40, 40)));
  m = push_motion(before, other, view, 0.25);
  EXPECT_EQ(m.most, 1);
  EXPECT_TRUE(m.alone(1));
  // Both moved as much (shares saturate): the pushed blob is the one that moved most (two
  // moving, not a drift); with no pushed blob given, the first.
  cv::Mat twice = after.clone();
  twice(cv::Rect(130, 40, 40, 40)).setTo(128);
  tex.copyTo(twice(cv::Rect(142, 40, 40, 40)));
  m = push_motion(before, twice, view, 0.25, 1);
  EXPECT_EQ(m.moved, (std::vector<int>{0, 1}));
  EXPECT_EQ(m.most, 1);
  EXPECT_EQ(push_motion(before, twice, view, 0.25).most, 0);
  // The pushed blob moved clearly less than another: that one moved most.
  EXPECT_EQ(push_motion(before, both, view, 0.25, 1).most, 0);
  // A higher threshold than any share: nothing counts.
  EXPECT_TRUE(push_motion(before, after, view, 1.01).moved.empty());
}

// The pixel rectangle of the table square of half side h at c (test::down_camera: image x =
// world x, image y = -world y).
cv::Rect square_px(const geometry::Camera& cam, const Eigen::Vector2d& c, double h) {
  const Eigen::Vector2d a = cam.project(Eigen::Vector3d(c.x() - h, c.y() + h, 0));
  const Eigen::Vector2d b = cam.project(Eigen::Vector3d(c.x() + h, c.y() - h, 0));
  return {cv::Point(static_cast<int>(a.x()), static_cast<int>(a.y())),
          cv::Point(static_cast<int>(b.x()), static_cast<int>(b.y()))};
}

TEST(SelfSupervision, EpisodeMotionSplitsTheBlobAndSeesTheNeighbourMove) {
  // Two textured squares 5 mm apart (one blob to the looks) and a third apart, seen from above.
  // The push moves the first 3 cm along +x; the neighbour is nudged 1 cm along -y in case 2.
  const geometry::Camera cam = test::down_camera();
  planning::PushPlanOptions po;
  po.centre_height = 0.0;  // the squares lie on the table
  const planning::TableRegion region;
  const double h = 0.03;
  const Eigen::Vector2d a(0.20, 0.0);
  const Eigen::Vector2d b(0.20, -0.065);
  const Eigen::Vector2d c(0.34, 0.12);
  cv::Mat tex(square_px(cam, a, h).size() + cv::Size(1, 1), CV_8UC1);
  cv::theRNG().state = 7;
  cv::randu(tex, 0, 255);
  const auto draw = [&](cv::Mat& img, const Eigen::Vector2d& at) {
    const cv::Rect r = square_px(cam, at, h);
    tex(cv::Rect(0, 0, r.width, r.height)).copyTo(img(r));
  };
  cv::Mat first(cam.height, cam.width, CV_8UC1, cv::Scalar(128));
  draw(first, a);
  draw(first, b);
  draw(first, c);
  const Eigen::Vector2d a_end = a + Eigen::Vector2d(0.03, 0);
  cv::Mat last(cam.height, cam.width, CV_8UC1, cv::Scalar(128));
  draw(last, a_end);
  draw(last, b);
  draw(last, c);
  cv::Mat nudged(cam.height, cam.width, CV_8UC1, cv::Scalar(128));
  draw(nudged, a_end);
  draw(nudged, b - Eigen::Vector2d(0, 0.01));
  draw(nudged, c);
  const planning::PlanningView looked =
      planning::make_planning_view(planning::textured_points(first, po), cam, region, po);
  ASSERT_EQ(looked.objects.size(), 2U);  // the two near squares are one blob
  const int merged = looked.objects[0].centre.x() < 0.27 ? 0 : 1;
  // The push's motion segmentation: the first square at its touch; all it swept over the push.
  cv::Mat touch(cam.height, cam.width, CV_8U, cv::Scalar(0));
  touch(square_px(cam, a, h)).setTo(255);
  cv::Mat explained(cam.height, cam.width, CV_8U, cv::Scalar(0));
  explained(square_px(cam, a, h) | square_px(cam, a_end, h)).setTo(255);
  // Case 1: the neighbour stayed: the blob is split, the pushed square moved alone.
  planning::PlanningView view = looked;
  EpisodeMotion em =
      episode_motion(view, merged, touch, explained, first, last, 0.25, 10, region, po);
  ASSERT_EQ(view.objects.size(), 3U);
  ASSERT_GE(em.pushed, 0);
  EXPECT_NEAR(view.objects[static_cast<std::size_t>(em.pushed)].centre.x(), a.x(), 0.01);
  EXPECT_NEAR(view.objects[static_cast<std::size_t>(em.pushed)].centre.y(), a.y(), 0.01);
  EXPECT_TRUE(em.motion.alone(em.pushed));
  EXPECT_EQ(em.motion.most, em.pushed);
  // Case 2: the neighbour was nudged 1 cm. The looks' blobs cannot see it (one blob moved, the
  // pushed one: "alone"); the split view judged by what the push's own motion leaves
  // unexplained sees two objects move.
  EXPECT_TRUE(push_motion(first, nudged, looked, 0.25, merged).alone(merged));
  view = looked;
  em = episode_motion(view, merged, touch, explained, first, nudged, 0.25, 10, region, po);
  ASSERT_EQ(view.objects.size(), 3U);
  EXPECT_EQ(em.motion.most, em.pushed);
  EXPECT_FALSE(em.motion.alone(em.pushed));
  ASSERT_EQ(em.motion.moved.size(), 2U);
  const int other = em.motion.moved[0] == em.pushed ? em.motion.moved[1] : em.motion.moved[0];
  EXPECT_NEAR(view.objects[static_cast<std::size_t>(other)].centre.y(), b.y(), 0.01);
  // Without a touch mask the blob stays whole, the planned blob is the pushed one; a neighbour's
  // points all explained by the push's motion count as not moved.
  view = looked;
  cv::Mat all(cam.height, cam.width, CV_8U, cv::Scalar(255));
  em = episode_motion(view, merged, cv::Mat(), all, first, nudged, 0.25, 10, region, po);
  EXPECT_EQ(view.objects.size(), 2U);
  EXPECT_EQ(em.pushed, merged);
  EXPECT_TRUE(em.motion.alone(merged));
  view = looked;
  EXPECT_THROW((void)episode_motion(view, 2, touch, explained, first, last, 0.25, 10, region, po),
               InternalError);
  // The pushed object after the push: of the split parts the push's end mask holds (here both
  // near squares, swept together), the one nearest the push's target, not the larger share.
  view = looked;
  (void)episode_motion(view, merged, touch, explained, first, last, 0.25, 10, region, po);
  cv::Mat end(cam.height, cam.width, CV_8U, cv::Scalar(0));
  end(square_px(cam, a, h) | square_px(cam, b, h)).setTo(255);
  const int at_a = pushed_part(view, end, a + Eigen::Vector2d(0.01, 0), 10);
  const int at_b = pushed_part(view, end, b + Eigen::Vector2d(0.01, 0), 10);
  ASSERT_GE(at_a, 0);
  ASSERT_GE(at_b, 0);
  EXPECT_NEAR(view.objects[static_cast<std::size_t>(at_a)].centre.y(), a.y(), 0.01);
  EXPECT_NEAR(view.objects[static_cast<std::size_t>(at_b)].centre.y(), b.y(), 0.01);
  // The third square is nearest a target by it, but the mask does not hold it; an empty mask
  // holds none.
  const int at_c = pushed_part(view, end, c, 10);
  EXPECT_TRUE(at_c == at_a || at_c == at_b);
  EXPECT_EQ(pushed_part(view, cv::Mat(cam.height, cam.width, CV_8U, cv::Scalar(0)), a, 10), -1);
  EXPECT_THROW((void)pushed_part(view, cv::Mat(10, 10, CV_8U), a, 10), InternalError);
}

TEST(SelfSupervision, MergedBlobIsSplitInTwoWhenFewerBlobsThanObjects) {
  // Two touching textured squares 5 mm apart (one blob to the looks), one reddish and one
  // bluish, and a third square apart: C = 3 objects, 2 blobs seen. The merged blob is split
  // into the two squares (k-means on positions and colours); with C = 2 nothing is split.
  const geometry::Camera cam = test::down_camera();
  planning::PushPlanOptions po;
  po.centre_height = 0.0;  // the squares lie on the table
  const planning::TableRegion region;
  const double h = 0.03;
  const Eigen::Vector2d a(0.20, 0.0);
  const Eigen::Vector2d b(0.20, -0.065);
  const Eigen::Vector2d c(0.34, 0.12);
  const cv::Size size = square_px(cam, a, h).size() + cv::Size(1, 1);
  cv::Mat grey(size, CV_8UC1);
  cv::theRNG().state = 7;
  cv::randu(grey, 0, 255);
  const auto tinted = [&](const cv::Scalar& tint) {
    cv::Mat g3;
    cv::cvtColor(grey, g3, cv::COLOR_GRAY2BGR);
    cv::Mat out;
    cv::multiply(g3, tint, out, 1.0 / 255);
    return out;
  };
  const auto draw = [&](cv::Mat& img, const Eigen::Vector2d& at, const cv::Mat& tex) {
    const cv::Rect r = square_px(cam, at, h);
    tex(cv::Rect(0, 0, r.width, r.height)).copyTo(img(r));
  };
  cv::Mat img(cam.height, cam.width, CV_8UC3, cv::Scalar(128, 128, 128));
  draw(img, a, tinted({60, 60, 255}));  // reddish (BGR)
  draw(img, b, tinted({255, 80, 60}));  // bluish
  draw(img, c, tinted({60, 255, 60}));
  cv::Mat gray;
  cv::cvtColor(img, gray, cv::COLOR_BGR2GRAY);
  const planning::PlanningView looked =
      planning::make_planning_view(planning::textured_points(gray, po), cam, region, po);
  ASSERT_EQ(looked.objects.size(), 2U);  // the two near squares are one blob
  const int merged = looked.objects[0].centre.x() < 0.27 ? 0 : 1;
  for (const double colour : {1.0, 0.0}) {
    SCOPED_TRACE(colour);
    planning::PlanningView view = looked;
    const std::vector<int> split = split_merged_blobs(view, img, 3, 10, colour, region, po);
    ASSERT_EQ(split, std::vector<int>{merged});
    ASSERT_EQ(view.objects.size(), 3U);
    // The two parts are the two squares: one centre at each, each with its own points only.
    std::vector<Eigen::Vector2d> centres;
    for (const auto& o : view.objects) {
      if (o.centre.x() < 0.27) centres.push_back(o.centre);
    }
    ASSERT_EQ(centres.size(), 2U);
    if (centres[0].y() < centres[1].y()) std::swap(centres[0], centres[1]);
    EXPECT_NEAR(centres[0].x(), a.x(), 0.005);
    EXPECT_NEAR(centres[0].y(), a.y(), 0.005);
    EXPECT_NEAR(centres[1].x(), b.x(), 0.005);
    EXPECT_NEAR(centres[1].y(), b.y(), 0.005);
    std::size_t points = 0;
    for (const auto& o : view.objects) points += o.pixels.size();
    std::size_t before = 0;
    for (const auto& o : looked.objects) before += o.pixels.size();
    EXPECT_EQ(points, before);  // no feature point lost or counted twice
  }
  // As many blobs as objects: nothing split. Too few points for two parts: left as it was.
  planning::PlanningView view = looked;
  EXPECT_TRUE(split_merged_blobs(view, img, 2, 10, 1.0, region, po).empty());
  EXPECT_EQ(view.objects.size(), 2U);
  EXPECT_TRUE(split_merged_blobs(view, img, 3, 100000, 1.0, region, po).empty());
  EXPECT_EQ(view.objects.size(), 2U);
  // Bad input: a grey image, an image of another size, no classes, a negative weight.
  EXPECT_THROW((void)split_merged_blobs(view, gray, 3, 10, 1.0, region, po), Error);
  EXPECT_THROW(
      (void)split_merged_blobs(view, img(cv::Rect(0, 0, 10, 10)).clone(), 3, 10, 1.0, region, po),
      Error);
  EXPECT_THROW((void)split_merged_blobs(view, img, 0, 10, 1.0, region, po), Error);
  EXPECT_THROW((void)split_merged_blobs(view, img, 3, 10, -1.0, region, po), Error);
  EXPECT_FALSE(SelfSupervisionOptions{}.split_merged);  // off unless measured better
  EXPECT_EQ(SelfSupervisionOptions{}.singulate_tries, 0);
}

TEST(SelfSupervision, FallbackGoalsGoInwardWhenAsked) {
  // The object 16 cm out from the work centre along +x; its first goal was outward (a0 = 0).
  const Eigen::Vector2d centre(0.24, 0.0);
  const Eigen::Vector2d chosen(0.40, 0.0);
  const double length = 0.08;
  // Off: the other seven sides in turn, an eighth of a turn apart, the first at 45 degrees.
  const std::vector<Eigen::Vector2d> all =
      fallback_goals(chosen, centre, 0.0, length, 8, 0.07, false);
  ASSERT_EQ(all.size(), 7U);
  EXPECT_NEAR(all[0].x(), 0.40 + length * std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(all[0].y(), length * std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(all[3].x(), 0.32, 1e-12);  // k = 4: straight back toward the centre
  // On: toward the centre first (straight back), nearest first; none ends farther out than the
  // object is now (45 degrees off outward, 90 degrees off, ... are left out).
  const std::vector<Eigen::Vector2d> in =
      fallback_goals(chosen, centre, 0.0, length, 8, 0.07, true);
  ASSERT_FALSE(in.empty());
  EXPECT_LT(in.size(), all.size());
  EXPECT_NEAR(in[0].x(), 0.32, 1e-12);
  EXPECT_NEAR(in[0].y(), 0.0, 1e-12);
  for (std::size_t k = 0; k < in.size(); ++k) {
    EXPECT_LE((in[k] - centre).norm(), (chosen - centre).norm() + 1e-12);
    if (k > 0) {
      EXPECT_GE((in[k] - centre).norm(), (in[k - 1] - centre).norm());
    }
  }
  // Within the circle of targets any side is allowed (sorted still).
  EXPECT_EQ(fallback_goals(centre, centre, 0.0, 0.05, 8, 0.07, true).size(), 7U);
  EXPECT_FALSE(SelfSupervisionOptions{}.inward_sides);  // off unless measured better
  EXPECT_THROW((void)fallback_goals(chosen, centre, 0.0, 0.0, 8, 0.07, true), InternalError);
}

TEST(SelfSupervision, FreeSpotsAreTheRoomTheOthersLeave) {
  // The chosen object (blob 0, a 4 cm square) 2 cm from a neighbour to its right; a third blob
  // far up. The work centre at the origin, spots within 10 cm of it on a 2 cm grid.
  planning::PlanningView view;
  view.objects = {square_blob(0.0, 0.0, 0.02), square_blob(0.06, 0.0, 0.02),
                  square_blob(0.0, 0.3, 0.02)};
  const std::vector<FreeSpot> spots = free_spots(view, 0, {0, 0}, 0.10, 1.0, 0.02);
  ASSERT_FALSE(spots.empty());
  // Best first; every spot within the radius; its gap the carried hull's least hull_gap.
  for (std::size_t k = 0; k < spots.size(); ++k) {
    EXPECT_LE(spots[k].point.norm(), 0.10 + 1e-12);
    if (k > 0) {
      EXPECT_LE(spots[k].gap, spots[k - 1].gap + 0.001);
    }
  }
  // The best: the disc's point farthest from the neighbour beside it, (-0.10, 0), with 12 cm of
  // room (the far blob is 26 cm above it).
  EXPECT_NEAR(spots[0].point.x(), -0.10, 1e-12);
  EXPECT_NEAR(spots[0].point.y(), 0.0, 1e-12);
  EXPECT_NEAR(spots[0].gap, 0.12, 1e-9);
  const std::vector<Eigen::Vector2d> moved = {
      spots[0].point + Eigen::Vector2d(-0.02, -0.02), spots[0].point + Eigen::Vector2d(0.02, -0.02),
      spots[0].point + Eigen::Vector2d(0.02, 0.02), spots[0].point + Eigen::Vector2d(-0.02, 0.02)};
  EXPECT_NEAR(
      spots[0].gap,
      std::min(hull_gap(moved, view.objects[1].hull), hull_gap(moved, view.objects[2].hull)),
      1e-12);
  // Its own place (on the grid): the 2 cm it has.
  bool own = false;
  for (const FreeSpot& f : spots) {
    if (f.point.norm() < 1e-12) {
      own = true;
      EXPECT_NEAR(f.gap, 0.02, 1e-9);
    }
  }
  EXPECT_TRUE(own);
  // Within `reach` of the blob only: 3 cm leaves the 9 points of the grid about it.
  const std::vector<FreeSpot> near = free_spots(view, 0, {0, 0}, 0.10, 0.03, 0.02);
  EXPECT_EQ(near.size(), 9U);
  for (const FreeSpot& f : near) EXPECT_LE(f.point.norm(), 0.03 + 1e-12);
  EXPECT_LT(near[0].point.x(), 0.0);  // away from the neighbour
  // Alone: its own place, infinite room.
  planning::PlanningView alone;
  alone.objects = {square_blob(0.05, 0.0, 0.02)};
  const std::vector<FreeSpot> a = free_spots(alone, 0, {0, 0}, 0.10, 1.0, 0.02);
  ASSERT_EQ(a.size(), 1U);
  EXPECT_EQ(a[0].point, Eigen::Vector2d(0.05, 0.0));
  EXPECT_TRUE(std::isinf(a[0].gap));
  EXPECT_THROW((void)free_spots(view, 3, {0, 0}, 0.1, 1.0, 0.02), InternalError);
  EXPECT_THROW((void)free_spots(view, 0, {0, 0}, 0.1, 1.0, 0.0), InternalError);
  EXPECT_EQ(SelfSupervisionOptions{}.free_space, 0.0);  // off unless measured better
}

TEST(SelfSupervision, MergedBlobHoldsAnotherBlobsCentre) {
  planning::PlanningView before;
  before.objects = {square_blob(0, 0, 0.02), square_blob(0.08, 0, 0.02), square_blob(0, 0.2, 0.02)};
  // After the push the object (blob 0) was carried to the neighbour: one blob over both.
  planning::PlanningView after;
  after.objects = {square_blob(0, 0.2, 0.02)};
  planning::PutativeObject both;
  both.centre = Eigen::Vector2d(0.06, 0);
  both.hull = {{0.03, -0.02}, {0.10, -0.02}, {0.10, 0.02}, {0.03, 0.02}};
  after.objects.push_back(both);
  EXPECT_EQ(merged_blob(before, 0, after, 1), 1);
  // Its own centre does not count, nor a blob that stayed apart.
  EXPECT_EQ(merged_blob(before, 1, after, 1), -1);
  EXPECT_EQ(merged_blob(before, 0, after, 0), 2);  // the blob at blob 2's place holds it
  EXPECT_EQ(merged_blob(before, 2, after, 0), -1);
  // The object alone, moved: no merge; no blob (-1) or a bad index: none.
  planning::PlanningView moved;
  moved.objects = {square_blob(0.03, 0, 0.02)};
  EXPECT_EQ(merged_blob(before, 0, moved, 0), -1);
  EXPECT_EQ(merged_blob(before, 0, moved, -1), -1);
  EXPECT_EQ(merged_blob(before, 0, moved, 3), -1);
}

TEST(SelfSupervision, MergedByGrowthWhenTheObjectsBlobGrowsAndBlobsFall) {
  // A blob of n feature points (their positions do not matter to the test).
  const auto blob = [](int n) {
    planning::PutativeObject o;
    o.pixels.assign(static_cast<std::size_t>(n), Eigen::Vector2d(10, 10));
    return o;
  };
  planning::PlanningView before;
  before.objects = {blob(100), blob(80), blob(60)};
  // The push carried the object (blob 0, 100 points) into its neighbour: two blobs left, the
  // object's blob of 180 points.
  planning::PlanningView after;
  after.objects = {blob(60), blob(180)};
  EXPECT_TRUE(merged_by_growth(before, 0, after, 1, 1.5));
  EXPECT_TRUE(merged_by_growth(before, 0, after, 1, 1.8));  // at the ratio exactly
  EXPECT_FALSE(merged_by_growth(before, 0, after, 1, 1.9));
  // The object alone, turned (more points) but as many blobs: no merge.
  planning::PlanningView turned;
  turned.objects = {blob(180), blob(80), blob(60)};
  EXPECT_FALSE(merged_by_growth(before, 0, turned, 0, 1.5));
  // Fewer blobs (a neighbour pushed off the table) but the object's blob no larger: no merge.
  planning::PlanningView left;
  left.objects = {blob(105), blob(80)};
  EXPECT_FALSE(merged_by_growth(before, 0, left, 0, 1.5));
  // No blob found (-1), bad indices, an empty blob before: none.
  EXPECT_FALSE(merged_by_growth(before, 0, after, -1, 1.5));
  EXPECT_FALSE(merged_by_growth(before, 0, after, 2, 1.5));
  EXPECT_FALSE(merged_by_growth(before, 5, after, 1, 1.5));
  planning::PlanningView empty_before;
  empty_before.objects = {blob(0), blob(80), blob(60)};
  EXPECT_FALSE(merged_by_growth(empty_before, 0, after, 1, 1.5));
  // A ratio of 1 or less (or not finite) is not a growth.
  EXPECT_THROW((void)merged_by_growth(before, 0, after, 1, 1.0), Error);
  EXPECT_THROW((void)merged_by_growth(before, 0, after, 1, std::nan("")), Error);
  // The option: off by default; 0 or above 1.
  EXPECT_EQ(SelfSupervisionOptions{}.merge_ratio, 0.0);
  SelfSupervisionOptions o;
  o.merge_ratio = 0.5;
  EXPECT_THROW(o.validate(), Error);
  o.merge_ratio = 1.5;
  EXPECT_NO_THROW(o.validate());
}

// arm_patches_out: a feature whose patch reaches the arm's own image is left out, so the
// object's document does not depend on what the arm beside it looks like (session 28: in the
// push frames the patches on the object's outline described the arm's texture).
TEST(SelfSupervision, ArmPatchesOutLeavesTheArmOutOfTheObjectsDocument) {
  cv::Mat table(120, 160, CV_8UC3, cv::Scalar(120, 130, 140));
  cv::RNG rng(7);
  const cv::Rect object(40, 30, 40, 50);
  const cv::Rect arm_box(82, 10, 40, 100);  // beside the object, 2 px off its outline
  cv::Mat with_arm = table.clone();
  cv::Mat patch(object.size(), CV_8UC3);
  rng.fill(patch, cv::RNG::UNIFORM, 0, 255);
  patch.copyTo(with_arm(object));
  cv::Mat plain = with_arm.clone();  // the same object, no arm beside it
  cv::Mat stripes(arm_box.size(), CV_8UC3, cv::Scalar(20, 20, 20));
  for (int y = 0; y < stripes.rows; y += 6) {
    stripes.rowRange(y, std::min(y + 3, stripes.rows)).setTo(cv::Scalar(250, 250, 250));
  }
  stripes.copyTo(with_arm(arm_box));
  cv::Mat mask(table.size(), CV_8U, cv::Scalar(0));
  mask(object).setTo(255);
  cv::Mat arm(table.size(), CV_8U, cv::Scalar(0));
  arm(arm_box).setTo(255);
  features::DenseSiftOptions ds;
  ds.step = 4;
  features::KmeansOptions k;
  k.words = 16;
  k.threads = 1;
  const features::Vocabulary vocabulary =
      features::build_vocabulary(features::dense_sift(with_arm, ds).descriptors, k).vocabulary;
  features::ExtractOptions fo;
  fo.dense.step = 4;
  const auto sorted = [](std::vector<std::int32_t> d) {
    std::sort(d.begin(), d.end());
    return d;
  };
  // Without it the arm's stripes change the words of the patches on the object's right edge.
  const auto kept_arm = sorted(masked_document(with_arm, mask, vocabulary, fo, 4));
  const auto kept_plain = sorted(masked_document(plain, mask, vocabulary, fo, 4));
  EXPECT_EQ(kept_arm.size(), kept_plain.size());
  EXPECT_NE(kept_arm, kept_plain);
  // With it the documents with and without the arm are the same, and smaller.
  const auto out_arm = sorted(masked_document(with_arm, mask, vocabulary, fo, 4, arm));
  const auto out_plain = sorted(masked_document(plain, mask, vocabulary, fo, 4, arm));
  EXPECT_FALSE(out_arm.empty());
  EXPECT_LT(out_arm.size(), kept_arm.size());
  EXPECT_EQ(out_arm, out_plain);
  // The caller's mask is left as it was (it was grown by `dilate` at every call before).
  EXPECT_EQ(cv::countNonZero(mask), object.area());
  // An empty exclude mask is none; one of another size is an Error; the option is off.
  EXPECT_EQ(sorted(masked_document(with_arm, mask, vocabulary, fo, 4, cv::Mat())), kept_arm);
  EXPECT_THROW((void)masked_document(with_arm, mask, vocabulary, fo, 4,
                                     cv::Mat(10, 10, CV_8U, cv::Scalar(255))),
               Error);
  EXPECT_FALSE(SelfSupervisionOptions{}.arm_patches_out);
}

// Colour words (LearnOptions::colour_words, features::colour_words): a document is its SIFT
// words, then one colour word a feature numbered after the vocabulary's; the colour words of a
// textured red object are reds, of the same texture in blue blues.
TEST(SelfSupervision, ColourWordsFollowTheSiftWordsOfADocument) {
  cv::Mat1b texture(50, 40);
  cv::RNG rng(3);
  rng.fill(texture, cv::RNG::UNIFORM, 60, 200);
  const auto coloured = [&](int channel) {
    cv::Mat image(120, 160, CV_8UC3, cv::Scalar(120, 130, 140));
    std::vector<cv::Mat> planes(3, cv::Mat1b(texture.size(), uchar{0}));
    planes[static_cast<std::size_t>(channel)] = texture;
    cv::Mat object;
    cv::merge(planes, object);
    object.copyTo(image(cv::Rect(40, 30, 40, 50)));
    return image;
  };
  const cv::Mat red = coloured(2);
  const cv::Mat blue = coloured(0);
  cv::Mat mask(red.size(), CV_8U, cv::Scalar(0));
  mask(cv::Rect(44, 34, 32, 42)).setTo(255);  // inside the object (the patches too)
  features::ExtractOptions fo;
  fo.dense.step = 4;
  features::KmeansOptions k;
  k.words = 16;
  k.threads = 1;
  const features::Vocabulary vocabulary =
      features::build_vocabulary(features::dense_sift(red, fo.dense).descriptors, k).vocabulary;
  const features::ColourWordOptions colour;
  const int v = vocabulary.size();
  EXPECT_EQ(features::document_vocabulary_size(vocabulary, colour), v + 28);
  EXPECT_EQ(features::document_vocabulary_size(vocabulary, std::nullopt), v);
  const auto sift = masked_document(red, mask, vocabulary, fo, 0);
  const auto with_red = masked_document(red, mask, vocabulary, fo, 0, {}, colour);
  const auto with_blue = masked_document(blue, mask, vocabulary, fo, 0, {}, colour);
  const std::size_t n = sift.size();
  ASSERT_GT(n, 10U);
  ASSERT_EQ(with_red.size(), 2 * n);
  EXPECT_TRUE(std::equal(sift.begin(), sift.end(), with_red.begin()));
  ASSERT_EQ(with_blue.size(), 2 * n);
  for (std::size_t i = n; i < 2 * n; ++i) {
    // Red: hue bin 0 (or 11, just below 360 degrees); blue: bin 8 (240 degrees); vivid.
    EXPECT_TRUE(with_red[i] == v + 1 || with_red[i] == v + 23) << with_red[i] - v;
    EXPECT_EQ(with_blue[i], v + 8 * 2 + 1);
  }
  // Colour words only with the features: no features, no words.
  EXPECT_TRUE(
      masked_document(red, cv::Mat(red.size(), CV_8U, cv::Scalar(0)), vocabulary, fo, 0, {}, colour)
          .empty());
  // selfsupervise's own rungs make SIFT documents: colour words are refused with them.
  SelfSupervisionOptions o;
  o.colour_words = true;
  EXPECT_NO_THROW(o.validate());
  o.oracle_ladder = true;
  EXPECT_THROW(o.validate(), Error);
}

// A vocabulary and an LDA model (K = 3) made from the robot's first look: dense SIFT of the
// image, 24 words; documents are the words of 40 x 40 tiles.
struct TinyModel {
  features::Vocabulary vocabulary;
  topics::LdaModel lda;
};

// With `colour` the tiles' documents carry colour words (features::document_words): the model
// has the vocabulary's words + colour->count().
TinyModel tiny_model(const cv::Mat& image,
                     const std::optional<features::ColourWordOptions>& colour = std::nullopt) {
  features::DenseSiftOptions ds;
  ds.step = 4;
  const features::Features f = features::dense_sift(image, ds);
  features::KmeansOptions k;
  k.words = 24;
  k.threads = 1;
  TinyModel m{features::build_vocabulary(f.descriptors, k).vocabulary, {}};
  topics::Corpus corpus(features::document_vocabulary_size(m.vocabulary, colour));
  for (int ty = 0; ty < image.rows; ty += 40) {
    for (int tx = 0; tx < image.cols; tx += 40) {
      std::vector<int> rows;
      for (int i = 0; i < f.size(); ++i) {
        const cv::Point2f p = f.keypoints[static_cast<std::size_t>(i)].pt;
        if (p.x >= tx && p.x < tx + 40 && p.y >= ty && p.y < ty + 40) rows.push_back(i);
      }
      if (rows.empty()) continue;
      corpus.add_tokens(features::document_words(m.vocabulary, image,
                                                 features::select_features(f, rows), colour));
    }
  }
  topics::BatchLdaOptions lo;
  lo.num_topics = 3;
  lo.max_iterations = 20;
  m.lda = topics::train_batch_lda(corpus, lo).model;
  return m;
}

SelfSupervisionOptions small_options() {
  SelfSupervisionOptions o;
  o.objects = "book,bottle";
  o.pushes = 2;
  o.clear_pushes = 2;
  o.views = ViewSource::kBlob;
  o.min_features = 3;
  o.held_out = 4;
  o.width = 320;
  o.height = 240;
  o.features.dense.step = 4;
  o.seed = 2;
  return o;
}

sim::TableOptions table_of(const SelfSupervisionOptions& o) {
  sim::TableOptions t;
  t.objects = parse_object_list(o.objects);
  t.seed = o.seed;
  t.width = o.width;
  t.height = o.height;
  return t;
}

// A robot that sees and refuses: every push throws, as a real arm's driver would for a path it
// cannot follow; or, with `blind`, every look is a blank image.
class RefusingRobot final : public robot::Robot {
 public:
  RefusingRobot(sim::SimulatedRobot& inner, bool blind) : inner_(inner), blind_(blind) {}
  robot::Look look() override {
    robot::Look l = inner_.look();
    if (blind_) l.image.setTo(cv::Scalar(128, 128, 128));
    return l;
  }
  [[nodiscard]] geometry::Camera camera() const override { return inner_.camera(); }
  [[nodiscard]] const robot::Arm& arm() const override { return inner_.arm(); }
  [[nodiscard]] robot::JointVector joints() const override { return inner_.joints(); }
  void hold_still(double seconds) override { inner_.hold_still(seconds); }
  robot::PushReport push(const robot::TablePush& /*push*/,
                         const robot::PushRecording& /*recording*/) override {
    ++refused;
    throw Error("push: the arm's driver refused the path");
  }
  int refused = 0;

 private:
  sim::SimulatedRobot& inner_;
  bool blind_;
};

class CountingAttendant final : public TableAttendant {
 public:
  std::string rescatter(int round) override {
    ++rescatters;
    return "re-scatter " + std::to_string(round);
  }
  int rescatters = 0;
};

// Counts the choices it is told of (TableAttendant::chose).
class ChoiceCounter final : public TableAttendant {
 public:
  std::string rescatter(int round) override { return "re-scatter " + std::to_string(round); }
  void chose(int /*round*/, const planning::PlanningView& /*view*/, int /*blob*/) override {
    ++choices;
  }
  int choices = 0;
};

bool logged(const Learning& l, const std::string& fault) {
  for (const auto& j : l.log) {
    if (j.fault == fault) return true;
  }
  return false;
}

TEST(SelfSupervision, FaultsAreLoggedOutcomesNotCrashes) {
  const SelfSupervisionOptions o = small_options();
  const sim::ObjectCatalogue catalogue = sim::ObjectCatalogue::load_default();  // outlives it
  sim::SimulatedRobot sim_robot(table_of(o), catalogue);
  const TinyModel m = tiny_model(sim_robot.look().image);
  {
    RefusingRobot robot(sim_robot, false);
    CountingAttendant attendant;
    const Learning l = learn_by_pushing(robot, attendant, 2, m.lda, m.vocabulary, o, {});
    EXPECT_GT(robot.refused, 0);
    EXPECT_EQ(attendant.rescatters, 1);
    EXPECT_TRUE(logged(l, "robot-refused"));
    EXPECT_TRUE(l.views.labels.empty());  // no view without a push behind it
    EXPECT_EQ(l.model.num_classes(), 0);
    EXPECT_TRUE(logged(l, "class-dropped"));
    EXPECT_EQ(l.pushes_learn, 0);
  }
  {
    RefusingRobot robot(sim_robot, true);
    CountingAttendant attendant;
    const Learning l = learn_by_pushing(robot, attendant, 2, m.lda, m.vocabulary, o, {});
    EXPECT_TRUE(logged(l, "no-blobs"));
    EXPECT_EQ(robot.refused, 0);
    EXPECT_EQ(l.stop_reasons.at(0), "no blobs");
  }
  // Bad input: a vocabulary that is not the model's, no objects.
  CountingAttendant attendant;
  topics::LdaModel other = m.lda;
  other.lambda.conservativeResize(Eigen::NoChange, other.lambda.cols() + 1);
  other.lambda.rightCols(1).setOnes();
  EXPECT_THROW(learn_by_pushing(sim_robot, attendant, 2, other, m.vocabulary, o, {}), Error);
  EXPECT_THROW(learn_by_pushing(sim_robot, attendant, 0, m.lda, m.vocabulary, o, {}), Error);
}

// A document's tokens of words below `v` (SIFT words) and from `v` on (colour words): stored as
// (word, count).
std::pair<std::int64_t, std::int64_t> sift_and_colour_tokens(const topics::DocumentView& doc,
                                                             int v) {
  std::pair<std::int64_t, std::int64_t> n{0, 0};
  for (std::size_t i = 0; i < doc.size(); ++i) {
    (doc.words[i] < v ? n.first : n.second) += doc.counts[i];
  }
  return n;
}

// selfsupervise --colour-words: every document made with the given vocabulary (here the views')
// is its N features' SIFT words, then their N colour words numbered V + w (2N tokens); the model
// must have V + 28 words: a SIFT-only model is refused, as is a colour model without the flag.
TEST(SelfSupervision, ColourWordsRunNeedsAColourModelAndMakesColourDocuments) {
  SelfSupervisionOptions o = small_options();
  const sim::ObjectCatalogue catalogue = sim::ObjectCatalogue::load_default();  // outlives it
  sim::SimulatedRobot robot(table_of(o), catalogue);
  const cv::Mat first = robot.look().image;
  const features::ColourWordOptions grid;
  const TinyModel sift = tiny_model(first);
  const TinyModel coloured = tiny_model(first, grid);
  const int v = coloured.vocabulary.size();
  ASSERT_EQ(coloured.lda.num_words(), v + grid.count());
  EXPECT_FALSE(SelfSupervisionOptions{}.colour_words);
  {
    CountingAttendant attendant;
    o.colour_words = false;
    EXPECT_THROW(learn_by_pushing(robot, attendant, 2, coloured.lda, coloured.vocabulary, o, {}),
                 Error);
    o.colour_words = true;
    EXPECT_THROW(learn_by_pushing(robot, attendant, 2, sift.lda, sift.vocabulary, o, {}), Error);
  }
  o.colour_words = true;
  GroundTruthAttendant attendant(robot, o.seed);
  const Learning l =
      learn_by_pushing(robot, attendant, 2, coloured.lda, coloured.vocabulary, o, {});
  ASSERT_GT(l.views.words.num_documents(), 0U);
  EXPECT_EQ(l.views.words.num_words(), v + grid.count());
  // A document is stored as (word, count): N SIFT tokens (< V) and N colour tokens (>= V).
  for (std::size_t d = 0; d < l.views.words.num_documents(); ++d) {
    const auto [sift_tokens, colour_tokens] = sift_and_colour_tokens(l.views.words.document(d), v);
    EXPECT_GE(sift_tokens, o.min_features);
    EXPECT_EQ(colour_tokens, sift_tokens) << "document " << d;
  }
}

// learn_by_pushing of 2 classes on the simulated table of `o` (the tiny model made from its
// first look; the attendant kept for scoring). `masks`: the table records the ground-truth masks
// (the oracle ladder's).
struct TableRun {
  std::optional<TinyModel> tiny;
  Learning l;
  std::unique_ptr<GroundTruthAttendant> attendant;
};

TableRun learn_on_table(const SelfSupervisionOptions& o, const std::filesystem::path& dir,
                        bool masks) {
  TableRun r;
  const sim::ObjectCatalogue catalogue = sim::ObjectCatalogue::load_default();  // outlives it
  sim::TableOptions t = table_of(o);
  t.record_masks = masks;
  sim::SimulatedRobot robot(t, catalogue);
  r.tiny = tiny_model(robot.look().image, o.document_colour());  // colour_words: V + 28 words
  r.attendant = std::make_unique<GroundTruthAttendant>(robot, o.seed);
  r.l = learn_by_pushing(robot, *r.attendant, 2, r.tiny->lda, r.tiny->vocabulary, o, dir);
  return r;
}

// A model made with weighted colour words (recognize train --colour-weight 8: its word weights
// count each colour word 8 times): the views' documents still count each once (the colour
// classifier reads them so), and their theta is the model's reading of them weighted.
TEST(SelfSupervision, AModelWithWordWeightsWeighsTheViewsTheta) {
  SelfSupervisionOptions o = small_options();
  o.colour_words = true;
  const sim::ObjectCatalogue catalogue = sim::ObjectCatalogue::load_default();  // outlives it
  sim::SimulatedRobot robot(table_of(o), catalogue);
  TinyModel tiny = tiny_model(robot.look().image, o.document_colour());
  const int v = tiny.vocabulary.size();
  topics::LdaModel weighted = tiny.lda;
  weighted.word_weights = topics::weights_from(weighted.num_words(), v, 8);
  GroundTruthAttendant attendant(robot, o.seed);
  const Learning l = learn_by_pushing(robot, attendant, 2, weighted, tiny.vocabulary, o, {});
  ASSERT_GT(l.views.words.num_documents(), 0U);
  ASSERT_EQ(static_cast<std::size_t>(l.views.theta.rows()), l.views.words.num_documents());
  for (std::size_t d = 0; d < l.views.words.num_documents(); ++d) {
    const auto [sift_tokens, colour_tokens] = sift_and_colour_tokens(l.views.words.document(d), v);
    EXPECT_EQ(colour_tokens, sift_tokens) << "document " << d;
  }
  const Eigen::MatrixXd by_hand =
      recognition::document_theta(tiny.lda, topics::weighted_from(l.views.words, v, 8)).theta;
  const Eigen::MatrixXd once = recognition::document_theta(tiny.lda, l.views.words).theta;
  EXPECT_LT((l.views.theta - by_hand).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_GT((l.views.theta - once).cwiseAbs().maxCoeff(), 1e-3);
}

// With colour words c is also scored by the colour words alone (classify_by_colour), on the same
// held-out views and classes as the theta figure; mot_classifier colour makes it c itself.
TEST(SelfSupervision, ColourWordsScoreCAlsoByTheColourWordsAlone) {
  SelfSupervisionOptions o = small_options();
  o.colour_words = true;
  TableRun run = learn_on_table(o, {}, false);
  const Learning& l = run.l;
  ASSERT_GT(l.model.num_classes(), 0);
  const std::vector<std::string> objects{"book", "bottle"};
  const SelfSupervisionScore s =
      score_self_supervision(l, *run.attendant, objects, run.tiny->lda, run.tiny->vocabulary, o);
  ASSERT_TRUE(s.colour_accuracy.has_value());
  int right = 0;
  int all = 0;
  for (const ObjectScore& os : s.objects) {
    ASSERT_TRUE(os.colour_accuracy.has_value()) << os.name;
    EXPECT_GE(*os.colour_accuracy, 0.0);
    EXPECT_LE(*os.colour_accuracy, 1.0);
    right += static_cast<int>(std::lround(*os.colour_accuracy * os.held_out));
    all += os.held_out;
  }
  ASSERT_GT(all, 0);
  EXPECT_DOUBLE_EQ(*s.colour_accuracy, static_cast<double>(right) / all);
  const core::Json j = core::fields_to_json(s);
  EXPECT_EQ(j["colour_accuracy"].get<double>(), *s.colour_accuracy);
  EXPECT_EQ(j["objects"][0]["colour_accuracy"].get<double>(), *s.objects[0].colour_accuracy);
  // mot_classifier colour: c (and its confusion) by the colour words; theta's argmax unchanged.
  SelfSupervisionOptions q = o;
  q.mot_classifier = MotClassifier::kColour;
  const SelfSupervisionScore c =
      score_self_supervision(l, *run.attendant, objects, run.tiny->lda, run.tiny->vocabulary, q);
  EXPECT_DOUBLE_EQ(c.mot_accuracy, *s.colour_accuracy);
  EXPECT_DOUBLE_EQ(*c.colour_accuracy, *s.colour_accuracy);
  EXPECT_DOUBLE_EQ(c.argmax_accuracy, s.argmax_accuracy);
  for (std::size_t oi = 0; oi < objects.size(); ++oi) {
    EXPECT_DOUBLE_EQ(c.objects[oi].mot_accuracy, *s.objects[oi].colour_accuracy) << oi;
  }
  int diagonal = 0;  // the confusion's cells of each object's own classes
  for (std::size_t oi = 0; oi < objects.size(); ++oi) {
    for (std::size_t m = 0; m < c.mot.columns.size(); ++m) {
      if (c.mot.columns[m].find("(" + objects[oi] + ")") != std::string::npos) {
        diagonal += c.mot.counts[oi][m];
      }
    }
  }
  EXPECT_EQ(diagonal, right);
  // A learning without its views' words (learn's scoring keeps none): no colour figure, and
  // c by colour cannot be scored.
  Learning bare = l;
  bare.views.words = topics::Corpus(l.views.words.num_words());
  const SelfSupervisionScore b =
      score_self_supervision(bare, *run.attendant, objects, run.tiny->lda, run.tiny->vocabulary, o);
  EXPECT_FALSE(b.colour_accuracy.has_value());
  EXPECT_FALSE(b.objects[0].colour_accuracy.has_value());
  EXPECT_DOUBLE_EQ(b.mot_accuracy, s.mot_accuracy);
  EXPECT_THROW((void)score_self_supervision(bare, *run.attendant, objects, run.tiny->lda,
                                            run.tiny->vocabulary, q),
               Error);
  // validate(): colour needs colour words.
  EXPECT_NO_THROW(q.validate());
  q.colour_words = false;
  EXPECT_THROW(q.validate(), Error);
}

// recheck_tries on the simulated table: after (b) of every round with a learned class the chosen
// blob is checked again (event "recheck", with each blob's claim), and the round does what the
// check says: choose again (a "choose" before its next push) when a class claims the blob and
// another is unclaimed, otherwise the learn pushes start on it.
TEST(SelfSupervision, RecheckAfterClearingIsLoggedAndFollowed) {
  SelfSupervisionOptions o = small_options();
  o.recheck_tries = 2;
  TableRun run = learn_on_table(o, {}, false);
  const Learning& l = run.l;
  EXPECT_EQ(l.classes, 2);
  int rechecks = 0;
  for (std::size_t i = 0; i < l.log.size(); ++i) {
    const auto& j = l.log[i];
    if (j.event != "recheck") continue;
    ++rechecks;
    ASSERT_TRUE(j.round && j.blob && j.scores && j.why);
    EXPECT_GE(*j.round, 1) << "round 1 has no learned class to claim anything";
    // The event's claims are choose_unlearned's: at most one blob a class.
    NextChoice cl;
    std::vector<int> claimed;
    for (const BlobScore& b : *j.scores) {
      ASSERT_TRUE(b.claimed_by && b.nearest);
      cl.claimed_by.push_back(*b.claimed_by);
      cl.nearest.push_back(*b.nearest);
      if (*b.claimed_by >= 0) claimed.push_back(*b.claimed_by);
    }
    std::sort(claimed.begin(), claimed.end());
    EXPECT_EQ(std::adjacent_find(claimed.begin(), claimed.end()), claimed.end());
    // The choice the claims give: the unclaimed scored blob farthest from the classes.
    double far = -1;
    for (std::size_t b = 0; b < cl.claimed_by.size(); ++b) {
      if (cl.claimed_by[b] < 0 && cl.nearest[b] >= 0 && cl.nearest[b] > far) {
        far = cl.nearest[b];
        cl.blob = static_cast<int>(b);
      }
    }
    const bool again = recheck_claimed(cl, *j.blob);
    EXPECT_EQ(j.why->find("choosing again") != std::string::npos, again) << *j.why;
    // What follows in the round: a new choice, or the learn pushes.
    std::string next;
    for (std::size_t k = i + 1; k < l.log.size() && next.empty(); ++k) {
      const auto& e = l.log[k];
      if (e.round != j.round) break;
      if (e.event == "choose") next = "choose";
      if (e.event == "push" || e.event == "plan") next = e.phase.value_or("");
    }
    if (again) {
      EXPECT_EQ(next, "choose");
    } else if (!next.empty()) {
      EXPECT_EQ(next, "learn");
    }
  }
  EXPECT_GE(rechecks, 1);
  // Off (the default): no recheck.
  TableRun off = learn_on_table(small_options(), {}, false);
  EXPECT_TRUE(std::none_of(off.l.log.begin(), off.l.log.end(),
                           [](const auto& j) { return j.event == "recheck"; }));
}

// claims_by view-words on the simulated table (with recheck_tries, whose claims are the same):
// every scored choice after round 1 is by the classes' views' words, one blob a class, with the
// looks' claims beside it; the rechecks choose again exactly when their claims say so.
TEST(SelfSupervision, ClaimsByViewWordsOnTheTableAreLoggedAndFollowed) {
  SelfSupervisionOptions o = small_options();
  o.claims_by = ClaimSignal::kViewWords;
  o.other_claims_by = ClaimSignal::kLooks;
  o.recheck_tries = 2;
  TableRun run = learn_on_table(o, {}, false);
  const Learning& l = run.l;
  ASSERT_GT(l.views.labels.size(), 0U);
  int scored = 0;
  int rechecks = 0;
  for (const auto& j : l.log) {
    if (j.event == "recheck") {
      ++rechecks;
      ASSERT_TRUE(j.scores && j.blob);
    }
    if (j.event != "choose" || !j.scores || !j.scores->front().claimed_by) continue;
    ++scored;
    ASSERT_TRUE(j.why);
    EXPECT_NE(j.why->find("views' words"), std::string::npos) << *j.why;
    std::vector<int> claimed;
    for (const BlobScore& b : *j.scores) {
      ASSERT_TRUE(b.claimed_by && b.nearest && b.other_claimed_by);
      // Only round 1's class has views here (2 objects): it claims at most one blob.
      if (*b.claimed_by >= 0) claimed.push_back(*b.claimed_by);
      EXPECT_TRUE(std::isfinite(*b.nearest));
    }
    EXPECT_LE(claimed.size(), 1U);
    for (const int c : claimed) {
      EXPECT_TRUE(std::find(l.views.labels.begin(), l.views.labels.end(), c) !=
                  l.views.labels.end())
          << "a class claims only with views";
    }
  }
  EXPECT_GE(scored, 1);
  EXPECT_GE(rechecks, 1);
}

// claims_by descriptors on the simulated table (session 36): every scored choice after round 1
// says "descriptors", a class claims at most one blob, only a class with looks claims, the
// looks' thetas' claims are logged beside (other_claims_by looks); without other_claims_by (the
// default) no other signal's claims are computed or logged.
TEST(SelfSupervision, ClaimsByDescriptorsOnTheTableAreLoggedAndFollowed) {
  SelfSupervisionOptions o = small_options();
  o.claims_by = ClaimSignal::kDescriptors;
  o.other_claims_by = ClaimSignal::kLooks;
  TableRun run = learn_on_table(o, {}, false);
  const Learning& l = run.l;
  ASSERT_GT(l.views.labels.size(), 0U);
  int scored = 0;
  for (const auto& j : l.log) {
    if (j.event != "choose" || !j.scores || !j.scores->front().claimed_by) continue;
    ++scored;
    ASSERT_TRUE(j.why);
    EXPECT_NE(j.why->find("descriptors"), std::string::npos) << *j.why;
    std::vector<int> claimed;
    for (const BlobScore& b : *j.scores) {
      ASSERT_TRUE(b.claimed_by && b.nearest && b.other_claimed_by);
      if (*b.claimed_by >= 0) {
        claimed.push_back(*b.claimed_by);
        EXPECT_LE(*b.nearest, -o.descriptor_min_share) << "a claim has its least share";
      }
      EXPECT_GE(*b.nearest, -1.0);
      EXPECT_LE(*b.nearest, 0.0);
    }
    EXPECT_LE(claimed.size(), 1U) << "2 objects: only round 1's class claims";
  }
  EXPECT_GE(scored, 1);
  // descriptor_source views: the classes' descriptors are their views'; only a class with views
  // claims, and the run differs from the looks' only in (d).
  o.descriptor_source = DescriptorSource::kViews;
  TableRun views = learn_on_table(o, {}, false);
  int by_views = 0;
  for (const auto& j : views.l.log) {
    if (j.event != "choose" || !j.scores || !j.scores->front().claimed_by) continue;
    ++by_views;
    EXPECT_NE(j.why->find("descriptors"), std::string::npos) << *j.why;
    for (const BlobScore& b : *j.scores) {
      if (*b.claimed_by < 0) continue;
      EXPECT_TRUE(std::find(views.l.views.labels.begin(), views.l.views.labels.end(),
                            *b.claimed_by) != views.l.views.labels.end())
          << "a class claims only with views";
    }
  }
  EXPECT_GE(by_views, 1);
  // The default: no comparison computed.
  TableRun def = learn_on_table(small_options(), {}, false);
  for (const auto& j : def.l.log) {
    if (j.event != "choose" || !j.scores) continue;
    for (const BlobScore& b : *j.scores) EXPECT_FALSE(b.other_claimed_by.has_value());
  }
}

// claims_by colour on the simulated table (session 41): every scored choice after round 1 says
// "pixel colours", a Hellinger distance in [0, 1]; the book and the bottle differ in colour, so
// round 1's class claims the blob of the object round 1 learned (the ground truth), and round 2
// chooses the other; the looks' thetas' claims are logged beside.
TEST(SelfSupervision, ClaimsByColourClaimTheObjectTheClassLearned) {
  SelfSupervisionOptions o = small_options();
  o.claims_by = ClaimSignal::kColour;
  o.other_claims_by = ClaimSignal::kLooks;
  // Seed 3: round 2's look shows both objects apart (at seeds 1 and 5 one blob holds both or
  // one has too few features, and then any claim is forced).
  o.seed = 3;
  TableRun run = learn_on_table(o, {}, false);
  const auto& truth = run.attendant->rounds();
  ASSERT_EQ(truth.size(), 2U);
  ASSERT_FALSE(truth[0].chosen.empty());
  int scored = 0;
  for (const auto& j : run.l.log) {
    if (j.event != "choose" || !j.scores || !j.scores->front().claimed_by) continue;
    ++scored;
    ASSERT_EQ(j.round.value_or(-1), 1);
    ASSERT_TRUE(j.why && j.blob);
    EXPECT_NE(j.why->find("pixel colours"), std::string::npos) << *j.why;
    int claims = 0;
    for (const BlobScore& b : *j.scores) {
      ASSERT_TRUE(b.claimed_by && b.nearest && b.other_claimed_by);
      EXPECT_GE(*b.nearest, 0.0);
      EXPECT_LE(*b.nearest, 1.0);
      if (*b.claimed_by < 0) continue;
      ++claims;
      EXPECT_EQ(*b.claimed_by, 0);
      EXPECT_EQ(truth[1].blobs[static_cast<std::size_t>(b.blob)], truth[0].chosen);
    }
    EXPECT_EQ(claims, 1);
    EXPECT_NE(truth[1].blobs[static_cast<std::size_t>(*j.blob)], truth[0].chosen);
  }
  EXPECT_EQ(scored, 1);
  EXPECT_NE(truth[1].chosen, truth[0].chosen);
  // By the looks' thetas: the same first round.
  o.claims_by = ClaimSignal::kLooks;
  o.other_claims_by = ClaimSignal::kNone;
  TableRun looks = learn_on_table(o, {}, false);
  EXPECT_EQ(looks.attendant->rounds()[0].chosen, truth[0].chosen);
  o.other_claims_by = ClaimSignal::kColour;
  EXPECT_NO_THROW(o.validate());
  o.colour.hue_bins = 0;
  EXPECT_THROW(o.validate(), Error);
}

// colour_first_look (session 43): a round's colours come from its first look (the object after
// (b)) only. The same seed makes the same first round either way (claims act from round 2 on);
// its first-look counts are within its all-looks counts and fewer, as the round looked again
// before each later learn push. Without claims by colour or refind_colour it is refused.
TEST(SelfSupervision, ColourFirstLookKeepsOnlyTheRoundsFirstLooksColours) {
  SelfSupervisionOptions o = small_options();
  o.claims_by = ClaimSignal::kColour;
  o.seed = 3;
  const TableRun all = learn_on_table(o, {}, false);
  o.colour_first_look = true;
  const TableRun first = learn_on_table(o, {}, false);
  ASSERT_EQ(all.l.round_colours.size(), 2U);
  ASSERT_EQ(first.l.round_colours.size(), 2U);
  EXPECT_EQ(first.attendant->rounds()[0].chosen, all.attendant->rounds()[0].chosen);
  const Eigen::VectorXd& a = all.l.round_colours[0];
  const Eigen::VectorXd& f = first.l.round_colours[0];
  ASSERT_EQ(a.size(), f.size());
  EXPECT_GT(f.sum(), 0.0);
  EXPECT_LT(f.sum(), a.sum());
  EXPECT_TRUE(((a - f).array() >= 0).all());
  // Another claim signal and no refind_colour: nothing to choose the looks of.
  o.claims_by = ClaimSignal::kLooks;
  EXPECT_THROW(o.validate(), Error);
  o.refind_colour = 0.5;
  EXPECT_NO_THROW(o.validate());
  // Without claims by colour or refind_colour: no colours kept.
  o.colour_first_look = false;
  o.refind_colour = 0;
  EXPECT_TRUE(learn_on_table(o, {}, false).l.round_colours.empty());
}

// views both (session 41, learn's LearnViews::kBoth): each learn push that gave motion views
// also gives the look before it, cut out by the pushed blob, once a motion view: every "views"
// event of source both counts twice its push's motion views, and the ground truth names a view
// for each; round 1's pushes are the motion views' own.
TEST(SelfSupervision, ViewsBothAddTheLookBeforeEachPushWeighingAsMuch) {
  SelfSupervisionOptions o = small_options();
  const test::TempDir dir("proprio_selfsup_both_");
  std::map<ViewSource, TableRun> runs;
  for (const ViewSource v : {ViewSource::kMotion, ViewSource::kBoth}) {
    o.views = v;
    runs.emplace(v, learn_on_table(o, dir.path() / core::choice_name(v, kViewSourceNames), false));
  }
  const Learning& both = runs.at(ViewSource::kBoth).l;
  const Learning& motion = runs.at(ViewSource::kMotion).l;
  int pushes = 0;
  int views = 0;
  for (const auto& j : both.log) {
    if (j.event != "views" || !j.views || *j.views == 0) continue;
    ASSERT_TRUE(j.source);
    if (*j.source == "both") {
      ++pushes;
      EXPECT_EQ(*j.views % 2, 0);
    }
    views += *j.views;
  }
  EXPECT_GE(pushes, 1);
  EXPECT_EQ(static_cast<int>(both.views.labels.size()), views);
  EXPECT_EQ(runs.at(ViewSource::kBoth).attendant->views().size(), both.views.labels.size());
  // Round 1 pushed the same objects the same way: the same learn pushes, twice the views.
  const auto round0 = [](const Learning& l) {
    std::vector<std::string> out;
    for (const auto& j : l.log) {
      if (j.event == "push" && j.round.value_or(-1) == 0 && j.plan) out.push_back(j.plan->message);
    }
    return out;
  };
  EXPECT_EQ(round0(both), round0(motion));
  const auto of_round0 = [](const Learning& l) {
    return std::count(l.views.labels.begin(), l.views.labels.end(), 0);
  };
  EXPECT_EQ(of_round0(both), 2 * of_round0(motion));
}

TEST(SelfSupervision, LearnsOnTheSimulatedTableAndIsScored) {
  // With the geometry that keeps a round on its object (off by default: measured no better).
  SelfSupervisionOptions o = small_options();
  o.learn_clearance = 0.03;
  o.stop_on_drift = true;
  o.alone_views = true;
  TableRun run = learn_on_table(o, {}, false);
  const std::optional<TinyModel>& tiny = run.tiny;
  const Learning& l = run.l;
  const auto& attendant = run.attendant;
  const TinyModel& m = *tiny;
  EXPECT_EQ(l.classes, 2);
  EXPECT_EQ(l.class_names, (std::vector<std::string>{"object_1", "object_2"}));
  EXPECT_GT(l.pushes_learn, 0);
  EXPECT_EQ(attendant->rounds().size(), 2U);
  // Every view has a class and a theta row summing to 1.
  ASSERT_EQ(static_cast<std::size_t>(l.views.theta.rows()), l.views.labels.size());
  for (Eigen::Index d = 0; d < l.views.theta.rows(); ++d) {
    EXPECT_NEAR(l.views.theta.row(d).sum(), 1.0, 1e-6);
  }
  // The log has the choice, looks, pushes with their plans, and the end.
  int chooses = 0;
  int pushes = 0;
  for (const auto& j : l.log) {
    if (j.event == "choose") ++chooses;
    if (j.event == "push") {
      ++pushes;
      ASSERT_TRUE(j.plan.has_value());
      EXPECT_TRUE(core::fields_to_json(j).at("plan").contains("cost"));
    }
  }
  EXPECT_EQ(chooses, 2);
  EXPECT_EQ(pushes, l.pushes_clear + l.pushes_learn + (pushes - l.pushes_clear - l.pushes_learn));
  // Every executed learn push's motion is logged (which blobs moved); a push that moved another
  // blob most gives no views and stops its round (drift), one that moved two gives no views.
  int motions = 0;
  for (std::size_t i = 0; i < l.log.size(); ++i) {
    const auto& j = l.log[i];
    if (j.event != "motion") continue;
    ++motions;
    ASSERT_TRUE(j.shares && j.moved_most && j.blob && j.round);
    int moved = 0;
    for (const double sh : *j.shares) moved += sh >= o.moved_share ? 1 : 0;
    const bool drift = *j.moved_most >= 0 && *j.moved_most != *j.blob;
    const bool two = !drift && *j.moved_most == *j.blob && moved > 1;
    for (std::size_t k = i + 1; k < l.log.size(); ++k) {
      if (l.log[k].event != "views") continue;
      if (drift || two) {
        EXPECT_EQ(l.log[k].taken, 0);
      }
      break;
    }
    if (drift) {
      EXPECT_EQ(l.stop_reasons.at(static_cast<std::size_t>(*j.round)),
                "the push moved another object most");
    }
  }
  EXPECT_EQ(motions, l.pushes_learn);
  EXPECT_EQ(l.log.back().event, "end");

  const SelfSupervisionScore s =
      score_self_supervision(l, *attendant, {"book", "bottle"}, m.lda, m.vocabulary, o);
  EXPECT_EQ(s.objects.size(), 2U);
  EXPECT_GE(s.purity, 0.0);
  EXPECT_LE(s.purity, 1.0);
  EXPECT_GE(s.singulation, 0.0);
  EXPECT_LE(s.singulation, 1.0);
  for (const ObjectScore& os : s.objects) {
    if (l.model.num_classes() > 0) {
      EXPECT_EQ(os.held_out, o.held_out) << os.name;
    }
    EXPECT_GE(os.mot_accuracy, 0.0);
    EXPECT_LE(os.mot_accuracy, 1.0);
  }
  EXPECT_EQ(s.mot.total(), s.objects[0].held_out + s.objects[1].held_out);
  const core::Json j = core::fields_to_json(s);
  EXPECT_TRUE(j.contains("mot_confusion"));
  // Each executed learn push, intended>moved, per round.
  ASSERT_EQ(s.class_learn_pushes.size(), 2U);
  std::size_t listed = 0;
  for (const auto& r : s.class_learn_pushes) {
    listed += r.size();
    for (const auto& p : r) EXPECT_NE(p.find('>'), std::string::npos) << p;
  }
  EXPECT_EQ(listed, static_cast<std::size_t>(l.pushes_learn));
  // Each learn push's blob by object, "name:share+...", largest first, led by its intended.
  ASSERT_EQ(s.class_learn_blobs.size(), s.class_learn_pushes.size());
  for (std::size_t r = 0; r < s.class_learn_blobs.size(); ++r) {
    ASSERT_EQ(s.class_learn_blobs[r].size(), s.class_learn_pushes[r].size());
    for (std::size_t k = 0; k < s.class_learn_blobs[r].size(); ++k) {
      const std::string& b = s.class_learn_blobs[r][k];
      const std::string intended =
          s.class_learn_pushes[r][k].substr(0, s.class_learn_pushes[r][k].find('>'));
      if (intended.empty()) {
        EXPECT_TRUE(b.empty()) << b;
        continue;
      }
      EXPECT_EQ(b.rfind(intended + ":", 0), 0U) << b << " / " << intended;
    }
  }
  for (const ObjectScore& os : s.objects) {
    EXPECT_GE(os.turn_deg, 0.0);
    EXPECT_LE(os.turn_deg, 180.0);
  }
  EXPECT_NO_THROW((void)j.dump());  // no NaN or Inf
}

TEST(SelfSupervision, SplitByMotionJudgesLearnPushesByTheirEpisodes) {
  // Motion views with split_by_motion: each learn push's segmentation splits the looks' blobs
  // (logged "split") and what it moved is judged from its episode (motion source "episode");
  // with alone_views a push that moved two objects gives no views.
  // Off by default: measured no better (docs/results/selfsupervision-history.md, session 18).
  EXPECT_FALSE(SelfSupervisionOptions{}.split_by_motion);
  SelfSupervisionOptions o = small_options();
  o.views = ViewSource::kMotion;
  o.split_by_motion = true;
  o.alone_views = true;
  const test::TempDir dir("proprio_selfsup_split_");
  std::optional<TinyModel> tiny;
  Learning l;
  {
    const sim::ObjectCatalogue catalogue = sim::ObjectCatalogue::load_default();
    sim::SimulatedRobot robot(table_of(o), catalogue);
    tiny = tiny_model(robot.look().image);
    GroundTruthAttendant attendant(robot, o.seed);
    l = learn_by_pushing(robot, attendant, 2, tiny->lda, tiny->vocabulary, o, dir.path());
  }
  ASSERT_GT(l.pushes_learn, 0);
  int episode_judged = 0;
  int splits = 0;
  for (std::size_t i = 0; i < l.log.size(); ++i) {
    const auto& j = l.log[i];
    if (j.event == "split") {
      ++splits;
      EXPECT_EQ(j.phase, "learn");
      EXPECT_TRUE(j.then.has_value());
    }
    if (j.event != "motion" || j.source != "episode") continue;
    ++episode_judged;
    ASSERT_TRUE(j.shares && j.moved_most && j.blob);
    // The split came first (the look before the push, split by its touch mask).
    EXPECT_GT(splits, 0);
    ASSERT_LT(*j.blob, static_cast<int>(j.shares->size()));
    int moved = 0;
    for (const double sh : *j.shares) moved += sh >= o.moved_share ? 1 : 0;
    const bool two = *j.moved_most == *j.blob && moved > 1;
    for (std::size_t k = i + 1; k < l.log.size(); ++k) {
      if (l.log[k].event != "views") continue;
      if (two) {
        EXPECT_EQ(l.log[k].taken, 0);
      }
      break;
    }
  }
  EXPECT_GT(episode_judged, 0);
  EXPECT_EQ(splits, episode_judged);
}

TEST(SelfSupervision, FreeSpacePushesTheChosenObjectAndCentresItsLearnPushes) {
  // free_space: (b) pushes the chosen object itself toward a free spot (a clearing push of the
  // chosen blob, logged "free space"), and (c)'s circle of targets is about its place after (b)
  // (logged "hub", within free_space of the work centre).
  SelfSupervisionOptions o = small_options();
  o.free_space = 0.12;
  o.seed = 11;  // a table whose chosen object can be pushed into free space in round 0
  Learning l;
  {
    const sim::ObjectCatalogue catalogue = sim::ObjectCatalogue::load_default();
    sim::SimulatedRobot robot(table_of(o), catalogue);
    const TinyModel m = tiny_model(robot.look().image);
    CountingAttendant attendant;
    l = learn_by_pushing(robot, attendant, 2, m.lda, m.vocabulary, o, {});
  }
  std::optional<std::vector<double>> centre;
  std::optional<int> chosen;  // the last look's chosen blob
  int hubs = 0;
  int free_plans = 0;
  int free_pushes = 0;
  for (std::size_t i = 0; i < l.log.size(); ++i) {
    const auto& j = l.log[i];
    if (j.event == "start") centre = j.work_centre;
    if (j.event == "look" && j.chosen) chosen = j.chosen;
    if (j.event == "hub") {
      ASSERT_TRUE(centre && j.work_centre);
      if (j.why) {
        // No learn push could be planned about the object's place: the work centre again.
        EXPECT_NEAR((*j.work_centre)[0], (*centre)[0], 1e-12);
        EXPECT_NEAR((*j.work_centre)[1], (*centre)[1], 1e-12);
        continue;
      }
      ++hubs;
      const double d =
          std::hypot((*j.work_centre)[0] - (*centre)[0], (*j.work_centre)[1] - (*centre)[1]);
      EXPECT_LE(d, o.free_space + 1e-9);
    }
    if (j.event == "plan" && j.then && j.then->rfind("free space", 0) == 0) {
      ++free_plans;
      // The chosen blob itself is planned, and the spot gives it more room than it had.
      EXPECT_EQ(j.phase, "clear");
      ASSERT_TRUE(chosen.has_value());
      EXPECT_EQ(j.blob, chosen);
      if (j.plan && j.plan->outcome == planning::PlanOutcome::kPlanned) {
        ASSERT_LT(i + 1, l.log.size());
        EXPECT_EQ(l.log[i + 1].event, "push");
        EXPECT_EQ(l.log[i + 1].blob, chosen);
        ++free_pushes;
      }
    }
  }
  EXPECT_EQ(hubs, 2);  // each round's learn pushes
  EXPECT_GT(free_plans, 0);
  EXPECT_GT(free_pushes, 0);
  EXPECT_LE(free_plans, 2 * kFreeMoves * 4);  // at most kFreeTries spots a try
}

TEST(SelfSupervision, SplitLooksAndTheSingulationGateAreLogged) {
  // Told of 3 objects on a table of 2: every look shows fewer blobs than C, so with
  // split_merged its largest blob is split (event "split", the look then has more blobs). With
  // a clearance no table leaves (0.5 m) and no clearing pushes, (b) never singulates: with
  // singulate_tries 2 each round starts (b) twice more, then (c) starts anyway, all logged.
  SelfSupervisionOptions o = small_options();
  o.pushes = 1;
  o.clear_pushes = 0;
  o.clearance = 0.5;
  const auto run = [&](const SelfSupervisionOptions& opt) {
    const sim::ObjectCatalogue catalogue = sim::ObjectCatalogue::load_default();
    sim::SimulatedRobot robot(table_of(opt), catalogue);
    const TinyModel m = tiny_model(robot.look().image);
    CountingAttendant attendant;
    return learn_by_pushing(robot, attendant, 3, m.lda, m.vocabulary, opt, {});
  };
  const auto again = [](const SelfSupervisionDecision& j) {
    return j.event == "replan" && j.why && j.why->rfind("(b) ended", 0) == 0;
  };
  const auto anyway = [](const SelfSupervisionDecision& j) {
    return j.event == "replan" && j.why && j.why->rfind("(b) tried again", 0) == 0;
  };
  {
    const Learning l = run(o);  // both off: no split, no second (b)
    for (const auto& j : l.log) {
      EXPECT_NE(j.event, "split");
      EXPECT_FALSE(again(j) || anyway(j));
    }
  }
  o.split_merged = true;
  o.singulate_tries = 2;
  const Learning l = run(o);
  int splits = 0;
  int split_looks = 0;
  std::map<int, int> not_alone;  // per round: (b) ended without the object alone
  std::map<int, int> retries;
  std::map<int, int> gave_up;
  for (std::size_t i = 0; i < l.log.size(); ++i) {
    const auto& j = l.log[i];
    if (j.event == "split") {
      ++splits;
      ASSERT_TRUE(j.blobs && j.why);
      EXPECT_GE(j.blobs->size(), 2U);
      EXPECT_LE(j.blobs->size(), 3U);
      // A look logged right after it is the split one (the learn pushes' looks log no event).
      if (i + 1 < l.log.size() && l.log[i + 1].event == "look") {
        ++split_looks;
        ASSERT_TRUE(l.log[i + 1].blobs);
        EXPECT_EQ(l.log[i + 1].blobs->size(), j.blobs->size());
      }
    }
    if (j.event == "fault" && j.fault == "not-singulated") ++not_alone[*j.round];
    if (again(j)) ++retries[*j.round];
    if (anyway(j)) ++gave_up[*j.round];
    if (j.event == "singulated") ADD_FAILURE() << "no clearance of 0.5 m on this table";
  }
  EXPECT_GT(splits, 0);
  EXPECT_GT(split_looks, 0);
  ASSERT_FALSE(not_alone.empty());
  for (const auto& [r, n] : not_alone) {
    SCOPED_TRACE(r);
    EXPECT_EQ(n, 3);  // the first (b) and two more
    EXPECT_EQ(retries[r], 2);
    EXPECT_EQ(gave_up[r], 1);
  }
}

TEST(SelfSupervision, DepthCheckIsLoggedAndAnotherObjectIsChosenWhenNotAlone) {
  // The book and the bottle with a clearance no table leaves (0.5 m) and no clearing pushes: (b)
  // never singulates. Without depth the looks of (b) carry no depth verdict; with
  // alone_by_depth every look of (b) logs the depth check ("depth: ... not alone", its gap), and
  // with switch_tries 1 each round that was not singulated chooses once another blob (logged,
  // the attendant told), whose (b) ends not singulated too.
  SelfSupervisionOptions o = small_options();
  o.pushes = 1;
  o.clear_pushes = 0;
  o.clearance = 0.5;
  const auto run = [&](const SelfSupervisionOptions& opt, ChoiceCounter& attendant) {
    const sim::ObjectCatalogue catalogue = sim::ObjectCatalogue::load_default();
    sim::TableOptions t = table_of(opt);
    t.depth = opt.depth || opt.alone_by_depth;
    sim::SimulatedRobot robot(t, catalogue);
    const TinyModel m = tiny_model(robot.look().image);
    return learn_by_pushing(robot, attendant, 2, m.lda, m.vocabulary, opt, {});
  };
  const auto switched = [](const SelfSupervisionDecision& j) {
    return j.event == "replan" && j.why && j.why->rfind("(b) could not singulate", 0) == 0;
  };
  {
    ChoiceCounter attendant;
    const Learning l = run(o, attendant);
    for (const auto& j : l.log) {
      if (j.event == "look" && j.phase == "clear") {
        EXPECT_FALSE(j.why.has_value());
      }
      EXPECT_FALSE(switched(j));
    }
  }
  o.alone_by_depth = true;
  o.switch_tries = 1;
  ChoiceCounter attendant;
  const Learning l = run(o, attendant);
  int clear_looks = 0;
  std::map<int, int> not_alone;
  std::map<int, int> switches;
  for (const auto& j : l.log) {
    if (j.event == "look" && j.phase == "clear") {
      ++clear_looks;
      ASSERT_TRUE(j.why.has_value());
      EXPECT_EQ(j.why->rfind("feature hulls: ", 0), 0U) << *j.why;
      EXPECT_NE(j.why->find("; depth: "), std::string::npos) << *j.why;
      EXPECT_NE(j.why->find("not alone"), std::string::npos) << *j.why;
      if (j.gap) {
        EXPECT_LT(*j.gap, 0.5);
      }
    }
    if (j.event == "fault" && (j.fault == "not-singulated" || j.fault == "cannot-clear")) {
      ++not_alone[*j.round];
    }
    if (switched(j)) {
      ++switches[*j.round];
      ASSERT_TRUE(j.blob && j.blobs);
      EXPECT_LT(*j.blob, static_cast<int>(j.blobs->size()));
    }
    if (j.event == "singulated") ADD_FAILURE() << "no clearance of 0.5 m on this table";
  }
  EXPECT_GT(clear_looks, 0);
  ASSERT_FALSE(not_alone.empty());
  int total = 0;
  for (const auto& [r, n] : not_alone) {
    SCOPED_TRACE(r);
    EXPECT_EQ(n, 2);  // the first (b) and the switched object's
    EXPECT_EQ(switches[r], 1);
    total += switches[r];
  }
  // The attendant is told of each choice: the first of each round and each switch.
  EXPECT_EQ(attendant.choices, static_cast<int>(not_alone.size()) + total);
}

// Two rounds of learn_by_pushing on the table of o, with the tiny model of its first look: the
// run and how often the attendant was told a choice.
std::pair<Learning, int> two_round_run(const SelfSupervisionOptions& o) {
  const sim::ObjectCatalogue catalogue = sim::ObjectCatalogue::load_default();
  sim::SimulatedRobot robot(table_of(o), catalogue);
  const TinyModel m = tiny_model(robot.look().image);
  ChoiceCounter attendant;
  Learning l = learn_by_pushing(robot, attendant, 2, m.lda, m.vocabulary, o, {});
  return {std::move(l), attendant.choices};
}

TEST(SelfSupervision, ARoundWhoseFirstViewsALearnedClassExplainsChoosesAgain) {
  // repeat_tries 1 at a share any explained view meets: round 1's first views (blob views of
  // the book and the bottle) are tested against object_1's Mixture of Topics; on this table
  // they are explained, so the round drops them (logged, event "repeat"), looks again and
  // chooses again (the attendant told), and its class keeps only the views of the later pushes.
  SelfSupervisionOptions o = small_options();
  o.pushes = 4;  // round 0's class needs 2 views or more to be in the model
  o.repeat_tries = 1;
  o.repeat_share = 0.01;
  const auto [l, choices] = two_round_run(o);
  int repeats = 0;
  int again_looks = 0;
  int chooses = 0;
  int dropped = 0;
  int taken_after = 0;  // round 1's views logged after the repeat
  for (const auto& j : l.log) {
    if (j.event == "choose") ++chooses;
    if (j.event == "repeat") {
      ++repeats;
      EXPECT_EQ(j.round, 1);  // round 0 has no class to test against
      ASSERT_TRUE(j.why && j.views);
      EXPECT_EQ(j.why->rfind("the round's first views are explained by object_1", 0), 0U) << *j.why;
      dropped = *j.views;
    }
    if (j.event == "look" && j.why && j.why->find("learned already") != std::string::npos) {
      ++again_looks;
    }
    if (j.event == "views" && j.round == 1 && repeats > 0) taken_after += j.taken.value_or(0);
  }
  EXPECT_EQ(repeats, 1);
  EXPECT_EQ(again_looks, 1);
  EXPECT_GT(dropped, 0);
  EXPECT_EQ(chooses, 3);
  EXPECT_EQ(choices, 3);
  EXPECT_EQ(static_cast<int>(std::count(l.views.labels.begin(), l.views.labels.end(), 1)),
            taken_after);

  // Off (the default): no test, no "repeat" event, one choice a round.
  o.repeat_tries = 0;
  const auto [l2, choices2] = two_round_run(o);
  for (const auto& j : l2.log) EXPECT_NE(j.event, "repeat");
  EXPECT_EQ(choices2, 2);
}

// The rounds tests: two objects learned on the simulated table of `opt` with a tiny model; and
// how many of a run's decisions are of `event`.
Learning learn_two_objects(const SelfSupervisionOptions& opt) {
  const sim::ObjectCatalogue catalogue = sim::ObjectCatalogue::load_default();
  sim::SimulatedRobot robot(table_of(opt), catalogue);
  const TinyModel m = tiny_model(robot.look().image);
  ChoiceCounter attendant;
  return learn_by_pushing(robot, attendant, 2, m.lda, m.vocabulary, opt, {});
}
int count_events(const Learning& l, const std::string& event) {
  return static_cast<int>(
      std::count_if(l.log.begin(), l.log.end(), [&](const auto& j) { return j.event == event; }));
}

TEST(SelfSupervision, MoreRoundsThanObjectsAreMergedByTheRobotsJudgement) {
  SelfSupervisionOptions o = small_options();
  o.pushes = 3;
  o.rounds = 3;
  const auto run = learn_two_objects;
  const auto count = count_events;
  // Any two round classes are one object by this threshold: the robot never judges two objects
  // learned, runs all 3 rounds and merges them into 2 classes, every merge logged.
  o.same_object = 10;
  const Learning all = run(o);
  EXPECT_EQ(all.classes, 2);
  EXPECT_EQ(all.class_names, (std::vector<std::string>{"object_1", "object_2"}));
  ASSERT_EQ(all.round_class.size(), 3U);
  EXPECT_EQ(all.stop_reasons.size(), 3U);
  EXPECT_EQ(count(all, "choose"), 3);
  EXPECT_EQ(count(all, "judge"), 1);  // after round 2 (round 3 is the last)
  EXPECT_EQ(all.views_per_class.size(), 2U);
  int views = 0;
  for (const int v : all.views_per_class) views += v;
  EXPECT_EQ(views, static_cast<int>(all.views.labels.size()));
  for (const int l : all.views.labels) {
    EXPECT_GE(l, 0);
    EXPECT_LT(l, 2);
  }
  int with_views = 0;
  for (const int c : all.round_class) with_views += c >= 0 ? 1 : 0;
  int merges = 0;
  for (const auto& j : all.log) {
    if (j.event != "merge" || !j.merged) continue;
    ++merges;
    ASSERT_TRUE(j.distance && j.why);
    EXPECT_GE(*j.distance, 0.0);
    EXPECT_NE(j.why->find("rounds "), std::string::npos) << *j.why;
  }
  EXPECT_EQ(merges, std::max(0, with_views - 2));
  EXPECT_EQ(all.log.back().event, "end");
  // Judged by words: each pair's distance is its views' word distance.
  for (const auto& j : all.log) {
    if (j.event != "distance") continue;
    ASSERT_TRUE(j.distance && j.word_distance);
    EXPECT_EQ(*j.word_distance, *j.distance);
  }

  // Nothing is below threshold 0: after round 2 every round with views is its own object, so
  // with two such rounds the robot stops there, each round its own class.
  o.same_object = 0;
  const Learning judged = run(o);
  const auto it = std::find_if(judged.log.begin(), judged.log.end(),
                               [](const auto& j) { return j.event == "judge"; });
  ASSERT_NE(it, judged.log.end());
  ASSERT_TRUE(it->classes.has_value());
  if (*it->classes == 2) {
    EXPECT_EQ(count(judged, "choose"), 2);
    EXPECT_EQ(judged.round_class, (std::vector<int>{0, 1}));
  } else {
    EXPECT_EQ(count(judged, "choose"), 3);
  }

  // Fewer rounds than objects: bad input.
  o.rounds = 1;
  EXPECT_THROW((void)run(o), Error);
}

// same_object_by colour (session 44): the rounds are judged by their looks' pixel colours. At
// bound 1 (only colours with nothing in common are apart) the robot never judges two objects
// learned and runs all 3 rounds; at bound 0 it stops after round 2 when both rounds gave views.
// The judgement and the distances say they are colours' (Hellinger, in [0, 1]); the rounds'
// colours are kept although the claims are by another signal. Without rounds it is refused.
TEST(SelfSupervision, MoreRoundsThanObjectsAreJudgedByTheirLooksColours) {
  SelfSupervisionOptions o = small_options();
  o.pushes = 3;
  o.rounds = 3;
  o.claims_by = ClaimSignal::kLooks;
  o.same_object_by = RoundSimilarity::kColour;
  o.same_object = 0;  // the words' bound: would judge every round apart
  const auto run = learn_two_objects;
  const auto count = count_events;
  o.same_colour = 1.0;
  const Learning all = run(o);
  EXPECT_EQ(count(all, "choose"), 3);
  EXPECT_GT(count(all, "distance"), 0);  // at least two rounds gave views
  EXPECT_EQ(all.classes, 2);
  ASSERT_EQ(all.round_colours.size(), 3U);
  for (const auto& j : all.log) {
    if (j.event == "judge") {
      ASSERT_TRUE(j.why);
      EXPECT_NE(j.why->find("Hellinger"), std::string::npos) << *j.why;
      ASSERT_TRUE(j.classes);
      EXPECT_LE(*j.classes, 1);
    }
    if (j.event == "distance") {
      ASSERT_TRUE(j.distance && j.merged);
      const auto& r = *j.merged;
      EXPECT_NEAR(*j.distance,
                  colour_round_distance(all.round_colours[static_cast<std::size_t>(r[0])],
                                        all.round_colours[static_cast<std::size_t>(r[1])]),
                  1e-12);
      EXPECT_LE(*j.distance, 1.0);
      // The diagnostic distances beside it: the looks' colours are the judgement's own.
      ASSERT_TRUE(j.look_colour_distance && j.word_distance);
      EXPECT_EQ(*j.look_colour_distance, *j.distance);
      EXPECT_GE(*j.word_distance, 0.0);
      EXPECT_FALSE(j.view_colour_distance);  // the tiny model has no colour words
    }
    if (j.event == "merge" && j.merged) {
      ASSERT_TRUE(j.why);
      EXPECT_NE(j.why->find("same_colour"), std::string::npos) << *j.why;
    }
  }
  o.same_colour = 0;
  const Learning apart = run(o);
  const auto it = std::find_if(apart.log.begin(), apart.log.end(),
                               [](const auto& j) { return j.event == "judge"; });
  ASSERT_NE(it, apart.log.end());
  ASSERT_TRUE(it->classes.has_value());
  EXPECT_EQ(count(apart, "choose"), *it->classes == 2 ? 2 : 3);
  o.rounds = 0;
  EXPECT_THROW(o.validate(), Error);
}

// moved_colours (session 45): a round's colours are exactly the pixels its learn pushes moved,
// each push logged (event "colours"); its looks add none. Without the option no push is logged
// so and the looks give the colours. Refused without a colour signal and with colour_first_look.
TEST(SelfSupervision, MovedColoursAreThePixelsTheLearnPushesMoved) {
  SelfSupervisionOptions o = small_options();
  o.pushes = 3;
  o.rounds = 3;  // the round colours are reported with the rounds' judgement by colour
  o.same_object_by = RoundSimilarity::kColour;
  o.same_colour = 1.0;  // every round runs
  o.moved_colours = true;
  const Learning moved = learn_two_objects(o);
  ASSERT_EQ(moved.round_colours.size(), 3U);
  std::vector<double> logged(3, 0.0);
  int learn_pushes = 0;
  for (const auto& j : moved.log) {
    if (j.event == "push" && j.phase == "learn" && j.executed.value_or(false)) ++learn_pushes;
    if (j.event != "colours") continue;
    ASSERT_TRUE(j.round && j.moved_pixels);
    EXPECT_GE(*j.moved_pixels, 0);
    logged[static_cast<std::size_t>(*j.round)] += *j.moved_pixels;
  }
  EXPECT_EQ(count_events(moved, "colours"), learn_pushes);
  double total = 0;
  for (std::size_t r = 0; r < 3; ++r) {
    EXPECT_DOUBLE_EQ(moved.round_colours[r].sum(), logged[r]) << "round " << r;
    total += logged[r];
  }
  EXPECT_GT(total, 0.0);  // the pushes moved something

  o.moved_colours = false;
  const Learning blobs = learn_two_objects(o);
  EXPECT_EQ(count_events(blobs, "colours"), 0);
  double blob_total = 0;
  for (const auto& c : blobs.round_colours) blob_total += c.sum();
  EXPECT_GT(blob_total, 0.0);

  o.moved_colours = true;
  o.colour_first_look = true;
  EXPECT_THROW(o.validate(), Error);
  o.colour_first_look = false;
  o.rounds = 0;
  o.same_object_by = RoundSimilarity::kWords;
  o.claims_by = ClaimSignal::kLooks;
  EXPECT_THROW(o.validate(), Error);
}

// Round 1's choice (the run's second "choose" event) of two_round_run with `o`.
SelfSupervisionDecision second_choice(const SelfSupervisionOptions& o) {
  int seen = 0;
  for (const auto& j : two_round_run(o).first.log) {
    if (j.event == "choose" && seen++ == 1) return j;
  }
  ADD_FAILURE() << "no second choice";
  return SelfSupervisionDecision{};
}

// Two runs' choices of round 1 that score the same blobs (the runs the same up to that choice) by
// other colour distances, each a Hellinger distance.
void expect_other_colour_distances(const SelfSupervisionDecision& a,
                                   const SelfSupervisionDecision& b) {
  ASSERT_TRUE(a.scores && b.scores);
  ASSERT_EQ(a.scores->size(), b.scores->size());
  ASSERT_FALSE(a.scores->empty());
  bool differ = false;
  for (std::size_t k = 0; k < a.scores->size(); ++k) {
    const auto& p = (*a.scores)[k];
    const auto& q = (*b.scores)[k];
    EXPECT_EQ(p.blob, q.blob);
    ASSERT_TRUE(p.nearest && q.nearest);
    EXPECT_GE(*q.nearest, 0.0);
    EXPECT_LE(*q.nearest, 1.0);
    if (std::abs(*p.nearest - *q.nearest) > 1e-9) differ = true;
  }
  EXPECT_TRUE(differ);
}

// colour_by_look (session 45): the claims by colour compare a blob with each of a class's looks.
// Both runs are the same up to round 1's choice (same table, same pushes), so its look scores the
// same blobs; the distances differ (the least over object_1's looks, not the distance to their
// pooled colours) and stay Hellinger distances. Refused without claims by colour, with
// colour_first_look or with moved_colours.
TEST(SelfSupervision, ClaimsByColourLookByLookTakeTheNearestLook) {
  SelfSupervisionOptions o = small_options();
  o.pushes = 3;
  const SelfSupervisionDecision pooled = second_choice(o);
  o.colour_by_look = true;
  expect_other_colour_distances(pooled, second_choice(o));
  o.colour_first_look = true;
  EXPECT_THROW(o.validate(), Error);
  o.colour_first_look = false;
  o.moved_colours = true;
  EXPECT_THROW(o.validate(), Error);
  o.moved_colours = false;
  o.claims_by = ClaimSignal::kLooks;
  EXPECT_THROW(o.validate(), Error);
  o.claims_by = ClaimSignal::kColour;
  EXPECT_NO_THROW(o.validate());
}

// table_colours_out (session 49): the claims by colour leave the table's words out of the blobs'
// and the classes' colours. Both runs are the same up to round 1's choice, so its look scores the
// same blobs; the distances differ and stay Hellinger distances. Refused without claims by
// colour or with moved_colours.
TEST(SelfSupervision, ClaimsByColourWithoutTheTablesColoursMeasureOtherDistances) {
  SelfSupervisionOptions o = small_options();
  o.pushes = 3;
  const SelfSupervisionDecision with_table = second_choice(o);
  o.table_colours_out = true;
  expect_other_colour_distances(with_table, second_choice(o));
  o.moved_colours = true;
  EXPECT_THROW(o.validate(), Error);
  o.moved_colours = false;
  o.claims_by = ClaimSignal::kLooks;
  EXPECT_THROW(o.validate(), Error);
  o.other_claims_by = ClaimSignal::kColour;
  EXPECT_NO_THROW(o.validate());
}

TEST(SelfSupervision, ARoundWhoseLaterViewsALearnedClassExplainsStops) {
  // repeat_later at a share any explained view meets: round 1's first views are kept (no
  // repeat_tries), each later push's views are tested against object_1's Mixture of Topics; on
  // this table they are explained, so the round drops them (event "repeat"), gives no more
  // views and stops with the reason said; its class keeps only the views before.
  SelfSupervisionOptions o = small_options();
  o.pushes = 4;  // round 0's class needs 2 views or more to be in the model
  o.repeat_later = true;
  o.repeat_share = 0.01;
  const auto [l, choices] = two_round_run(o);
  int repeats = 0;
  int taken_before = 0;  // round 1's views logged before the repeat
  int views_after = 0;   // round 1's "views" events after it
  bool first_views = false;
  for (const auto& j : l.log) {
    if (j.event == "repeat") {
      ++repeats;
      EXPECT_EQ(j.round, 1);  // round 0 has no class to test against
      ASSERT_TRUE(j.why && j.views);
      EXPECT_EQ(j.why->rfind("a later push's views are explained by object_1", 0), 0U) << *j.why;
      EXPECT_NE(j.why->find("the round stops"), std::string::npos) << *j.why;
      EXPECT_GT(*j.views, 0);
      EXPECT_TRUE(first_views);  // never the round's first push with views
    }
    if (j.event == "views" && j.round == 1) {
      if (repeats > 0) {
        ++views_after;
      } else {
        taken_before += j.taken.value_or(0);
        first_views = first_views || j.taken.value_or(0) > 0;
      }
    }
  }
  EXPECT_EQ(repeats, 1);
  EXPECT_EQ(views_after, 0);  // the round stopped at the dropped push
  EXPECT_GT(taken_before, 0);
  EXPECT_EQ(static_cast<int>(std::count(l.views.labels.begin(), l.views.labels.end(), 1)),
            taken_before);
  ASSERT_EQ(l.stop_reasons.size(), 2U);
  EXPECT_EQ(l.stop_reasons[1], "a later push's views were explained by a learned class");
  EXPECT_EQ(choices, 2);  // the round stops; it does not choose again
}

TEST(SelfSupervision, OracleLadderIsScoredOnTheSameRun) {
  // Motion views with the oracle ladder: the episodes carry ground-truth masks (the table's
  // record_masks), the attendant records every view's truth in the views' order, and the score
  // has every rung, (c) being the run's own figure.
  SelfSupervisionOptions o = small_options();
  o.views = ViewSource::kMotion;
  o.oracle_ladder = true;
  const test::TempDir dir("proprio_selfsup_ladder_");
  TableRun run = learn_on_table(o, dir.path(), true);
  const std::optional<TinyModel>& tiny = run.tiny;
  const Learning& l = run.l;
  const auto& attendant = run.attendant;
  ASSERT_GT(l.views.labels.size(), 0U);
  ASSERT_EQ(attendant->views().size(), l.views.labels.size());
  double arm = 0;
  for (const ViewTruth& v : attendant->views()) {
    EXPECT_TRUE(v.known);
    EXPECT_GE(v.frame, 0);
    EXPECT_FALSE(v.episode.empty());
    EXPECT_LE(v.share_object + v.share_arm + v.share_background, 1.0 + 1e-9);
    arm += v.share_arm;
  }
  // The arm's own image is cut out of the motion views (cut_arm): before, a third of the
  // views' masks lay on the arm (seed 2 of the report, docs/results/selfsupervision-history.md).
  EXPECT_LT(arm / static_cast<double>(attendant->views().size()), 0.05);
  const SelfSupervisionScore s =
      score_self_supervision(l, *attendant, {"book", "bottle"}, tiny->lda, tiny->vocabulary, o);
  ASSERT_TRUE(s.ladder.has_value());
  std::vector<std::string> names;
  for (const LadderRung& r : s.ladder->rungs) {
    names.push_back(r.name);
    EXPECT_EQ(r.per_object.size(), 2U) << r.name;
    EXPECT_GE(r.accuracy, 0.0) << r.name;
    EXPECT_LE(r.accuracy, 1.0) << r.name;
  }
  EXPECT_EQ(names, (std::vector<std::string>{"a0", "a0_table", "a", "a_last", "a_alone", "b",
                                             "b_pure", "c_named", "c"}));
  // (a0): both objects rendered kLadderRenders (24) times each at the centre.
  EXPECT_EQ(s.ladder->rungs[0].training_views, 48);
  EXPECT_EQ(s.ladder->rungs[0].classes, 2);
  EXPECT_GT(s.ladder->rungs[2].training_views, 0);  // (a): true masks of the pushed objects
  // (a_alone): one render a push, in the pose the ground truth gave its last view (recorded).
  int posed_pushes = 0;
  const auto& views = attendant->views();
  for (std::size_t i = 0; i < views.size(); ++i) {
    if (!views[i].posed) continue;
    EXPECT_LT(views[i].position.norm(), 2.0);  // on the table, m
    if (i + 1 == views.size() || views[i + 1].episode != views[i].episode) ++posed_pushes;
  }
  EXPECT_GT(posed_pushes, 0);
  EXPECT_GT(s.ladder->rungs[4].training_views, 0);
  EXPECT_LE(s.ladder->rungs[4].training_views, posed_pushes);
  EXPECT_GT(s.ladder->rungs[5].training_views, 0);  // (b): the robot's views, true labels
  EXPECT_LE(s.ladder->rungs[5].training_views, static_cast<int>(l.views.labels.size()));
  EXPECT_DOUBLE_EQ(s.ladder->rungs.back().accuracy, s.mot_accuracy);
  EXPECT_NO_THROW((void)core::fields_to_json(s).dump());
  EXPECT_FALSE(s.pooled.has_value());           // pooled_score off: no pooled figures
  EXPECT_FALSE(s.colour_accuracy.has_value());  // no colour words: no colour figure
  // The pooled words classifier learns from the same views: one document a training view, of
  // the view's own length.
  ASSERT_EQ(l.views.words.num_documents(), l.views.labels.size());
  for (std::size_t i = 0; i < l.views.labels.size(); ++i) {
    EXPECT_EQ(l.views.words.document(i).tokens(), l.views.tokens[i]) << i;
  }
  // pooled_score: every rung and c scored by it too, on the same held-out views; the theta
  // figures unchanged. mot_classifier kPooled at a weight gives the same figure as c's pooled one
  // at that weight (weight 1: naive Bayes on the views' words with the MoT's prior).
  o.pooled_score = true;
  const SelfSupervisionScore p =
      score_self_supervision(l, *attendant, {"book", "bottle"}, tiny->lda, tiny->vocabulary, o);
  EXPECT_DOUBLE_EQ(p.mot_accuracy, s.mot_accuracy);
  ASSERT_TRUE(p.pooled.has_value());
  ASSERT_EQ(p.pooled->size(), kPooledWeights.size() + 1);
  EXPECT_TRUE(p.pooled->back().once);
  for (std::size_t k = 0; k < kPooledWeights.size(); ++k) {
    EXPECT_DOUBLE_EQ((*p.pooled)[k].weight, kPooledWeights[k]);
    EXPECT_FALSE((*p.pooled)[k].once);
  }
  for (const LadderRung& r : p.ladder->rungs) {
    if (r.classes == 0) continue;
    ASSERT_TRUE(r.pooled.has_value()) << r.name;
    EXPECT_EQ(r.pooled->size(), r.name == "c" ? kPooledWeights.size() + 1 : kPooledWeights.size())
        << r.name;
    for (const PooledFigure& f : *r.pooled) {
      EXPECT_GE(f.accuracy, 0.0) << r.name;
      EXPECT_LE(f.accuracy, 1.0) << r.name;
      EXPECT_EQ(f.per_object.size(), 2U) << r.name;
    }
  }
  for (const std::size_t k : {std::size_t{1}, kPooledWeights.size() - 1}) {
    SelfSupervisionOptions q = o;
    q.pooled_score = false;
    q.oracle_ladder = false;
    q.mot_classifier = MotClassifier::kPooled;
    q.mot_word_weight = kPooledWeights[k];
    const SelfSupervisionScore by =
        score_self_supervision(l, *attendant, {"book", "bottle"}, tiny->lda, tiny->vocabulary, q);
    EXPECT_DOUBLE_EQ(by.mot_accuracy, (*p.pooled)[k].accuracy) << kPooledWeights[k];
    for (std::size_t oi = 0; oi < 2; ++oi) {
      EXPECT_DOUBLE_EQ(by.objects[oi].mot_accuracy, (*p.pooled)[k].per_object[oi]);
    }
  }
}

TEST(SelfSupervision, OwnModelRungsBuildAVocabularyAndLdaOfTheirOwnViews) {
  // own_model_rungs: the learner keeps each view's descriptors (the rows its documents were
  // made of), the ladder gains a0_own, a_own, b_own, c_own after its other rungs, which are
  // unchanged, and c_own is the robot's views and classes through a vocabulary and LDA model of
  // their own, classified by the pooled per-view words classifier (recomputed here from the
  // library's functions on held-out views rendered and cut out as the scorer does).
  SelfSupervisionOptions o = small_options();
  o.views = ViewSource::kMotion;
  o.oracle_ladder = true;
  o.own_model_rungs = true;
  o.own_words = 30;
  o.own_topics = 4;
  const test::TempDir dir("proprio_selfsup_own_");
  TableRun run = learn_on_table(o, dir.path(), true);
  const std::optional<TinyModel>& tiny = run.tiny;
  const Learning& l = run.l;
  const auto& attendant = run.attendant;
  ASSERT_GT(l.views.labels.size(), 0U);
  ASSERT_EQ(l.views.descriptors.size(), l.views.labels.size());
  for (std::size_t i = 0; i < l.views.labels.size(); ++i) {
    EXPECT_EQ(l.views.descriptors[i].rows, l.views.tokens[i]) << i;
    const topics::DocumentView doc = l.views.words.document(i);
    std::vector<std::int32_t> words;
    for (std::size_t k = 0; k < doc.size(); ++k) {
      words.insert(words.end(), static_cast<std::size_t>(doc.counts[k]), doc.words[k]);
    }
    std::vector<std::int32_t> again =
        features::bag_of_words(tiny->vocabulary, l.views.descriptors[i]);
    std::sort(again.begin(), again.end());
    std::sort(words.begin(), words.end());
    EXPECT_EQ(again, words) << i;
  }
  const std::vector<std::string> objects{"book", "bottle"};
  const SelfSupervisionScore s =
      score_self_supervision(l, *attendant, objects, tiny->lda, tiny->vocabulary, o);
  SelfSupervisionOptions off = o;
  off.own_model_rungs = false;
  const SelfSupervisionScore base =
      score_self_supervision(l, *attendant, objects, tiny->lda, tiny->vocabulary, off);
  ASSERT_TRUE(s.ladder && base.ladder);
  ASSERT_EQ(s.ladder->rungs.size(), base.ladder->rungs.size() + 6);
  for (std::size_t k = 0; k < base.ladder->rungs.size(); ++k) {
    EXPECT_EQ(s.ladder->rungs[k].name, base.ladder->rungs[k].name);
    EXPECT_DOUBLE_EQ(s.ladder->rungs[k].accuracy, base.ladder->rungs[k].accuracy)
        << s.ladder->rungs[k].name;
  }
  EXPECT_DOUBLE_EQ(s.mot_accuracy, base.mot_accuracy);
  const auto rung = [&](const std::string& name) -> const LadderRung& {
    for (const LadderRung& r : s.ladder->rungs) {
      if (r.name == name) return r;
    }
    throw Error("no rung " + name);
  };
  const std::size_t n = base.ladder->rungs.size();
  EXPECT_EQ(s.ladder->rungs[n].name, "a0_own");
  EXPECT_EQ(s.ladder->rungs[n + 3].name, "c_own");
  EXPECT_EQ(rung("a0_own").training_views, rung("a0").training_views);
  EXPECT_EQ(rung("a_own").training_views, rung("a").training_views);
  EXPECT_EQ(rung("b_own").training_views, rung("b").training_views);
  // a_up: (a)'s views whose object stood after its push, by the run's model and an own one.
  EXPECT_EQ(s.ladder->rungs[n + 4].name, "a_up");
  EXPECT_EQ(s.ladder->rungs[n + 5].name, "a_up_own");
  EXPECT_LE(rung("a_up").training_views, rung("a").training_views);
  EXPECT_EQ(rung("a_up_own").training_views, rung("a_up").training_views);
  EXPECT_EQ(rung("a_up_own").classes, rung("a_up").classes);
  for (const char* name : {"a0_own", "a_own", "b_own", "c_own", "a_up_own"}) {
    const LadderRung& r = rung(name);
    if (r.classes == 0) continue;
    ASSERT_TRUE(r.pooled.has_value()) << name;
    ASSERT_EQ(r.pooled->size(), kPooledWeights.size()) << name;
    EXPECT_DOUBLE_EQ((*r.pooled)[1].weight, o.mot_word_weight);
    EXPECT_DOUBLE_EQ((*r.pooled)[1].accuracy, r.accuracy) << name;
    EXPECT_GE(r.accuracy, 0.0) << name;
    EXPECT_LE(r.accuracy, 1.0) << name;
  }
  // c_own recomputed: the robot's classes (>= 2 views), each right for the object it is named
  // after.
  std::map<std::string, int> count;
  for (const int c : l.views.labels) ++count[l.class_names[static_cast<std::size_t>(c)]];
  std::vector<std::string> classes;
  for (const auto& [name, k] : count) {
    if (k >= 2) classes.push_back(name);
  }
  ASSERT_FALSE(classes.empty());
  std::vector<cv::Mat> views;
  std::vector<int> ids;
  for (std::size_t i = 0; i < l.views.labels.size(); ++i) {
    const std::string& name = l.class_names[static_cast<std::size_t>(l.views.labels[i])];
    const auto it = std::find(classes.begin(), classes.end(), name);
    if (it == classes.end()) continue;
    views.push_back(l.views.descriptors[i]);
    ids.push_back(static_cast<int>(it - classes.begin()));
  }
  EXPECT_EQ(rung("c_own").training_views, static_cast<int>(views.size()));
  const features::Vocabulary vocabulary = views_vocabulary(views, o.own_words, o.seed);
  EXPECT_EQ(vocabulary.size(), 30);
  topics::Corpus corpus(vocabulary.size());
  for (const cv::Mat& v : views) corpus.add_tokens(features::bag_of_words(vocabulary, v));
  const topics::LdaModel lda = views_lda(corpus, o.own_topics, o.seed);
  EXPECT_EQ(lda.num_topics(), 4);
  const topics::MotModel model =
      topics::fit_mot(recognition::document_theta(lda, corpus).theta, ids, classes, o.mot).model;
  const Eigen::MatrixXd log_phi = weighted_word_multinomials(
      corpus, ids, static_cast<int>(classes.size()), per_view_weights(corpus, ids));
  int right = 0;
  int all = 0;
  const sim::ObjectCatalogue catalogue = sim::ObjectCatalogue::load_default();
  for (const std::string& object : objects) {
    sim::TableOptions t;
    t.objects = {object};
    t.seed = o.seed;
    t.width = o.width;
    t.height = o.height;
    sim::SimulatedRobot alone(t, catalogue);
    const int id = alone.ground_truth().at(0).id;
    topics::Corpus held(vocabulary.size());
    for (int v = 0; v < o.held_out; ++v) {
      const HeldOutView view = render_held_out_view(alone, object, id, v, o.held_out);
      const cv::Mat d = masked_descriptors(view.image, view.mask, o.features, o.dilate);
      if (d.rows >= o.min_features) held.add_tokens(features::bag_of_words(vocabulary, d));
    }
    if (held.num_documents() == 0) continue;
    const topics::MotClassification cls = topics::pool_word_multinomials(
        model, topics::classify_mot_words(model, lda, held), log_phi, held, o.mot_word_weight);
    for (const int c : cls.predicted) {
      const auto k = std::find(l.class_names.begin(), l.class_names.end(),
                               classes[static_cast<std::size_t>(c)]) -
                     l.class_names.begin();
      right += s.class_object[static_cast<std::size_t>(k)] == object ? 1 : 0;
      ++all;
    }
  }
  ASSERT_GT(all, 0);
  EXPECT_DOUBLE_EQ(rung("c_own").accuracy, static_cast<double>(right) / all);
  EXPECT_NO_THROW((void)core::fields_to_json(s).dump());
}

TEST(SelfSupervision, ViewsVocabularyKnownAnswers) {
  // k-means over the views' stacked descriptors (empty views skipped), at most min(words, rows)
  // words, as build_vocabulary over them with the seed and one thread; bad input throws.
  cv::Mat a(6, 128, CV_32F);
  cv::Mat b(5, 128, CV_32F);
  cv::randu(a, 0.0F, 1.0F);
  cv::randu(b, 0.5F, 2.0F);
  const std::vector<cv::Mat> views{a, cv::Mat(), b};
  const features::Vocabulary v = views_vocabulary(views, 3, 7);
  EXPECT_EQ(v.size(), 3);
  cv::Mat stacked;
  cv::vconcat(std::vector<cv::Mat>{a, b}, stacked);
  features::KmeansOptions ko;
  ko.words = 3;
  ko.seed = 7;
  ko.threads = 1;
  const features::Vocabulary w = features::build_vocabulary(stacked, ko).vocabulary;
  EXPECT_EQ(features::bag_of_words(v, stacked), features::bag_of_words(w, stacked));
  EXPECT_EQ(views_vocabulary(views, 50, 7).size(), 11);  // capped by the 11 descriptors
  EXPECT_THROW((void)views_vocabulary(views, 0, 7), Error);
  EXPECT_THROW((void)views_vocabulary(std::vector<cv::Mat>{cv::Mat()}, 3, 7), Error);
  EXPECT_THROW((void)views_vocabulary(std::vector<cv::Mat>{}, 3, 7), Error);
}

TEST(SelfSupervision, WeightedWordMultinomialsKnownAnswers) {
  topics::Corpus c(3);
  c.add_tokens(std::vector<std::int32_t>{0, 0, 1});  // class 0
  c.add_tokens(std::vector<std::int32_t>{2});        // class 1
  c.add_tokens(std::vector<std::int32_t>{1, 2});     // left out (-1)
  const std::vector<int> labels{0, 1, -1};
  // Unweighted: the same as topics::fit_word_multinomials (add-one).
  const Eigen::MatrixXd plain = weighted_word_multinomials(c, labels, 2);
  EXPECT_TRUE(plain.isApprox(topics::fit_word_multinomials(c, labels, 2, 1.0)));
  EXPECT_NEAR(plain(0, 0), std::log(3.0 / 6.0), 1e-12);
  // Document 0 at weight 0.5: counts 1 + 1, 1 + 0.5, 1 of 4.5.
  const std::vector<double> w{0.5, 1, 1};
  const Eigen::MatrixXd half = weighted_word_multinomials(c, labels, 2, w);
  EXPECT_NEAR(half(0, 0), std::log(2.0 / 4.5), 1e-12);
  EXPECT_NEAR(half(0, 1), std::log(1.5 / 4.5), 1e-12);
  EXPECT_NEAR(half(0, 2), std::log(1.0 / 4.5), 1e-12);
  EXPECT_NEAR(half(1, 2), std::log(2.0 / 4.0), 1e-12);
  // Weights of 1: as unweighted.
  EXPECT_TRUE(
      weighted_word_multinomials(c, labels, 2, std::vector<double>{1, 1, 1}).isApprox(plain));
  EXPECT_THROW((void)weighted_word_multinomials(c, labels, 2, std::vector<double>{1, -1, 1}),
               Error);
  EXPECT_THROW((void)weighted_word_multinomials(c, labels, 2, std::vector<double>{1, 1}), Error);
  EXPECT_THROW((void)weighted_word_multinomials(c, std::vector<int>{0, 2, -1}, 2,
                                                std::vector<double>{1, 1, 1}),
               Error);
  // Every view alike (per_view_weights): the labelled documents with words (3 and 1 tokens)
  // weigh their mean (2) over their own; the unlabelled one 0.
  EXPECT_EQ(per_view_weights(c, labels), (std::vector<double>{2.0 / 3, 2.0, 0.0}));
  topics::Corpus with_empty(3);
  with_empty.add_tokens(std::vector<std::int32_t>{0, 1, 1, 2});
  with_empty.add_tokens(std::vector<std::int32_t>{});
  EXPECT_EQ(per_view_weights(with_empty, std::vector<int>{0, 0}), (std::vector<double>{1.0, 0.0}));
  EXPECT_THROW((void)per_view_weights(c, std::vector<int>{0, 1}), Error);
  // Each push's views weigh 1 together: (class, push) groups of 3, 1 and 2 views.
  const std::vector<double> once =
      counts_once(std::vector<int>{0, 0, 0, 0, 1, 1}, std::vector<int>{0, 0, 0, 1, 0, 0});
  EXPECT_EQ(once, (std::vector<double>{1.0 / 3, 1.0 / 3, 1.0 / 3, 1, 0.5, 0.5}));
  EXPECT_THROW((void)counts_once(std::vector<int>{0}, std::vector<int>{0, 1}), Error);
  // The colour words alone: words 3 and 4 of 5 renumbered 0 and 1; a document without them is
  // empty; each class's colour multinomial weighs its views alike (3 and 1 colour tokens: the
  // mean, 2, over each).
  topics::Corpus coloured(5);
  coloured.add_tokens(std::vector<std::int32_t>{0, 3, 3, 4});
  coloured.add_tokens(std::vector<std::int32_t>{1, 2});
  coloured.add_tokens(std::vector<std::int32_t>{4, 2});
  const topics::Corpus colours = words_from(coloured, 3);
  ASSERT_EQ(colours.num_words(), 2);
  ASSERT_EQ(colours.num_documents(), 3U);
  EXPECT_EQ(colours.num_tokens(), 4);
  EXPECT_EQ(colours.document(0).words[0], 0);
  EXPECT_EQ(colours.document(0).counts[0], 2);
  EXPECT_TRUE(colours.document(1).empty());
  EXPECT_EQ(colours.document(2).words[0], 1);
  EXPECT_THROW((void)words_from(coloured, 5), Error);
  EXPECT_THROW((void)words_from(coloured, -1), Error);
  // Class 0: documents 0 (2 x word 0, 1 x word 1; weight 2/3) and 2 (1 x word 1; weight 2).
  const Eigen::MatrixXd lc = colour_multinomials(coloured, std::vector<int>{0, 0, 0}, 1, 3);
  EXPECT_NEAR(lc(0, 0), std::log((4.0 / 3 + 1) / (2 + 2 + 2.0)), 1e-12);
  EXPECT_NEAR(lc(0, 1), std::log((2.0 / 3 + 2 + 1) / (2 + 2 + 2.0)), 1e-12);
}

TEST(SelfSupervision, ClassifyByColourIsNaiveBayesOnTheColourWordsWithTheMotPrior) {
  // Words 0-2 are SIFT words, 3 and 4 colour words. Class 0's three views are colour 3 (2, 1 and
  // 1 tokens), class 1's two views colour 4, and their SIFT words alike. The prior (views) is
  // 3/5 and 2/5. The colour corpus's views have 6 tokens, 1.2 the mean: weights 0.6, 1.2, 1.2,
  // 1.2, 1.2, so class 0's colour counts are 1 + 1.2 + 1.2 + 1.2 = 4.6 and 1 (add-one), class
  // 1's 1 and 1 + 2.4 = 3.4.
  topics::Corpus training(5);
  training.add_tokens(std::vector<std::int32_t>{0, 1, 3, 3});
  training.add_tokens(std::vector<std::int32_t>{0, 3});
  training.add_tokens(std::vector<std::int32_t>{1, 3});
  training.add_tokens(std::vector<std::int32_t>{0, 1, 4});
  training.add_tokens(std::vector<std::int32_t>{0, 4});
  const std::vector<int> labels{0, 0, 0, 1, 1};
  topics::BatchLdaOptions bo;
  bo.num_topics = 2;
  bo.seed = 3;
  const topics::LdaModel lda = topics::train_batch_lda(training, bo).model;
  const topics::MotModel model =
      topics::fit_mot(recognition::document_theta(lda, training).theta, labels, {"c0", "c1"}, {})
          .model;
  const Eigen::VectorXd lp = model.log_prior();
  ASSERT_NEAR(lp(0), std::log(0.6), 1e-12);
  ASSERT_NEAR(lp(1), std::log(0.4), 1e-12);
  const Eigen::MatrixXd lc = colour_multinomials(training, labels, 2, 3);
  ASSERT_EQ(lc.rows(), 2);
  ASSERT_EQ(lc.cols(), 2);
  const double l0 = std::log(4.6 / 5.6);
  const double l1 = std::log(1 / 5.6);
  const double k0 = std::log(1 / 4.4);
  const double k1 = std::log(3.4 / 4.4);
  EXPECT_NEAR(lc(0, 0), l0, 1e-12);
  EXPECT_NEAR(lc(0, 1), l1, 1e-12);
  EXPECT_NEAR(lc(1, 0), k0, 1e-12);
  EXPECT_NEAR(lc(1, 1), k1, 1e-12);
  // Held out: one colour-3 token (class 0); two colour-4 tokens with class 0's SIFT words
  // (class 1: the SIFT words count for nothing); one colour-4 token (class 1: its p(w | c) is
  // 4.3 times class 0's, the prior's odds 1.5); no colour word (the prior's class, 0).
  topics::Corpus held(5);
  held.add_tokens(std::vector<std::int32_t>{2, 3});
  held.add_tokens(std::vector<std::int32_t>{0, 0, 1, 4, 4});
  held.add_tokens(std::vector<std::int32_t>{2, 4});
  held.add_tokens(std::vector<std::int32_t>{0, 1, 2});
  const topics::MotClassification c = classify_by_colour(model, lc, held, 3);
  EXPECT_EQ(c.predicted, (std::vector<int>{0, 1, 1, 0}));
  const double p0 = std::log(0.6);
  const double p1 = std::log(0.4);
  const Eigen::MatrixXd want = (Eigen::MatrixXd(4, 2) << p0 + l0, p1 + k0, p0 + 2 * l1, p1 + 2 * k1,
                                p0 + l1, p1 + k1, p0, p1)
                                   .finished();
  ASSERT_EQ(c.log_score.rows(), 4);
  ASSERT_EQ(c.log_score.cols(), 2);
  EXPECT_LT((c.log_score - want).cwiseAbs().maxCoeff(), 1e-12) << c.log_score;
  EXPECT_NEAR(c.posterior.row(0).sum(), 1.0, 1e-12);
  // The same classes as learn's colour figure (pool_word_multinomials at weight 1 with the MoT's
  // scores by words, whose term then weighs nothing).
  const topics::MotClassification learn_way = topics::pool_word_multinomials(
      model, topics::classify_mot_words(model, lda, held), lc, words_from(held, 3), 1.0);
  EXPECT_EQ(learn_way.predicted, c.predicted);
  EXPECT_LT((learn_way.log_score - c.log_score).cwiseAbs().maxCoeff(), 1e-9);
  // Bad input: colour words from past the documents' words; multinomials of another size.
  EXPECT_THROW((void)classify_by_colour(model, lc, held, 5), Error);
  EXPECT_THROW((void)classify_by_colour(model, lc, held, 2), Error);  // 3 words, lc has 2
  EXPECT_THROW((void)classify_by_colour(model, lc.topRows(1), held, 3), Error);
}

TEST(SelfSupervision, PushedMostNamesByPushesThenViewsThenName) {
  const auto push = [](int round, const char* intended, int views, const char* shown,
                       bool executed = true) {
    PushTruth p;
    p.round = round;
    p.phase = "learn";
    p.intended = intended;
    p.executed = executed;
    p.views = views;
    p.view_truth = shown;
    return p;
  };
  std::vector<PushTruth> pushes{
      // Round 0: three pushes to three objects (a 1-1-1 tie); the views show the giraffe most.
      push(0, "bottle", 2, "bottle"), push(0, "book", 1, "book"), push(0, "giraffe", 5, "giraffe"),
      // Round 1: the bottle twice, the book once with many views: pushes come first.
      push(1, "bottle", 1, "bottle"), push(1, "bottle", 1, "bottle"), push(1, "book", 9, "book"),
      // Round 2: a tie in pushes and in views: the first by name.
      push(2, "cd", 3, "cd"), push(2, "book", 3, "book"),
      // Round 3: views of an object no push was aimed at do not name it; a push not executed
      // does not count.
      push(3, "cd", 0, "giraffe"), push(3, "cd", 0, "", false), push(3, "book", 2, "giraffe")};
  pushes.push_back(push(4, "book", 4, "book"));
  pushes.back().phase = "clear";  // clearing pushes name nothing
  const auto round = [&pushes](int r) {
    return pushed_most(pushes, [r](int x) { return x == r; });
  };
  EXPECT_EQ(round(0), "giraffe");  // by name alone it was "book"
  EXPECT_EQ(round(1), "bottle");
  EXPECT_EQ(round(2), "book");
  EXPECT_EQ(round(3), "book");  // 1-1 tie; "giraffe" was shown but never aimed at
  EXPECT_EQ(round(4), "");
  EXPECT_EQ(round(5), "");
  EXPECT_EQ(pushed_most(pushes, [](int x) { return x <= 1; }), "bottle");  // 3 pushes of 6
}

// crowded_reclears (session 46): a round whose (c) stopped "crowded" runs (b) again about its
// object and goes on with (c); the ground truth's singulation is scored only by the round's first
// (b) (no cleared() after the round's first learn push). Off, the round stops there. Refused
// without learn_clearance.
class PhaseRecorder final : public TableAttendant {
 public:
  std::string rescatter(int round) override { return "re-scatter " + std::to_string(round); }
  void before_push(const PushIntent& intent) override {
    if (intent.phase == "learn") learned.insert(intent.round);
  }
  void cleared(int round, const planning::PlanningView& /*view*/, int /*blob*/) override {
    if (learned.contains(round)) ++cleared_in_learn;
  }
  std::set<int> learned;  // rounds with a learn push so far
  int cleared_in_learn = 0;
};

TEST(SelfSupervision, ACrowdedRoundClearsAgainAndGoesOn) {
  SelfSupervisionOptions o = small_options();
  o.objects = "book,bottle,giraffe";
  o.pushes = 4;
  o.learn_clearance = 0.2;  // every side toward the other object: rounds stop crowded
  const auto run = [](const SelfSupervisionOptions& opt, PhaseRecorder& attendant) {
    const sim::ObjectCatalogue catalogue = sim::ObjectCatalogue::load_default();
    sim::SimulatedRobot robot(table_of(opt), catalogue);
    const TinyModel m = tiny_model(robot.look().image);
    return learn_by_pushing(robot, attendant, 3, m.lda, m.vocabulary, opt, {});
  };
  const std::string stopped = "no learn push keeps clear of the other blobs";
  const auto is_reclear = [](const SelfSupervisionDecision& j) {
    return j.event == "replan" && j.why && j.why->starts_with("(c) stopped crowded");
  };
  PhaseRecorder off_attendant;
  const Learning off = run(o, off_attendant);
  ASSERT_TRUE(logged(off, "crowded")) << "the table did not crowd: the test is void";
  for (const auto& j : off.log) {
    EXPECT_FALSE(is_reclear(j));
    if (j.fault == "crowded") {
      EXPECT_EQ(off.stop_reasons.at(static_cast<std::size_t>(*j.round)), stopped);
    }
  }

  o.crowded_reclears = 1;
  PhaseRecorder on_attendant;
  const Learning on = run(o, on_attendant);
  std::map<int, int> reclears;
  for (std::size_t i = 0; i < on.log.size(); ++i) {
    const auto& j = on.log[i];
    if (!is_reclear(j)) continue;
    ASSERT_TRUE(j.round);
    ++reclears[*j.round];
    ASSERT_GT(i, 0U);
    EXPECT_EQ(on.log[i - 1].fault, std::optional<std::string>("crowded"));
    // (b) again: its look comes next.
    const auto next = std::find_if(on.log.begin() + static_cast<std::ptrdiff_t>(i) + 1,
                                   on.log.end(), [](const auto& k) { return k.event == "look"; });
    ASSERT_NE(next, on.log.end());
    EXPECT_EQ(next->phase, std::optional<std::string>("clear"));
  }
  ASSERT_FALSE(reclears.empty()) << "no round cleared again";
  for (const auto& [r, n] : reclears) EXPECT_LE(n, 1) << "round " << r;
  // A round that cleared again after a learn push: its (b) then would have been scored.
  bool learned_before = false;
  for (const auto& [r, n] : reclears) learned_before |= on_attendant.learned.contains(r);
  ASSERT_TRUE(learned_before) << "every re-clear came before any learn push: the test is void";
  EXPECT_EQ(on_attendant.cleared_in_learn, 0);

  o.learn_clearance = 0;
  EXPECT_THROW(o.validate(), Error);
}

}  // namespace
}  // namespace proprio::loop
