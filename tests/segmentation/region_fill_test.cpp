// The harmonic fill of regions without evidence (MlOptions::fill_unknown): known answers on
// small label images, colour weighting, chains, unreachable regions and its invariants.
#include "proprio/segmentation/region_fill.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

namespace proprio::segmentation {
namespace {

// Vertical stripes of 4 columns each, 12 rows, labelled left to right by `ids` (per stripe, top
// half then bottom half).
cv::Mat1i stripes(const std::vector<std::pair<int, int>>& ids) {
  cv::Mat1i lab(12, 4 * static_cast<int>(ids.size()));
  for (int s = 0; s < static_cast<int>(ids.size()); ++s) {
    lab(cv::Rect(4 * s, 0, 4, 6)).setTo(ids[s].first);
    lab(cv::Rect(4 * s, 6, 4, 6)).setTo(ids[s].second);
  }
  return lab;
}

std::vector<Eigen::Vector3f> grey(int n) {
  return {static_cast<size_t>(n), Eigen::Vector3f::Constant(128)};
}

TEST(RegionFill, UnknownRegionTakesTheBoundaryWeightedMeanOfItsNeighbours) {
  // 0 (score 1) | 1 (unknown) | 2 (score 0) over 3 (score 0.4): region 1 borders 0 along 12
  // pixels and 2 and 3 along 6 each: (12 * 1 + 6 * 0 + 6 * 0.4) / 24 = 0.6.
  const cv::Mat1i lab = stripes({{0, 0}, {1, 1}, {2, 3}});
  std::vector<float> score = {1.0f, 0.0f, 0.0f, 0.4f};
  const RegionFillSummary s = fill_unknown_scores(lab, {1, 0, 1, 1}, grey(4), 15.0, score);
  EXPECT_NEAR(score[1], 0.6f, 1e-5);
  EXPECT_EQ(score[0], 1.0f);
  EXPECT_EQ(score[2], 0.0f);
  EXPECT_FLOAT_EQ(score[3], 0.4f);
  EXPECT_EQ(s.unknown, 1);
  EXPECT_EQ(s.filled, 1);
  EXPECT_TRUE(s.converged);
}

TEST(RegionFill, ColourDecidesWhichNeighbourCounts) {
  const cv::Mat1i lab = stripes({{0, 0}, {1, 1}, {2, 2}});
  std::vector<Eigen::Vector3f> colour = {Eigen::Vector3f(200, 40, 40), Eigen::Vector3f(30, 30, 200),
                                         Eigen::Vector3f(30, 35, 190)};
  std::vector<float> score = {1.0f, 0.0f, 0.1f};
  (void)fill_unknown_scores(lab, {1, 0, 1}, colour, 15.0, score);
  EXPECT_NEAR(score[1], 0.1f, 1e-4) << "region 1 looks like region 2, not like region 0";
  // With a wide colour kernel both count alike (equal boundaries): the plain mean.
  score = {1.0f, 0.0f, 0.1f};
  (void)fill_unknown_scores(lab, {1, 0, 1}, colour, 1e5, score);
  EXPECT_NEAR(score[1], 0.55f, 1e-4);
}

TEST(RegionFill, ChainsOfUnknownRegionsInterpolateHarmonically) {
  // 0 (1) | 1 (?) | 2 (?) | 3 (0): u1 = (1 + u2) / 2, u2 = u1 / 2 -> 2/3 and 1/3.
  const cv::Mat1i lab = stripes({{0, 0}, {1, 1}, {2, 2}, {3, 3}});
  std::vector<float> score = {1.0f, 0.0f, 0.0f, 0.0f};
  const RegionFillSummary s = fill_unknown_scores(lab, {1, 0, 0, 1}, grey(4), 15.0, score);
  EXPECT_NEAR(score[1], 2.0f / 3.0f, 1e-3);
  EXPECT_NEAR(score[2], 1.0f / 3.0f, 1e-3);
  EXPECT_EQ(s.filled, 2);
  EXPECT_TRUE(s.converged);
  EXPECT_GT(s.sweeps, 1);
}

TEST(RegionFill, RegionsWithNoPathToAKnownOneKeepTheirScore) {
  const cv::Mat1i lab = stripes({{0, 0}, {1, 1}});
  std::vector<float> score = {0.3f, 0.7f};
  const RegionFillSummary s = fill_unknown_scores(lab, {0, 0}, grey(2), 15.0, score);
  EXPECT_EQ(score, (std::vector<float>{0.3f, 0.7f}));
  EXPECT_EQ(s.unknown, 2);
  EXPECT_EQ(s.filled, 0);
  // Nothing unknown: nothing to do.
  const RegionFillSummary none = fill_unknown_scores(lab, {1, 1}, grey(2), 15.0, score);
  EXPECT_EQ(none.unknown, 0);
  EXPECT_EQ(score, (std::vector<float>{0.3f, 0.7f}));
}

// Invariants on random region maps: known scores never change, filled ones stay within the
// known range (a weighted mean of them), and the result does not depend on anything but input.
TEST(RegionFill, StaysWithinTheKnownRangeAndIsDeterministic) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 20; ++trial) {
    const int n = 30;
    cv::Mat1i lab(40, 40);
    for (int y = 0; y < 40; y += 5)
      for (int x = 0; x < 40; x += 5) lab(cv::Rect(x, y, 5, 5)).setTo(static_cast<int>(rng() % n));
    std::vector<char> known(n);
    std::vector<float> score(n);
    std::vector<Eigen::Vector3f> colour(n);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (int i = 0; i < n; ++i) {
      known[i] = rng() % 2 ? 1 : 0;
      score[i] = u(rng);
      colour[i] = Eigen::Vector3f(255 * u(rng), 255 * u(rng), 255 * u(rng));
    }
    float lo = 1, hi = 0;
    for (int i = 0; i < n; ++i)
      if (known[i]) lo = std::min(lo, score[i]), hi = std::max(hi, score[i]);
    std::vector<float> a = score, b = score;
    const RegionFillSummary s = fill_unknown_scores(lab, known, colour, 40.0, a);
    (void)fill_unknown_scores(lab, known, colour, 40.0, b);
    EXPECT_EQ(a, b);
    for (int i = 0; i < n; ++i) {
      if (known[i]) {
        EXPECT_EQ(a[i], score[i]);
      } else if (a[i] != score[i]) {
        EXPECT_GE(a[i], lo - 1e-6f);
        EXPECT_LE(a[i], hi + 1e-6f);
      }
    }
    EXPECT_LE(s.filled, s.unknown);
  }
}

}  // namespace
}  // namespace proprio::segmentation
