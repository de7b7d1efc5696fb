// The Mixture of Topics (thesis 7.1, 7.3.3, 8.1.2): supervised, unsupervised and online fits on
// theta drawn from known Dirichlets, the posterior of eq 7.3, and bad input.
#include "proprio/topics/mixture_of_topics.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <numeric>
#include <string>
#include <vector>

#include "../support/error_of.hpp"
#include "proprio/core/error.hpp"
#include "proprio/core/random.hpp"

namespace proprio::topics {
namespace {

using test::error_of;

::testing::AssertionResult has(const std::string& text, const std::string& part) {
  if (text.find(part) != std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << '"' << text << "\" does not contain \"" << part << '"';
}

/// Three objects over T = 5 topics, each concentrated on its own topics (as LDA's theta of views
/// of distinct objects), with some overlap.
std::vector<Eigen::VectorXd> three_objects() {
  Eigen::VectorXd a(5), b(5), c(5);
  a << 4.0, 1.0, 0.3, 0.3, 0.5;
  b << 0.5, 3.0, 3.0, 0.3, 0.4;
  c << 0.4, 0.4, 0.6, 5.0, 2.0;
  return {a, b, c};
}

struct Views {
  Eigen::MatrixXd theta;
  std::vector<int> labels;
};

Views draw(const std::vector<Eigen::VectorXd>& alphas, int per_object, std::uint64_t seed) {
  core::Rng rng(seed);
  const int t = static_cast<int>(alphas[0].size());
  Views v;
  v.theta.resize(static_cast<Eigen::Index>(alphas.size()) * per_object, t);
  Eigen::Index r = 0;
  for (std::size_t c = 0; c < alphas.size(); ++c) {
    const Dirichlet dir(alphas[c]);
    for (int i = 0; i < per_object; ++i) {
      v.theta.row(r++) = dir.sample(rng).transpose();
      v.labels.push_back(static_cast<int>(c));
    }
  }
  return v;
}

double accuracy(const std::vector<int>& predicted, const std::vector<int>& truth) {
  int right = 0;
  for (std::size_t i = 0; i < truth.size(); ++i) right += predicted[i] == truth[i] ? 1 : 0;
  return static_cast<double>(right) / static_cast<double>(truth.size());
}

/// The accuracy of a clustering under the best matching of clusters to classes (3 classes).
double best_permutation_accuracy(const std::vector<int>& clusters, const std::vector<int>& truth,
                                 int k) {
  std::vector<int> perm(static_cast<std::size_t>(k));
  std::iota(perm.begin(), perm.end(), 0);
  double best = 0;
  do {
    int right = 0;
    for (std::size_t i = 0; i < truth.size(); ++i) {
      right += perm[static_cast<std::size_t>(clusters[i])] == truth[i] ? 1 : 0;
    }
    best = std::max(best, static_cast<double>(right) / static_cast<double>(truth.size()));
  } while (std::next_permutation(perm.begin(), perm.end()));
  return best;
}

double max_relative_error(const Eigen::VectorXd& got, const Eigen::VectorXd& want) {
  return ((got - want).array().abs() / want.array()).maxCoeff();
}

const std::vector<std::string> kNames{"book", "bottle", "giraffe"};

TEST(MixtureOfTopics, SupervisedFitRecoversEachObjectsDirichlet) {
  const auto alphas = three_objects();
  const Views train = draw(alphas, 3000, 1);
  const MotFit fit = fit_mot(train.theta, train.labels, kNames);
  ASSERT_EQ(fit.model.num_classes(), 3);
  EXPECT_EQ(fit.model.num_topics(), 5);
  EXPECT_EQ(fit.summary.views, 9000);
  for (int c = 0; c < 3; ++c) {
    EXPECT_EQ(fit.model.objects[c].name, kNames[c]);
    EXPECT_LT(max_relative_error(fit.model.objects[c].dirichlet.alpha(), alphas[c]), 0.1) << c;
    EXPECT_TRUE(fit.summary.fits[c].converged);
  }
  EXPECT_TRUE(std::isfinite(fit.summary.log_likelihood));
}

TEST(MixtureOfTopics, ClassifiesHeldOutViewsNearlyAsTheTrueModelDoes) {
  const auto alphas = three_objects();
  const Views train = draw(alphas, 300, 2);
  const Views test = draw(alphas, 500, 3);
  const MotFit fit = fit_mot(train.theta, train.labels, kNames);
  const MotClassification got = classify_mot(fit.model, test.theta);

  // The Bayes classifier with the true alphas: the best any classifier can do.
  MotModel truth;
  for (int c = 0; c < 3; ++c) truth.objects.push_back({kNames[c], {}, Dirichlet(alphas[c]), 1.0});
  const MotClassification ideal = classify_mot(truth, test.theta);
  const double acc = accuracy(got.predicted, test.labels);
  const double ideal_acc = accuracy(ideal.predicted, test.labels);
  std::cout << "MoT accuracy " << acc << ", Bayes with the true alphas " << ideal_acc << '\n';
  EXPECT_GT(acc, 0.9);
  EXPECT_GT(acc, ideal_acc - 0.01);
  ASSERT_EQ(got.posterior.rows(), test.theta.rows());
  for (Eigen::Index d = 0; d < got.posterior.rows(); ++d) {
    EXPECT_NEAR(got.posterior.row(d).sum(), 1.0, 1e-12);
    EXPECT_TRUE(got.posterior.row(d).allFinite());
  }
}

TEST(MixtureOfTopics, PosteriorIsBayesOverTheDirichlets) {  // eq 7.3
  Eigen::VectorXd a(3), b(3);
  a << 2.0, 1.0, 1.0;
  b << 1.0, 1.0, 3.0;
  MotModel m;
  m.objects.push_back({"a", {}, Dirichlet(a), 3.0});
  m.objects.push_back({"b", {}, Dirichlet(b), 1.0});
  Eigen::MatrixXd theta(1, 3);
  theta << 0.5, 0.3, 0.2;
  const double la = Dirichlet(a).log_density(theta.row(0).transpose()) + std::log(0.75);
  const double lb = Dirichlet(b).log_density(theta.row(0).transpose()) + std::log(0.25);
  const MotClassification got = classify_mot(m, theta);
  EXPECT_NEAR(got.posterior(0, 0), std::exp(la) / (std::exp(la) + std::exp(lb)), 1e-12);
  EXPECT_NEAR(got.log_score(0, 1), lb, 1e-12);
  EXPECT_EQ(got.predicted[0], la > lb ? 0 : 1);

  m.prior = MotPrior::kUniform;
  const double ua = la - std::log(0.75) + std::log(0.5);
  const double ub = lb - std::log(0.25) + std::log(0.5);
  EXPECT_NEAR(classify_mot(m, theta).posterior(0, 1), std::exp(ub) / (std::exp(ua) + std::exp(ub)),
              1e-12);
}

TEST(MixtureOfTopics, SmoothingIsAppliedInFittingAndKeptForClassifying) {
  const Views train = draw(three_objects(), 60, 11);
  MotOptions o;
  o.smoothing = 0.05;
  const MotFit fit = fit_mot(train.theta, train.labels, kNames, o);
  EXPECT_EQ(fit.model.smoothing, 0.05);
  // The statistics are those of log((1 - s) theta + s / T).
  const Eigen::MatrixXd smoothed = (0.95 * train.theta.array() + 0.01).matrix();
  Eigen::VectorXd mean = Eigen::VectorXd::Zero(5);
  for (int d = 0; d < 60; ++d) mean += smoothed.row(d).array().log().matrix().transpose();
  EXPECT_LT((fit.model.objects[0].stats.mean_log() - mean / 60.0).cwiseAbs().maxCoeff(), 1e-12);
  // classify_mot applies the model's smoothing: the same scores as the unsmoothed model of the
  // smoothed theta.
  MotModel plain = fit.model;
  plain.smoothing = 0;
  const MotClassification a = classify_mot(fit.model, train.theta.topRows(5));
  const MotClassification b = classify_mot(plain, smoothed.topRows(5));
  EXPECT_LT((a.log_score - b.log_score).cwiseAbs().maxCoeff(), 1e-9);
  // Exact zeros stay finite, and the smoothing bound is enforced.
  Eigen::MatrixXd zero = train.theta.topRows(1);
  zero.row(0) << 1.0, 0.0, 0.0, 0.0, 0.0;
  EXPECT_TRUE(classify_mot(fit.model, zero).log_score.allFinite());
  o.smoothing = 0.51;
  EXPECT_THROW(o.validate(), Error);
}

TEST(MixtureOfTopics, ZerosInThetaAreFlooredNotNaN) {
  const Views train = draw(three_objects(), 50, 4);
  Eigen::MatrixXd theta = train.theta;
  theta.row(0) << 1.0, 0.0, 0.0, 0.0, 0.0;
  const MotFit fit = fit_mot(theta, train.labels, kNames);
  const MotClassification got = classify_mot(fit.model, theta.topRows(3));
  EXPECT_TRUE(got.posterior.allFinite());
  EXPECT_TRUE(got.log_score.allFinite());
}

TEST(MixtureOfTopics, BadThetaIsAnErrorNamingTheRow) {
  const Views v = draw(three_objects(), 4, 5);
  Eigen::MatrixXd bad = v.theta;
  bad(3, 1) = -0.1;
  EXPECT_TRUE(has(error_of([&] { (void)fit_mot(bad, v.labels, kNames); }), "theta row 3, topic 1"));
  bad = v.theta;
  bad(7, 0) = std::nan("");
  EXPECT_TRUE(has(error_of([&] { (void)fit_mot_unsupervised(bad); }), "theta row 7"));
  bad = v.theta;
  bad.row(5) *= 0.9;
  EXPECT_TRUE(has(error_of([&] { (void)fit_mot(bad, v.labels, kNames); }), "theta row 5 sums to"));
  const MotFit fit = fit_mot(v.theta, v.labels, kNames);
  EXPECT_TRUE(has(error_of([&] { (void)classify_mot(fit.model, bad); }), "theta row 5"));
  EXPECT_TRUE(has(error_of([&] { (void)classify_mot(fit.model, v.theta.leftCols(4)); }),
                  "theta has 4 topics, the model 5"));
}

TEST(MixtureOfTopics, AnObjectWithFewerThanTwoViewsIsAnError) {
  const Views v = draw(three_objects(), 3, 6);
  std::vector<int> labels = v.labels;
  std::fill(labels.begin() + 3, labels.begin() + 5, -1);  // bottle keeps one view
  EXPECT_TRUE(has(error_of([&] { (void)fit_mot(v.theta, labels, kNames); }),
                  "object 'bottle' has 1 view(s)"));
  std::fill(labels.begin() + 3, labels.begin() + 6, -1);  // bottle has none
  EXPECT_TRUE(has(error_of([&] { (void)fit_mot(v.theta, labels, kNames); }),
                  "object 'bottle' has 0 view(s)"));
  labels = v.labels;
  labels[0] = 3;
  EXPECT_TRUE(has(error_of([&] { (void)fit_mot(v.theta, labels, kNames); }), "label 3 of row 0"));
  EXPECT_TRUE(has(error_of([&] { (void)fit_mot(v.theta, std::vector<int>(2, 0), kNames); }),
                  "2 labels for 9 theta rows"));
}

TEST(MixtureOfTopics, MoreObjectsThanViewsAllowIsAnError) {
  const Views v = draw(three_objects(), 3, 7);  // 9 views: at most 4 objects of 2 views
  MotOptions o;
  o.classes = 5;
  EXPECT_TRUE(
      has(error_of([&] { (void)fit_mot_unsupervised(v.theta, o); }), "5 objects from 9 views"));
  EXPECT_TRUE(
      has(error_of([&] { (void)fit_mot_unsupervised(v.theta.topRows(1), o); }), "1 view(s)"));
  o.classes = 4;
  EXPECT_NO_THROW((void)fit_mot_unsupervised(v.theta, o));
}

TEST(MixtureOfTopics, OptionsAreValidated) {
  MotOptions o;
  o.forgetting = 0;
  EXPECT_TRUE(has(error_of([&] { o.validate(); }), "forgetting"));
  o = {};
  o.kmeans_restarts = 0;
  EXPECT_TRUE(has(error_of([&] { o.validate(); }), "kmeans_restarts"));
  o = {};
  o.fit.tolerance = -1;
  EXPECT_TRUE(has(error_of([&] { o.validate(); }), "tolerance"));
}

TEST(MixtureOfTopics, UnsupervisedFindsTheObjectsWhenToldHowMany) {
  const Views v = draw(three_objects(), 200, 8);
  MotOptions o;
  o.classes = 3;
  const MotFit fit = fit_mot_unsupervised(v.theta, o);
  ASSERT_EQ(fit.model.num_classes(), 3);
  EXPECT_EQ(fit.model.objects[0].name, "object_1");
  const double acc = best_permutation_accuracy(fit.assignment, v.labels, 3);
  std::cout << "unsupervised clustering accuracy " << acc << ", hard-EM rounds "
            << fit.summary.refine_rounds << '\n';
  EXPECT_GT(acc, 0.9);
  // Deterministic for the seed.
  EXPECT_EQ(fit_mot_unsupervised(v.theta, o).assignment, fit.assignment);
}

TEST(MixtureOfTopics, BicChoosesTheNumberOfObjects) {
  MotOptions o;  // classes = 0: chosen
  o.max_classes = 6;
  const Views three = draw(three_objects(), 150, 9);
  const MotFit fit3 = fit_mot_unsupervised(three.theta, o);
  EXPECT_EQ(fit3.model.num_classes(), 3) << fit3.summary.brief();
  ASSERT_EQ(fit3.summary.bic.size(), 6U);
  EXPECT_EQ(
      std::min_element(fit3.summary.bic.begin(), fit3.summary.bic.end()) - fit3.summary.bic.begin(),
      2);

  const Views one = draw({three_objects()[1]}, 300, 10);
  EXPECT_EQ(fit_mot_unsupervised(one.theta, o).model.num_classes(), 1);
}

/// Two objects: "two-faced" seen in two poses (its views at topic 0 or topic 1), "between" whose
/// views mix topics 0 and 1. One Dirichlet for two-faced has alpha < 1 on both topics and is
/// high between them too; a mixture of two Dirichlets is not.
struct TwoFaced {
  Eigen::MatrixXd theta;
  std::vector<int> labels;
};

TwoFaced draw_two_faced(int per_object, std::uint64_t seed) {
  core::Rng rng(seed);
  Eigen::VectorXd a(4), b(4), c(4);
  a << 12.0, 1.0, 0.5, 0.5;
  b << 1.0, 12.0, 0.5, 0.5;
  c << 4.0, 4.0, 0.7, 0.7;
  TwoFaced v;
  v.theta.resize(2 * per_object, 4);
  for (int i = 0; i < 2 * per_object; ++i) {
    const bool first = i < per_object;
    const Eigen::VectorXd& alpha = first ? (rng.uniform() < 0.5 ? a : b) : c;
    v.theta.row(i) = Dirichlet(alpha).sample(rng).transpose();
    v.labels.push_back(first ? 0 : 1);
  }
  return v;
}

TEST(MixtureOfTopics, MixturesOfDirichletsFitObjectsSeenInSeveralPoses) {
  const TwoFaced train = draw_two_faced(400, 31);
  const TwoFaced test = draw_two_faced(400, 32);
  const std::vector<std::string> names{"two-faced", "between"};
  const MotFit one = fit_mot(train.theta, train.labels, names);
  MotOptions o;
  o.components = 5;
  const MotFit mixed = fit_mot(train.theta, train.labels, names, o);
  ASSERT_EQ(mixed.summary.mixtures.size(), 2U);
  EXPECT_EQ(mixed.summary.mixtures[0].components, 2) << mixed.summary.mixtures[0].brief();
  EXPECT_EQ(mixed.model.objects[0].mixture.num_components(), 2);
  // "between" is one Dirichlet: no mixture kept, its density is the plain fit's.
  EXPECT_EQ(mixed.summary.mixtures[1].components, 1) << mixed.summary.mixtures[1].brief();
  EXPECT_EQ(mixed.model.objects[1].mixture.num_components(), 0);
  EXPECT_EQ(mixed.model.objects[1].dirichlet.alpha(), one.model.objects[1].dirichlet.alpha());
  EXPECT_NE(mixed.summary.brief().find("components per object: 2 1"), std::string::npos)
      << mixed.summary.brief();
  const double acc_one = accuracy(classify_mot(one.model, test.theta).predicted, test.labels);
  const double acc_mixed = accuracy(classify_mot(mixed.model, test.theta).predicted, test.labels);
  std::cout << "one Dirichlet per object " << acc_one << ", mixtures " << acc_mixed << '\n';
  EXPECT_GT(acc_mixed, 0.93);  // the true model's Bayes accuracy is about 0.94 here
  EXPECT_GT(acc_mixed, acc_one + 0.03);
  EXPECT_GT(mixed.summary.log_likelihood, one.summary.log_likelihood);
  // components = 1 is the model of before, exactly.
  MotOptions plain;
  plain.components = 1;
  const MotFit again = fit_mot(train.theta, train.labels, names, plain);
  EXPECT_EQ(again.summary.log_likelihood, one.summary.log_likelihood);
  EXPECT_TRUE(again.summary.mixtures.empty());
}

TEST(MixtureOfTopics, MixtureObjectsUpdateOnline) {
  const TwoFaced first = draw_two_faced(300, 41);
  const TwoFaced second = draw_two_faced(300, 42);
  const TwoFaced test = draw_two_faced(400, 43);
  const std::vector<std::string> names{"two-faced", "between"};
  MotOptions o;
  o.components = 4;
  std::vector<std::string> labels;
  for (const int l : second.labels) labels.push_back(names[static_cast<std::size_t>(l)]);
  for (const auto rule : {MotUpdateRule::kExact, MotUpdateRule::kResample}) {
    MotFit fit = fit_mot(first.theta, first.labels, names, o);
    ASSERT_EQ(fit.model.objects[0].mixture.num_components(), 2);
    o.update = rule;
    const MotUpdateSummary s = update_mot(fit.model, second.theta, labels, o);
    EXPECT_EQ(s.mixtures.size(), 1U);  // only two-faced has a mixture
    const auto& m = fit.model.objects[0].mixture;
    ASSERT_GE(m.num_components(), 2);
    EXPECT_NO_THROW(m.validate());
    EXPECT_DOUBLE_EQ(fit.model.objects[0].views, 600.0);
    if (rule == MotUpdateRule::kExact) {
      double count = 0;
      for (const auto& c : m.components) count += c.stats.count();
      EXPECT_NEAR(count, 600.0, 1e-9);  // every new view merged with responsibilities summing to 1
    }
    EXPECT_GT(accuracy(classify_mot(fit.model, test.theta).predicted, test.labels), 0.92);
  }
}

TEST(MixtureOfTopics, SharedPrecisionGivesEveryObjectOnePrecision) {
  const auto alphas = three_objects();
  const Views train = draw(alphas, 300, 51);
  const Views test = draw(alphas, 300, 52);
  MotOptions o;
  o.shared_precision = true;
  const MotFit fit = fit_mot(train.theta, train.labels, kNames, o);
  ASSERT_TRUE(fit.summary.shared.has_value());
  EXPECT_TRUE(fit.summary.shared->converged) << fit.summary.shared->brief();
  const double s = fit.summary.shared->precision;
  for (const auto& obj : fit.model.objects) EXPECT_NEAR(obj.dirichlet.precision(), s, 1e-9 * s);
  // The objects' own precisions are 6.1, 7.2 and 8.4: the shared one lies among them.
  EXPECT_GT(s, 5.5);
  EXPECT_LT(s, 9.0);
  EXPECT_GT(accuracy(classify_mot(fit.model, test.theta).predicted, test.labels), 0.85);
  // The statistics stay each object's own, so an exact update refits jointly again.
  std::vector<std::string> names;
  for (const int l : test.labels) names.push_back(kNames[static_cast<std::size_t>(l)]);
  MotModel m = fit.model;
  (void)update_mot(m, test.theta, names, o);
  const double s2 = m.objects[0].dirichlet.precision();
  for (const auto& obj : m.objects) EXPECT_NEAR(obj.dirichlet.precision(), s2, 1e-9 * s2);
  o.components = 3;
  EXPECT_TRUE(has(error_of([&] { o.validate(); }), "shared_precision"));
}

TEST(MixtureOfTopics, ExactUpdateWithoutForgettingEqualsOneFitOfAllViews) {
  const auto alphas = three_objects();
  const Views first = draw(alphas, 40, 11);
  const Views second = draw(alphas, 30, 12);
  MotFit fit = fit_mot(first.theta, first.labels, kNames);
  std::vector<std::string> names;
  for (const int l : second.labels) names.push_back(kNames[l]);
  const MotUpdateSummary s = update_mot(fit.model, second.theta, names);
  EXPECT_EQ(s.views, 90);
  EXPECT_EQ(s.new_objects, 0);

  Eigen::MatrixXd all(first.theta.rows() + second.theta.rows(), 5);
  all << first.theta, second.theta;
  std::vector<int> labels = first.labels;
  labels.insert(labels.end(), second.labels.begin(), second.labels.end());
  const MotFit batch = fit_mot(all, labels, kNames);
  for (int c = 0; c < 3; ++c) {
    EXPECT_LT(max_relative_error(fit.model.objects[c].dirichlet.alpha(),
                                 batch.model.objects[c].dirichlet.alpha()),
              1e-6);
    EXPECT_DOUBLE_EQ(fit.model.objects[c].views, 70.0);
  }
}

TEST(MixtureOfTopics, UpdateAddsNewObjectsAndRefusesOneViewObjects) {
  const auto alphas = three_objects();
  const Views v = draw(alphas, 20, 13);
  std::vector<int> labels = v.labels;
  for (auto& l : labels) l = l == 2 ? -1 : l;
  MotFit fit = fit_mot(v.theta, labels, {"book", "bottle"});
  ASSERT_EQ(fit.model.num_classes(), 2);
  const MotModel before = fit.model;

  std::vector<std::string> names(static_cast<std::size_t>(v.theta.rows()));
  names[45] = "giraffe";  // one view of a new object
  EXPECT_TRUE(has(error_of([&] { (void)update_mot(fit.model, v.theta, names); }),
                  "new object 'giraffe' has 1 view(s)"));
  EXPECT_EQ(fit.model.num_classes(), 2);
  EXPECT_EQ(fit.model.objects[0].dirichlet.alpha(), before.objects[0].dirichlet.alpha());

  for (int d = 40; d < 60; ++d) names[static_cast<std::size_t>(d)] = "giraffe";
  const MotUpdateSummary s = update_mot(fit.model, v.theta, names);
  EXPECT_EQ(s.new_objects, 1);
  ASSERT_EQ(fit.model.num_classes(), 3);
  EXPECT_EQ(fit.model.objects[2].name, "giraffe");
}

/// The two online rules on a stream of batches of new views: the relative error of alpha after
/// each, for a fixed object (stationary) and for one whose Dirichlet changes halfway (drift).
struct StreamErrors {
  double stationary = 0;
  double drift = 0;
};

StreamErrors run_stream(MotUpdateRule rule, double forgetting) {
  Eigen::VectorXd a(4), b(4);
  a << 3.0, 1.0, 0.5, 0.5;
  b << 0.5, 0.5, 1.0, 3.0;
  constexpr int kBatches = 20;
  constexpr int kBatchViews = 20;
  StreamErrors out;
  for (const bool drift : {false, true}) {
    double err = 0;
    for (std::uint64_t rep = 0; rep < 10; ++rep) {
      const Views first = draw({a}, kBatchViews, 100 + rep);
      MotModel m = fit_mot(first.theta, first.labels, {"o"}).model;
      MotOptions o;
      o.update = rule;
      o.forgetting = forgetting;
      for (int i = 1; i < kBatches; ++i) {
        const Eigen::VectorXd& now = drift && i >= kBatches / 2 ? b : a;
        const Views batch = draw({now}, kBatchViews, 1000 * (rep + 1) + i);
        o.seed = 7 * rep + i;
        (void)update_mot(m, batch.theta, std::vector<std::string>(kBatchViews, "o"), o);
      }
      err += max_relative_error(m.objects[0].dirichlet.alpha(), drift ? b : a);
    }
    (drift ? out.drift : out.stationary) = err / 10;
  }
  return out;
}

TEST(MixtureOfTopics, ExactUpdateBeatsResamplingOnAStationaryObject) {
  const StreamErrors exact = run_stream(MotUpdateRule::kExact, 1.0);
  const StreamErrors forget = run_stream(MotUpdateRule::kExact, 0.5);
  const StreamErrors resample = run_stream(MotUpdateRule::kResample, 1.0);
  std::cout << "mean max relative alpha error after 20 batches of 20 views (stationary, drift "
               "halfway):\n  exact "
            << exact.stationary << ", " << exact.drift << "\n  exact, forgetting 0.5 "
            << forget.stationary << ", " << forget.drift << "\n  resample (50:50) "
            << resample.stationary << ", " << resample.drift << '\n';
  EXPECT_LT(exact.stationary, resample.stationary);
  EXPECT_LT(forget.drift, exact.drift);  // forgetting follows an object that changes
}

// Two objects over two topics: a mostly topic 0 (Dir(6, 1.5)), b mostly topic 1 (Dir(1.5, 6)),
// b three times as likely a priori.
MotModel two_object_model() {
  Eigen::VectorXd a(2), b(2);
  a << 6.0, 1.5;
  b << 1.5, 6.0;
  MotModel m;
  m.objects.push_back({"a", {}, Dirichlet(a), 1.0});
  m.objects.push_back({"b", {}, Dirichlet(b), 3.0});
  return m;
}

// Two topics over three words: beta_0 = (0.6, 0.2, 0.2), beta_1 = (0.2, 0.2, 0.6).
LdaModel two_topic_lda() {
  LdaModel m;
  m.lambda.resize(2, 3);
  m.lambda << 3.0, 1.0, 1.0, 1.0, 1.0, 3.0;
  m.alpha = 0.5;
  m.eta = 0.1;
  return m;
}

// log p(words | Beta(a0, a1)) for two topics, by Simpson's rule over theta_0 in (0, 1).
double exact_two_topic_marginal(const LdaModel& lda, double a0, double a1,
                                const std::vector<std::int32_t>& words,
                                const std::vector<std::int32_t>& counts) {
  const Eigen::MatrixXd beta = lda.topic_word();
  const int n = 20000;
  const double h = 1.0 / n;
  const double log_b = std::lgamma(a0 + a1) - std::lgamma(a0) - std::lgamma(a1);
  double sum = 0;
  for (int i = 0; i <= n; ++i) {
    const double t = std::clamp(i * h, 1e-12, 1 - 1e-12);
    double l = log_b + (a0 - 1) * std::log(t) + (a1 - 1) * std::log(1 - t);
    for (std::size_t j = 0; j < words.size(); ++j)
      l += counts[j] * std::log(t * beta(0, words[j]) + (1 - t) * beta(1, words[j]));
    sum += (i == 0 || i == n ? 1 : (i % 2 == 1 ? 4 : 2)) * std::exp(l);
  }
  return std::log(sum * h / 3);
}

TEST(MixtureOfTopics, WordsBoundIsBelowTheExactMarginalAndExactForSeparateTopics) {
  Eigen::VectorXd a(2);
  a << 2.0, 1.5;
  MotModel m;
  m.objects.push_back({"a", {}, Dirichlet(a), 1.0});
  const std::vector<std::vector<std::int32_t>> words{{0}, {0, 2}, {0, 1, 2}};
  const std::vector<std::vector<std::int32_t>> counts{{1}, {3, 1}, {5, 2, 5}};
  Corpus corpus(3);
  for (std::size_t d = 0; d < words.size(); ++d) corpus.add_document(words[d], counts[d]);
  // Topics that share words: the mean-field bound is below the marginal (a gap under a tenth
  // of a nat per token here: 0.05-0.08).
  const MotClassification c = classify_mot_words(m, two_topic_lda(), corpus);
  // Topics with (nearly) no word in common: each word's topic is known, the posterior of theta is
  // the Dirichlet alpha + counts, and the bound is exact.
  LdaModel apart = two_topic_lda();
  apart.lambda << 1e4, 1e4, 1e-4, 1e-4, 1e-4, 1e4;
  const MotClassification e = classify_mot_words(m, apart, corpus);
  for (std::size_t d = 0; d < words.size(); ++d) {
    const auto i = static_cast<Eigen::Index>(d);  // log p(c) = 0: the scores are the bounds
    const double exact = exact_two_topic_marginal(two_topic_lda(), 2.0, 1.5, words[d], counts[d]);
    std::cout << "document " << d << ": bound " << c.log_score(i, 0) << ", exact " << exact << '\n';
    EXPECT_LE(c.log_score(i, 0), exact + 1e-6) << d;
    EXPECT_GT(c.log_score(i, 0), exact - 0.1 * static_cast<double>(corpus.document(d).tokens()));
    EXPECT_NEAR(e.log_score(i, 0), exact_two_topic_marginal(apart, 2.0, 1.5, words[d], counts[d]),
                1e-3)
        << d;
  }
}

TEST(MixtureOfTopics, ClassifiesDocumentsByTheirWords) {
  // Two objects over two topics: a mostly topic 0, b mostly topic 1. Each document: theta from
  // its object's Dirichlet, 30 words from that mixture of the topics (LDA's generative process).
  const MotModel m = two_object_model();
  const LdaModel lda = two_topic_lda();
  const Eigen::MatrixXd beta = lda.topic_word();
  core::Rng rng(5);
  Corpus corpus(3);
  std::vector<int> truth;
  std::uniform_real_distribution<double> u(0, 1);
  for (int d = 0; d < 200; ++d) {
    const int c = d % 2;
    const Eigen::VectorXd theta = m.objects[static_cast<std::size_t>(c)].dirichlet.sample(rng);
    std::vector<std::int32_t> tokens;
    for (int n = 0; n < 30; ++n) {
      const int k = u(rng.engine()) < theta(0) ? 0 : 1;
      double r = u(rng.engine());
      int w = 0;
      while (w < 2 && r > beta(k, w)) r -= beta(k, w++);
      tokens.push_back(w);
    }
    corpus.add_tokens(tokens);
    truth.push_back(c);
  }
  corpus.add_document(std::span<const std::int32_t>{}, std::span<const std::int32_t>{});
  const MotClassification got = classify_mot_words(m, lda, corpus);
  ASSERT_EQ(got.posterior.rows(), 201);
  std::vector<int> predicted(got.predicted.begin(), got.predicted.end() - 1);
  EXPECT_GT(accuracy(predicted, truth), 0.8);
  for (Eigen::Index d = 0; d < got.posterior.rows(); ++d)
    EXPECT_NEAR(got.posterior.row(d).sum(), 1.0, 1e-12);
  // The empty document: the prior (views 1 and 3).
  EXPECT_NEAR(got.posterior(200, 0), 0.25, 1e-12);
  EXPECT_THROW((void)classify_mot_words(m, lda, Corpus(4)), Error);
  MotModel three = m;
  Eigen::VectorXd t3(3);
  t3 << 1, 1, 1;
  for (auto& o : three.objects) o.dirichlet = Dirichlet(t3);
  EXPECT_THROW((void)classify_mot_words(three, lda, corpus), Error);
}

// Each object's word multinomial: pooled counts plus the pseudo-count, normalised (known
// answers); a label < 0 leaves its document out.
TEST(MixtureOfTopics, WordMultinomialsArePooledCountsPlusThePseudoCount) {
  Corpus corpus(3);
  corpus.add_document(std::vector<std::int32_t>{0, 1}, std::vector<std::int32_t>{2, 1});  // 0
  corpus.add_document(std::vector<std::int32_t>{2}, std::vector<std::int32_t>{3});        // 1
  corpus.add_document(std::vector<std::int32_t>{0}, std::vector<std::int32_t>{9});        // out
  const std::vector<int> labels{0, 1, -1};
  const Eigen::MatrixXd p = fit_word_multinomials(corpus, labels, 2);
  ASSERT_EQ(p.rows(), 2);
  ASSERT_EQ(p.cols(), 3);
  EXPECT_NEAR(p(0, 0), std::log(3.0 / 6), 1e-12);
  EXPECT_NEAR(p(0, 1), std::log(2.0 / 6), 1e-12);
  EXPECT_NEAR(p(0, 2), std::log(1.0 / 6), 1e-12);
  EXPECT_NEAR(p(1, 0), std::log(1.0 / 6), 1e-12);
  EXPECT_NEAR(p(1, 2), std::log(4.0 / 6), 1e-12);
  const Eigen::MatrixXd half = fit_word_multinomials(corpus, labels, 3, 0.5);
  EXPECT_NEAR(half(0, 0), std::log(2.5 / 4.5), 1e-12);
  EXPECT_NEAR(half(2, 1), std::log(1.0 / 3), 1e-12);  // no document: uniform
  EXPECT_THROW((void)fit_word_multinomials(corpus, std::vector<int>{0, 2, -1}, 2), Error);
  EXPECT_THROW((void)fit_word_multinomials(corpus, std::vector<int>{0, 1}, 2), Error);
  EXPECT_THROW((void)fit_word_multinomials(corpus, labels, 2, 0.0), Error);
  EXPECT_THROW((void)fit_word_multinomials(corpus, labels, 0), Error);
}

// The pooled score (1 - w) (MoT by words - log p(c)) + w sum log p(word | c) + log p(c): known
// answers by hand; w = 0 is classify_mot_words, w = 1 naive Bayes with the MoT's prior.
TEST(MixtureOfTopics, PoolingWithWordMultinomialsWeighsTheTwoScores) {
  const MotModel m = two_object_model();
  const LdaModel lda = two_topic_lda();
  Corpus corpus(3);
  corpus.add_document(std::vector<std::int32_t>{0, 2}, std::vector<std::int32_t>{4, 1});
  corpus.add_document(std::vector<std::int32_t>{1}, std::vector<std::int32_t>{2});
  corpus.add_document(std::span<const std::int32_t>{}, std::span<const std::int32_t>{});
  const MotClassification words = classify_mot_words(m, lda, corpus);
  Eigen::MatrixXd log_phi(2, 3);
  log_phi << std::log(0.1), std::log(0.1), std::log(0.8),  // object a: mostly word 2
      std::log(0.7), std::log(0.2), std::log(0.1);         // object b: mostly word 0
  const Eigen::VectorXd log_p = m.log_prior();
  for (const double w : {0.0, 0.3, 1.0}) {
    const MotClassification got = pool_word_multinomials(m, words, log_phi, corpus, w);
    ASSERT_EQ(got.log_score.rows(), 3);
    for (int c = 0; c < 2; ++c) {
      const double mot0 = words.log_score(0, c) - log_p(c);
      const double mot1 = words.log_score(1, c) - log_p(c);
      const double multi0 = 4 * log_phi(c, 0) + log_phi(c, 2);
      const double multi1 = 2 * log_phi(c, 1);
      EXPECT_NEAR(got.log_score(0, c), (1 - w) * mot0 + w * multi0 + log_p(c), 1e-9) << w;
      EXPECT_NEAR(got.log_score(1, c), (1 - w) * mot1 + w * multi1 + log_p(c), 1e-9) << w;
      EXPECT_NEAR(got.log_score(2, c), log_p(c), 1e-12) << w;  // empty: the prior
    }
    for (Eigen::Index d = 0; d < 3; ++d) EXPECT_NEAR(got.posterior.row(d).sum(), 1.0, 1e-12);
    if (w == 0.0) {
      EXPECT_EQ(got.predicted, words.predicted);
    }
  }
  // Word 0 four times: naive Bayes says b (0.7 against 0.1) whatever the MoT says.
  EXPECT_EQ(pool_word_multinomials(m, words, log_phi, corpus, 1.0).predicted[0], 1);
  EXPECT_THROW((void)pool_word_multinomials(m, words, log_phi, corpus, -0.1), Error);
  EXPECT_THROW((void)pool_word_multinomials(m, words, log_phi, corpus, 1.5), Error);
  EXPECT_THROW((void)pool_word_multinomials(m, words, log_phi.leftCols(2), corpus, 0.5), Error);
  EXPECT_THROW((void)pool_word_multinomials(m, words, log_phi.topRows(1), corpus, 0.5), Error);
  MotClassification short_words = words;
  short_words.log_score.conservativeResize(2, 2);
  EXPECT_THROW((void)pool_word_multinomials(m, short_words, log_phi, corpus, 0.5), Error);
}

// Session 30: word 0 is the table, in every object's views (a: 20 %, b: 80 %); words 1 and 2
// are a's and b's own. A view of a with mostly table (8 table, 2 of a's words: a thin object's
// view) goes to b by the add-one multinomials (b's views hold most table) and to a with the
// shared background, which scores the view at its own share of table.
TEST(MixtureOfTopics, SharedBackgroundStopsTheTableVotingForAnObject) {
  Corpus train(3);
  std::vector<int> labels;
  for (int i = 0; i < 10; ++i) {
    train.add_document(std::vector<std::int32_t>{0, 1}, std::vector<std::int32_t>{2, 8});
    labels.push_back(0);
    train.add_document(std::vector<std::int32_t>{0, 2}, std::vector<std::int32_t>{8, 2});
    labels.push_back(1);
  }
  Corpus test(3);
  test.add_document(std::vector<std::int32_t>{0, 1}, std::vector<std::int32_t>{8, 2});  // a
  test.add_document(std::vector<std::int32_t>{0, 2}, std::vector<std::int32_t>{1, 3});  // b
  test.add_document(std::span<const std::int32_t>{}, std::span<const std::int32_t>{});
  const Eigen::MatrixXd log_phi = fit_word_multinomials(train, labels, 2);
  const auto plain = [&](Eigen::Index d, Eigen::Index c) {
    const DocumentView doc = test.document(static_cast<std::size_t>(d));
    double l = 0;
    for (std::size_t i = 0; i < doc.size(); ++i) l += doc.counts[i] * log_phi(c, doc.words[i]);
    return l;
  };
  EXPECT_GT(plain(0, 1), plain(0, 0));  // the table votes for b

  const BackgroundWordModel m = fit_background_word_model(train, labels, 2);
  ASSERT_EQ(m.log_object.rows(), 2);
  ASSERT_EQ(m.log_object.cols(), 3);
  ASSERT_EQ(m.log_background.size(), 3);
  EXPECT_NEAR(m.log_background.array().exp().sum(), 1.0, 1e-12);
  for (Eigen::Index c = 0; c < 2; ++c)
    EXPECT_NEAR(m.log_object.row(c).array().exp().sum(), 1.0, 1e-12);
  // The background is mostly table; b's training share of it is larger than a's.
  EXPECT_GT(m.log_background(0), std::log(0.8));
  EXPECT_GT(m.background_share(1), m.background_share(0));
  // Each object's own word gains once the background explains part of the table.
  EXPECT_GT(m.log_object(0, 1), log_phi(0, 1));
  EXPECT_GT(m.log_object(1, 2), log_phi(1, 2));

  const Eigen::MatrixXd scores = background_word_scores(m, test);
  ASSERT_EQ(scores.rows(), 3);
  ASSERT_EQ(scores.cols(), 2);
  EXPECT_GT(scores(0, 0), scores(0, 1));  // the view of a: a
  EXPECT_GT(scores(1, 1), scores(1, 0));  // the view of b: b
  EXPECT_EQ(scores(2, 0), 0.0);           // empty: no evidence
  EXPECT_EQ(scores(2, 1), 0.0);
  // Each score is the best share's: no share in a grid of 101 does better.
  const Eigen::VectorXd bg = m.log_background.array().exp().matrix();
  for (Eigen::Index d = 0; d < 2; ++d) {
    for (Eigen::Index c = 0; c < 2; ++c) {
      const DocumentView doc = test.document(static_cast<std::size_t>(d));
      for (int k = 0; k <= 100; ++k) {
        const double s = k / 100.0;
        double l = 0;
        for (std::size_t i = 0; i < doc.size(); ++i) {
          l += doc.counts[i] *
               std::log(s * bg(doc.words[i]) + (1 - s) * std::exp(m.log_object(c, doc.words[i])));
        }
        EXPECT_LE(l, scores(d, c) + 1e-6) << d << " " << c << " " << s;
      }
    }
  }
  // Pooled at weight 1 with a flat MoT: the background scores decide.
  const MotModel mot = two_object_model();
  MotClassification flat;
  flat.log_score = Eigen::MatrixXd::Zero(3, 2);
  for (Eigen::Index d = 0; d < 3; ++d) flat.log_score.row(d) = mot.log_prior().transpose();
  const MotClassification pooled = pool_word_scores(mot, flat, scores, 1.0);
  EXPECT_EQ(pooled.predicted[0], 0);
  EXPECT_EQ(pooled.predicted[1], 1);
  EXPECT_NEAR(pooled.log_score(0, 1), scores(0, 1) + mot.log_prior()(1), 1e-12);

  EXPECT_THROW((void)fit_background_word_model(train, labels, 2, 1.0, 0), Error);
  EXPECT_THROW((void)fit_background_word_model(train, std::vector<int>{0}, 2), Error);
  EXPECT_THROW((void)background_word_scores(m, Corpus(4)), Error);
  EXPECT_THROW((void)background_word_scores(m, test, 0), Error);
  EXPECT_THROW((void)pool_word_scores(mot, flat, scores.leftCols(1), 1.0), Error);
  EXPECT_THROW((void)pool_word_scores(mot, flat, scores.topRows(2), 1.0), Error);
  EXPECT_THROW((void)pool_word_scores(mot, flat, scores, 1.5), Error);
}

TEST(MixtureOfTopics, WordsOfAMixtureObjectSumItsComponents) {
  Eigen::VectorXd a(2), b(2);
  a << 5.0, 1.0;
  b << 1.0, 5.0;
  MotModel one, two;
  one.objects.push_back({"a", {}, Dirichlet(a), 1.0});
  two.objects.push_back({"b", {}, Dirichlet(b), 1.0});
  MotModel mix;
  mix.objects.push_back({"m", {}, Dirichlet(a), 1.0});
  mix.objects[0].mixture.components = {{0.3, {}, Dirichlet(a)}, {0.7, {}, Dirichlet(b)}};
  Corpus corpus(3);
  const std::vector<std::int32_t> words{0, 2}, counts{4, 1};
  corpus.add_document(words, counts);
  const double la = classify_mot_words(one, two_topic_lda(), corpus).log_score(0, 0);
  const double lb = classify_mot_words(two, two_topic_lda(), corpus).log_score(0, 0);
  const double lm = classify_mot_words(mix, two_topic_lda(), corpus).log_score(0, 0);
  EXPECT_NEAR(lm, std::log(0.3 * std::exp(la) + 0.7 * std::exp(lb)), 1e-9);
}

}  // namespace
}  // namespace proprio::topics
