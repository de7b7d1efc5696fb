// Region scores smoothed over the region graph (MlOptions::region_smoothing): known answers on
// small label images, colour weighting, chains, regions without evidence, and its invariants.
#include "proprio/segmentation/region_smoothing.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <string>

#include "proprio/core/error.hpp"

namespace proprio::segmentation {
namespace {

// Vertical stripes 4 columns wide and 12 rows high, left to right; each stripe's top half
// takes the pair's first label, its bottom half the second.
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

// Only regions without evidence move (a huge data weight).
RegionSmoothingOptions fill_only() {
  RegionSmoothingOptions o;
  o.data_weight = 1e9;
  o.colour_sigma = 15.0;
  return o;
}

TEST(RegionSmoothing, RegionWithoutEvidenceTakesTheBoundaryWeightedMeanOfItsNeighbours) {
  // 0 (score 1) | 1 (no evidence) | 2 (score 0) over 3 (score 0.4): region 1 borders 0 along 12
  // pixels and 2 and 3 along 6 each: (12 * 1 + 6 * 0 + 6 * 0.4) / 24 = 0.6.
  const cv::Mat1i lab = stripes({{0, 0}, {1, 1}, {2, 3}});
  std::vector<float> score = {1.0f, 0.0f, 0.0f, 0.4f};
  const RegionSmoothingSummary s =
      smooth_region_scores(lab, {5, 0, 5, 5}, grey(4), fill_only(), score);
  EXPECT_NEAR(score[1], 0.6f, 1e-5);
  EXPECT_NEAR(score[0], 1.0f, 1e-6);
  EXPECT_NEAR(score[2], 0.0f, 1e-6);
  EXPECT_NEAR(score[3], 0.4f, 1e-6);
  EXPECT_EQ(s.regions, 4);
  EXPECT_EQ(s.without_evidence, 1);
  EXPECT_TRUE(s.converged);
}

TEST(RegionSmoothing, DepthStepsKeepRegionsApart) {
  // As above, but region 0 lies 100 mm nearer than the others (a step at its boundary with 1):
  // with depth_step 20 region 1 joins only 2 (score 0) and 3 (0.4) along 6 pixels each: 0.2.
  // Without the depth image, or with a step threshold above 100 mm, 0.6 again.
  const cv::Mat1i lab = stripes({{0, 0}, {1, 1}, {2, 3}});
  cv::Mat1f depth(lab.size(), 700.0f);
  depth(cv::Rect(0, 0, 4, 12)).setTo(600.0f);
  RegionSmoothingOptions o = fill_only();
  o.depth_step = 20.0;
  std::vector<float> score = {1.0f, 0.0f, 0.0f, 0.4f};
  (void)smooth_region_scores(lab, {5, 0, 5, 5}, grey(4), o, score, depth);
  EXPECT_NEAR(score[1], 0.2f, 1e-5);
  score = {1.0f, 0.0f, 0.0f, 0.4f};
  (void)smooth_region_scores(lab, {5, 0, 5, 5}, grey(4), o, score);
  EXPECT_NEAR(score[1], 0.6f, 1e-5);
  o.depth_step = 150.0;
  score = {1.0f, 0.0f, 0.0f, 0.4f};
  (void)smooth_region_scores(lab, {5, 0, 5, 5}, grey(4), o, score, depth);
  EXPECT_NEAR(score[1], 0.6f, 1e-5);
  // Unknown depth (0) on one side of the step joins as before.
  o.depth_step = 20.0;
  depth(cv::Rect(3, 0, 1, 12)).setTo(0.0f);
  score = {1.0f, 0.0f, 0.0f, 0.4f};
  (void)smooth_region_scores(lab, {5, 0, 5, 5}, grey(4), o, score, depth);
  EXPECT_NEAR(score[1], 0.6f, 1e-5);
  o.depth_step = -1.0;
  EXPECT_THROW(o.validate(), Error);
}

TEST(RegionSmoothing, ColourDecidesWhichNeighbourCounts) {
  const cv::Mat1i lab = stripes({{0, 0}, {1, 1}, {2, 2}});
  const std::vector<Eigen::Vector3f> colour = {
      Eigen::Vector3f(200, 40, 40), Eigen::Vector3f(30, 30, 200), Eigen::Vector3f(30, 35, 190)};
  std::vector<float> score = {1.0f, 0.0f, 0.1f};
  (void)smooth_region_scores(lab, {5, 0, 5}, colour, fill_only(), score);
  EXPECT_NEAR(score[1], 0.1f, 1e-4) << "region 1 looks like region 2, not like region 0";
  // With a wide colour kernel both count alike (equal boundaries): the plain mean.
  RegionSmoothingOptions wide = fill_only();
  wide.colour_sigma = 1e5;
  score = {1.0f, 0.0f, 0.1f};
  (void)smooth_region_scores(lab, {5, 0, 5}, colour, wide, score);
  EXPECT_NEAR(score[1], 0.55f, 1e-4);
}

TEST(RegionSmoothing, ChainsWithoutEvidenceInterpolateHarmonically) {
  // 0 (1) | 1 (?) | 2 (?) | 3 (0): u1 = (1 + u2) / 2, u2 = u1 / 2 -> 2/3 and 1/3.
  const cv::Mat1i lab = stripes({{0, 0}, {1, 1}, {2, 2}, {3, 3}});
  std::vector<float> score = {1.0f, 0.0f, 0.0f, 0.0f};
  const RegionSmoothingSummary s =
      smooth_region_scores(lab, {5, 0, 0, 5}, grey(4), fill_only(), score);
  EXPECT_NEAR(score[1], 2.0f / 3.0f, 1e-3);
  EXPECT_NEAR(score[2], 1.0f / 3.0f, 1e-3);
  EXPECT_TRUE(s.converged);
  EXPECT_GT(s.sweeps, 1);
}

TEST(RegionSmoothing, EvidenceHoldsARegionInProportionToItsCount) {
  // Two regions, one boundary of 12 pixels (each region's whole boundary): the minimum of
  // a1 (s1 - 1)^2 + a2 (s2 - 0)^2 + 12 (s1 - s2)^2 with a_i = beta n_i 12.
  const cv::Mat1i lab = stripes({{0, 0}, {1, 1}});
  RegionSmoothingOptions o;
  o.data_weight = 0.5;
  o.tolerance = 1e-7;
  std::vector<float> score = {1.0f, 0.0f};
  const RegionSmoothingSummary s = smooth_region_scores(lab, {4, 1}, grey(2), o, score);
  // Normal equations: (a1 + w) s1 - w s2 = a1, -w s1 + (a2 + w) s2 = 0 with a1 = 24, a2 = 6,
  // w = 12: s1 = 0.8, s2 = 0.533...
  const double a1 = 24, a2 = 6, w = 12;
  const double det = (a1 + w) * (a2 + w) - w * w;
  EXPECT_NEAR(score[0], a1 * (a2 + w) / det, 1e-4);
  EXPECT_NEAR(score[1], a1 * w / det, 1e-4);
  EXPECT_GT(score[0], score[1]) << "the region with more evidence keeps more of its own score";
  EXPECT_TRUE(s.converged);
}

TEST(RegionSmoothing, RegionsWithNoEvidenceAnywhereKeepTheirScores) {
  const cv::Mat1i lab = stripes({{0, 0}, {1, 1}});
  std::vector<float> score = {0.3f, 0.7f};
  const RegionSmoothingSummary s = smooth_region_scores(lab, {0, 0}, grey(2), {}, score);
  EXPECT_EQ(score, (std::vector<float>{0.3f, 0.7f}));
  EXPECT_EQ(s.without_evidence, 2);
  EXPECT_EQ(s.sweeps, 0);
}

// Invariants on random region maps: scores stay within the range of the evidenced ones, the
// result is deterministic, and a zero colour kernel width is refused.
TEST(RegionSmoothing, StaysWithinTheEvidencedRangeAndIsDeterministic) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int trial = 0; trial < 20; ++trial) {
    const int n = 30;
    cv::Mat1i lab(40, 40);
    for (int y = 0; y < 40; y += 5)
      for (int x = 0; x < 40; x += 5) lab(cv::Rect(x, y, 5, 5)).setTo(static_cast<int>(rng() % n));
    std::vector<int> evidence(n);
    std::vector<float> score(n);
    std::vector<Eigen::Vector3f> colour(n);
    for (int i = 0; i < n; ++i) {
      evidence[i] = static_cast<int>(rng() % 4);
      score[i] = u(rng);
      colour[i] = Eigen::Vector3f(255 * u(rng), 255 * u(rng), 255 * u(rng));
    }
    float lo = 1, hi = 0;
    for (int i = 0; i < n; ++i) {
      if (evidence[i] > 0) {
        lo = std::min(lo, score[i]);
        hi = std::max(hi, score[i]);
      }
    }
    RegionSmoothingOptions o;
    o.colour_sigma = 40.0;
    std::vector<float> a = score, b = score;
    const RegionSmoothingSummary s = smooth_region_scores(lab, evidence, colour, o, a);
    (void)smooth_region_scores(lab, evidence, colour, o, b);
    EXPECT_EQ(a, b);
    EXPECT_TRUE(s.converged);
    for (int i = 0; i < n; ++i) {
      if (a[i] == score[i]) continue;  // not in the image, or unchanged
      EXPECT_GE(a[i], lo - 1e-5f);
      EXPECT_LE(a[i], hi + 1e-5f);
    }
  }
  RegionSmoothingOptions bad;
  bad.colour_sigma = 0;
  try {
    bad.validate();
    ADD_FAILURE() << "colour_sigma 0 accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("colour_sigma"), std::string::npos);
  }
}

}  // namespace
}  // namespace proprio::segmentation
