// The views' theta for the Mixture of Topics: the word-posterior theta (recognition::
// ThetaSource::kWordPosterior) against a hand computation, and the E-step's through view_theta.
#include <gtest/gtest.h>

#include "proprio/core/error.hpp"
#include "proprio/recognition/mot.hpp"

namespace proprio::recognition {
namespace {

topics::LdaModel two_topics() {
  topics::LdaModel m;
  m.lambda.resize(2, 3);
  m.lambda << 3.0, 1.0, 1.0,  // topic 0: beta = 0.6 0.2 0.2
      1.0, 1.0, 3.0;          // topic 1: beta = 0.2 0.2 0.6
  m.alpha = 0.5;
  m.eta = 0.1;
  return m;
}

TEST(MotTheta, WordPosteriorIsTheMeanOfEachWordsTopicPosterior) {
  topics::Corpus corpus(3);
  const std::vector<std::int32_t> words{0, 2}, counts{3, 1};
  corpus.add_document(words, counts);
  corpus.add_document(std::span<const std::int32_t>{}, std::span<const std::int32_t>{});
  const DocumentTheta t = word_posterior_theta(two_topics(), corpus);
  // p(k | w0) = (0.75, 0.25), p(k | w2) = (0.25, 0.75): (3 (0.75, 0.25) + (0.25, 0.75)) / 4.
  EXPECT_NEAR(t.theta(0, 0), 0.625, 1e-12);
  EXPECT_NEAR(t.theta(0, 1), 0.375, 1e-12);
  EXPECT_FALSE(t.empty[0]);
  EXPECT_TRUE(t.empty[1]);
  EXPECT_NEAR(t.theta(1, 0), 0.5, 1e-12);  // empty: uniform

  const DocumentTheta e = view_theta(two_topics(), corpus, ThetaSource::kEStep);
  EXPECT_NEAR(e.theta.row(0).sum(), 1.0, 1e-9);
  EXPECT_GT(e.theta(0, 0), 0.5);
  EXPECT_THROW((void)word_posterior_theta(two_topics(), topics::Corpus(4)), Error);
}

TEST(MotCeilings, NearestNeighboursVoteAndSkipUnlabelledRows) {
  Eigen::MatrixXd train(5, 1), test(3, 1);
  train << 0.0, 0.1, 0.2, 1.0, 0.15;
  test << 0.05, 0.9, 0.6;
  const std::vector<int> labels{0, 0, 1, 1, -1};
  // k = 1: the nearest labelled row.
  EXPECT_EQ(knn_predict(train, labels, 2, test, 1), (std::vector<int>{0, 1, 1}));
  // k = 3 at 0.9: 1.0 (1), 0.2 (1), 0.1 (0): class 1; at 0.05: 0.0, 0.1, 0.2: class 0.
  EXPECT_EQ(knn_predict(train, labels, 2, test, 3)[0], 0);
  EXPECT_EQ(knn_predict(train, labels, 2, test, 3)[1], 1);
  // A tie of votes goes to the nearest's class.
  Eigen::MatrixXd two(2, 1), at(2, 1);
  two << 0.0, 1.0;
  at << 0.4, 0.6;
  const std::vector<int> one_each{0, 1};
  EXPECT_EQ(knn_predict(two, one_each, 2, at, 2), (std::vector<int>{0, 1}));
}

TEST(MotCeilings, LogisticRegressionSeparatesLinearlySeparableClasses) {
  Eigen::MatrixXd train(60, 2), test(3, 2);
  std::vector<int> labels;
  for (int i = 0; i < 60; ++i) {
    const int c = i % 3;
    train(i, 0) = c == 1 ? 3.0 : 0.0;
    train(i, 1) = c == 2 ? 3.0 : 0.0;
    train.row(i).array() += 0.1 * ((i * 7) % 11 - 5) / 5.0;
    labels.push_back(c);
  }
  test << 0.2, -0.1, 2.8, 0.3, 0.1, 3.2;
  EXPECT_EQ(logistic_predict(train, labels, 3, test), (std::vector<int>{0, 1, 2}));
}

TEST(MotCeilings, NaiveBayesUsesEachObjectsWords) {
  LabelledCorpus train{topics::Corpus(4), {0, 1}, {"a", "b"}};
  const std::vector<std::int32_t> wa{0, 1}, wb{2, 3}, c{5, 5};
  train.corpus.add_document(wa, c);
  train.corpus.add_document(wb, c);
  topics::Corpus test(4);
  const std::vector<std::int32_t> t0{0, 3}, c0{3, 1}, t1{2}, c1{1};
  test.add_document(t0, c0);
  test.add_document(t1, c1);
  test.add_document(std::span<const std::int32_t>{}, std::span<const std::int32_t>{});
  EXPECT_EQ(naive_bayes_predict(train, test), (std::vector<int>{0, 1, -1}));
}

TEST(MotCeilings, EveryCeilingClassifiesEveryTestView) {
  // Object a's views use word 0, b's word 2: every ceiling separates them.
  LabelledCorpus train{topics::Corpus(3), {}, {"a", "b"}};
  LabelledCorpus test{topics::Corpus(3), {}, {"a", "b"}};
  for (int i = 0; i < 12; ++i) {
    const int c = i % 2;
    const std::vector<std::int32_t> w{c == 0 ? 0 : 2, 1}, n{6 + i % 3, 1 + i % 2};
    (i < 8 ? train : test).corpus.add_document(w, n);
    (i < 8 ? train : test).labels.push_back(c);
  }
  const auto ceilings = representation_ceilings(two_topics(), train, test);
  std::vector<std::string> names;
  for (const auto& x : ceilings) {
    names.push_back(x.name);
    EXPECT_EQ(x.classes.total(), 4) << x.name;
    EXPECT_DOUBLE_EQ(x.classes.mean_class_accuracy(), 1.0) << x.name;
  }
  EXPECT_EQ(names, (std::vector<std::string>{"knn-estep", "logistic-estep", "knn-word-posterior",
                                             "logistic-word-posterior", "knn-words",
                                             "naive-bayes-words"}));
}

}  // namespace
}  // namespace proprio::recognition
