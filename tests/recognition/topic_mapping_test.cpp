#include "proprio/recognition/topic_mapping.hpp"

#include <gtest/gtest.h>

#include "proprio/core/error.hpp"
#include "proprio/core/random.hpp"
#include "proprio/recognition/image_corpus.hpp"
#include "proprio/topics/online_lda.hpp"

namespace proprio::recognition {
namespace {

TEST(TopicMapping, PlantedStructureMapsEachTopicToItsClass) {
  // Class 0 lives on topics 0 and 2, class 1 on topic 1, class 2 on topic 3.
  Eigen::MatrixXd theta(6, 4);
  theta << 0.5, 0.1, 0.3, 0.1,  //
      0.4, 0.1, 0.4, 0.1,       //
      0.1, 0.8, 0.05, 0.05,     //
      0.05, 0.9, 0.0, 0.05,     //
      0.1, 0.1, 0.1, 0.7,       //
      0.0, 0.2, 0.0, 0.8;
  const std::vector<int> labels{0, 0, 1, 1, 2, 2};
  const TopicMapping m = map_topics(theta, labels, 3);
  EXPECT_EQ(m.topic_class, (std::vector<int>{0, 1, 0, 2}));
  EXPECT_TRUE(m.orphan_classes.empty());
  EXPECT_NEAR(m.mean_theta(1, 1), 0.85, 1e-12);
  const std::vector<int> topic{2, 3, -1, 1};
  EXPECT_EQ(mapped_classes(topic, m), (std::vector<int>{0, 2, -1, 1}));
}

TEST(TopicMapping, UnlabelledRowsAreIgnoredAndOrphansReported) {
  Eigen::MatrixXd theta(3, 2);
  theta << 0.9, 0.1,  //
      0.6, 0.05,      //
      0.0, 1.0;       // unlabelled: counted as class 1, it would take topic 1 there
  const TopicMapping m = map_topics(theta, std::vector<int>{0, 1, -1}, 2);
  EXPECT_EQ(m.topic_class, (std::vector<int>{0, 0}));
  EXPECT_EQ(m.orphan_classes, (std::vector<int>{1}));
  const TopicMapping counted = map_topics(theta, std::vector<int>{0, 1, 1}, 2);
  EXPECT_EQ(counted.topic_class, (std::vector<int>{0, 1}));
}

TEST(TopicMapping, ClassWithoutDocumentsIsAnError) {
  Eigen::MatrixXd theta(1, 2);
  theta << 0.5, 0.5;
  try {
    (void)map_topics(theta, std::vector<int>{0}, 2);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("class 1 has no labelled document"), std::string::npos);
  }
}

// End to end: two planted topics over disjoint words; LDA learns them without labels, labelled
// documents name them, held-out documents are classified right.
TEST(TopicMapping, LdaOnPlantedTopicsClassifiesHeldOutDocuments) {
  core::Rng rng(3);
  auto make = [&](int n, LabelledCorpus& out) {
    out.corpus = topics::Corpus(20);
    out.classes = {"left", "right"};
    for (int d = 0; d < n; ++d) {
      const int c = d % 2;
      std::vector<std::int32_t> tokens;
      for (int t = 0; t < 40; ++t) {
        // 90% from the class's own ten words, 10% from anywhere.
        const bool own = rng.uniform() < 0.9;
        const int w =
            own ? 10 * c + static_cast<int>(rng.index(10)) : static_cast<int>(rng.index(20));
        tokens.push_back(w);
      }
      out.corpus.add_tokens(tokens);
      out.labels.push_back(c);
    }
  };
  LabelledCorpus train, labelled, test;
  make(200, train);
  make(20, labelled);
  make(60, test);
  topics::OnlineLdaOptions o;
  o.num_topics = 2;
  o.batch_size = 50;
  o.passes = 5;
  const auto model = topics::train_online_lda(train.corpus, o).model;
  const Evaluation e = evaluate_model(model, labelled, test);
  EXPECT_NE(e.mapping.topic_class[0], e.mapping.topic_class[1]);
  EXPECT_GE(e.classes.accuracy(), 0.95);
  EXPECT_EQ(e.topics.columns.size(), 2U);
  EXPECT_EQ(evaluation_to_json(e)["mapping"]["topic_class"].size(), 2U);
}

}  // namespace
}  // namespace proprio::recognition
