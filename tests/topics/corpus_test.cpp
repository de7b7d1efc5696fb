// Corpora in memory: weighted_from's known answers.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "proprio/core/error.hpp"
#include "proprio/topics/corpus.hpp"

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

}  // namespace
}  // namespace proprio::topics
