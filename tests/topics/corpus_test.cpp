// Corpora in memory: weighted_by's and weighted_from's known answers, and a model's word weights
// at inference.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "proprio/core/error.hpp"
#include "proprio/topics/corpus.hpp"
#include "proprio/topics/inference.hpp"
#include "proprio/topics/lda_model.hpp"

namespace proprio::topics {
namespace {

TEST(Corpus, WeightedFromKnownAnswers) {
  // Words 3 and 4 (say, colour words after a vocabulary of 3) counted 3 times, the others once;
  // the documents, their order, their words and the vocabulary's names kept.
  Corpus coloured(5, {"a", "b", "c", "red", "grey"});
  coloured.add_tokens(std::vector<std::int32_t>{0, 3, 3, 4});
  coloured.add_tokens(std::vector<std::int32_t>{1, 2});
  coloured.add_tokens(std::vector<std::int32_t>{4, 2});
  const Corpus weighted = weighted_from(coloured, 3, 3);
  ASSERT_EQ(weighted.num_words(), 5);
  ASSERT_EQ(weighted.num_documents(), 3U);
  EXPECT_EQ(weighted.vocabulary(), coloured.vocabulary());
  EXPECT_EQ(weighted.num_tokens(), 4 + 3 * 4);  // 4 other tokens, 4 colour tokens
  for (std::size_t d = 0; d < 3; ++d) {
    const DocumentView a = coloured.document(d);
    const DocumentView b = weighted.document(d);
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
      EXPECT_EQ(a.words[i], b.words[i]);
      EXPECT_EQ(b.counts[i], a.words[i] >= 3 ? 3 * a.counts[i] : a.counts[i]);
    }
  }
  EXPECT_EQ(weighted.document(0).counts[1], 6);  // word 3 twice in document 0, weighing 3
  EXPECT_EQ(weighted_from(coloured, 3, 1).num_tokens(), coloured.num_tokens());
  EXPECT_EQ(weighted_from(coloured, 5, 7).num_tokens(), coloured.num_tokens());      // none weighed
  EXPECT_EQ(weighted_from(coloured, 0, 2).num_tokens(), 2 * coloured.num_tokens());  // all
  EXPECT_THROW((void)weighted_from(coloured, 6, 2), Error);
  EXPECT_THROW((void)weighted_from(coloured, -1, 2), Error);
  EXPECT_THROW((void)weighted_from(coloured, 3, 0), Error);
}

TEST(Corpus, WeightedByKnownAnswersAndBounds) {
  Corpus c(3);
  c.add_tokens(std::vector<std::int32_t>{0, 1, 1, 2});
  c.add_tokens(std::vector<std::int32_t>{});
  const std::vector<std::int32_t> w{2, 1, 5};
  const Corpus x = weighted_by(c, w);
  ASSERT_EQ(x.num_documents(), 2U);
  EXPECT_EQ(x.num_tokens(), 2 + 2 + 5);
  EXPECT_TRUE(x.document(1).empty());
  EXPECT_EQ(weights_from(4, 1, 7), (std::vector<std::int32_t>{1, 7, 7, 7}));
  EXPECT_EQ(weights_from(2, 2, 7), (std::vector<std::int32_t>{1, 1}));
  EXPECT_THROW((void)weights_from(2, 3, 7), Error);
  EXPECT_THROW((void)weights_from(2, 1, kMaxWordWeight + 1), Error);
  EXPECT_THROW((void)weighted_by(c, std::vector<std::int32_t>{1, 1}), Error);     // 2 for 3
  EXPECT_THROW((void)weighted_by(c, std::vector<std::int32_t>{1, 0, 1}), Error);  // below 1
  // A count that the weight would overflow is refused, not wrapped.
  Corpus big(1);
  big.add_document(std::vector<std::int32_t>{0}, std::vector<std::int32_t>{3'000'000});
  EXPECT_THROW((void)weighted_by(big, std::vector<std::int32_t>{kMaxWordWeight}), Error);
}

// A model with word weights infers theta as the same model without them does on the documents
// weighted by hand: its readers never weigh twice, nor forget to.
TEST(Corpus, AModelsWordWeightsWeighTheDocumentsItInfers) {
  LdaModel m;
  m.lambda.resize(2, 4);
  m.lambda << 5, 5, 0.1, 0.1,  // topic 0: words 0 and 1
      0.1, 0.1, 5, 5;          // topic 1: words 2 and 3
  m.alpha = 0.5;
  m.eta = 0.01;
  Corpus docs(4);
  docs.add_tokens(std::vector<std::int32_t>{0, 0, 1, 2});
  docs.add_tokens(std::vector<std::int32_t>{1, 3, 3});
  LdaModel weighted = m;
  weighted.word_weights = weights_from(4, 2, 10);
  const Eigen::MatrixXd by_model = infer_topics(weighted, docs).theta();
  const Eigen::MatrixXd by_hand = infer_topics(m, weighted_from(docs, 2, 10)).theta();
  const Eigen::MatrixXd once = infer_topics(m, docs).theta();
  EXPECT_LT((by_model - by_hand).cwiseAbs().maxCoeff(), 1e-12);
  // Document 0: 3 tokens of topic 0 and 1 of topic 1 once; 3 against 10 weighted.
  EXPECT_GT(once(0, 0), 0.5);
  EXPECT_LT(by_model(0, 0), 0.5);
}

}  // namespace
}  // namespace proprio::topics
