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

}  // namespace
}  // namespace proprio::recognition
