// Corpora in memory: weighted_by's and weighted_from's known answers, and a model's word weights
// at inference and in perplexity.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "proprio/core/error.hpp"
#include "proprio/topics/corpus.hpp"
#include "proprio/topics/inference.hpp"
#include "proprio/topics/lda_model.hpp"
#include "proprio/topics/perplexity.hpp"

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

// Two topics of two words each, and two documents mixing them.
LdaModel two_topic_model() {
  LdaModel m;
  m.lambda.resize(2, 4);
  m.lambda << 5, 5, 0.1, 0.1,  // topic 0: words 0 and 1
      0.1, 0.1, 5, 5;          // topic 1: words 2 and 3
  m.alpha = 0.5;
  m.eta = 0.01;
  return m;
}

Corpus two_documents() {
  Corpus docs(4);
  docs.add_tokens(std::vector<std::int32_t>{0, 0, 1, 2});
  docs.add_tokens(std::vector<std::int32_t>{1, 3, 3});
  return docs;
}

// A model with word weights infers theta as the same model without them does on the documents
// weighted by hand: its readers never weigh twice, nor forget to.
TEST(Corpus, AModelsWordWeightsWeighTheDocumentsItInfers) {
  const LdaModel m = two_topic_model();
  const Corpus docs = two_documents();
  LdaModel weighted = m;
  weighted.word_weights = weights_from(4, 2, 10);
  const Eigen::MatrixXd by_model = infer_topics(weighted, docs).theta();
  const Eigen::MatrixXd by_hand = infer_topics(m, weighted_from(docs, 2, 10)).theta();
  const Eigen::MatrixXd once = infer_topics(m, docs).theta();
  EXPECT_EQ(by_model, by_hand);  // the same float counts, so the same to the bit
  // Document 0: 3 tokens of topic 0 and 1 of topic 1 once; 3 against 10 weighted.
  EXPECT_GT(once(0, 0), 0.5);
  EXPECT_LT(by_model(0, 0), 0.5);
}

// A weighted model's perplexity is of the weighted documents it models: by both methods, the same
// as the model without weights scores on documents weighted by hand (the completion split being of
// the documents' own tokens, each half weighted after it), and not the unweighted figure.
TEST(Corpus, AModelsWordWeightsWeighTheDocumentsItScores) {
  const LdaModel m = two_topic_model();
  const Corpus docs = two_documents();
  LdaModel weighted = m;
  weighted.word_weights = weights_from(4, 2, 10);

  PerplexityOptions bound;
  bound.method = PerplexityMethod::kVariationalBound;
  const PerplexityResult a = perplexity(weighted, docs, bound);
  const PerplexityResult b = perplexity(m, weighted_from(docs, 2, 10), bound);
  EXPECT_EQ(a.tokens, b.tokens);
  EXPECT_EQ(a.tokens, 4 + 10 * 3);  // words 0, 0, 1, 1 once; 2, 3, 3 ten times
  EXPECT_DOUBLE_EQ(a.log_likelihood, b.log_likelihood);
  EXPECT_DOUBLE_EQ(a.perplexity, b.perplexity);
  EXPECT_NE(a.perplexity, perplexity(m, docs, bound).perplexity);

  const CompletionSplit split = split_for_completion(docs, 3);
  const PerplexityResult c = completion_perplexity(weighted, split);
  const PerplexityResult d = completion_perplexity(
      m, CompletionSplit{weighted_from(split.observed, 2, 10), weighted_from(split.scored, 2, 10)});
  EXPECT_EQ(c.tokens, d.tokens);
  EXPECT_GT(c.tokens, split.scored.num_tokens());  // some scored token is of a weighted word
  EXPECT_DOUBLE_EQ(c.log_likelihood, d.log_likelihood);
  EXPECT_NE(c.perplexity, completion_perplexity(m, split).perplexity);
}

}  // namespace
}  // namespace proprio::topics
