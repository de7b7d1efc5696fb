#include "proprio/recognition/confusion.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace proprio::recognition {
namespace {

TEST(Confusion, CountsAccuracyAndMeanClassAccuracy) {
  // Class 0: 3 right, 1 wrong; class 1: 1 right, 1 unclassified.
  const std::vector<int> truth{0, 0, 0, 0, 1, 1};
  const std::vector<int> pred{0, 0, 0, 1, 1, -1};
  const ConfusionMatrix m = confusion_matrix(truth, pred, {"a", "b"}, {"a", "b"});
  EXPECT_EQ(m.counts, (std::vector<std::vector<int>>{{3, 1}, {0, 1}}));
  EXPECT_EQ(m.unclassified, (std::vector<int>{0, 1}));
  EXPECT_EQ(m.total(), 6);
  EXPECT_EQ(m.correct(), 4);
  EXPECT_DOUBLE_EQ(m.accuracy(), 4.0 / 6.0);
  EXPECT_DOUBLE_EQ(m.mean_class_accuracy(), (0.75 + 0.5) / 2);
  const std::string text = m.format();
  EXPECT_NE(text.find("none"), std::string::npos);
  EXPECT_EQ(m.to_json()["counts"][0][1], 1);
}

TEST(Confusion, ThesisTable64AverageIsTheMeanOfTheRows) {
  // Table 6.4 in percent per row: the "average accuracy" 83% is the mean of the diagonal.
  std::vector<int> truth, pred;
  const int rows[3][3] = {{94, 6, 0}, {0, 100, 0}, {0, 43, 57}};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      for (int n = 0; n < rows[r][c]; ++n) {
        truth.push_back(r);
        pred.push_back(c);
      }
  const ConfusionMatrix m =
      confusion_matrix(truth, pred, {"calc", "bike", "bottle"}, topic_names(3));
  EXPECT_NEAR(m.mean_class_accuracy(), 0.8367, 1e-4);
  EXPECT_EQ(m.columns.front(), "z_1");
  EXPECT_NE(m.format(true).find("57"), std::string::npos);
}

TEST(Confusion, EmptyMatrixHasZeroAccuracy) {
  const ConfusionMatrix m = confusion_matrix({}, {}, {"a"}, {"a"});
  EXPECT_EQ(m.total(), 0);
  EXPECT_EQ(m.accuracy(), 0.0);
  EXPECT_EQ(m.mean_class_accuracy(), 0.0);
}

}  // namespace
}  // namespace proprio::recognition
