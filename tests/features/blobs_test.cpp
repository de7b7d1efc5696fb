#include "proprio/features/blobs.hpp"

#include <gtest/gtest.h>

#include "proprio/core/random.hpp"
#include "test_util.hpp"

namespace proprio::features {
namespace {

using test::expect_error;

std::vector<cv::KeyPoint> cluster(cv::Point2f centre, double spread, int n, core::Rng& rng) {
  std::vector<cv::KeyPoint> k;
  for (int i = 0; i < n; ++i) {
    k.emplace_back(centre.x + static_cast<float>(rng.normal(0, spread)),
                   centre.y + static_cast<float>(rng.normal(0, spread)), 4.0F);
  }
  return k;
}

TEST(Blobs, TwoSeparatedClustersAreTwoBlobs) {
  core::Rng rng(5);
  auto a = cluster({100, 120}, 10, 60, rng);
  const auto b = cluster({400, 300}, 15, 40, rng);
  a.insert(a.end(), b.begin(), b.end());
  // Sparse background: lone features far apart stay below the threshold.
  for (int i = 0; i < 15; ++i) {
    a.emplace_back(static_cast<float>(rng.uniform(0, 640)),
                   static_cast<float>(rng.uniform(450, 480)), 4.0F);
  }
  const auto blobs = find_blobs(a, {640, 480});
  ASSERT_EQ(blobs.size(), 2U);
  EXPECT_TRUE(blobs[0].box.contains({100, 120}));
  EXPECT_TRUE(blobs[1].box.contains({400, 300}));
  EXPECT_GE(blobs[0].features.size(), 55U);
  EXPECT_LE(blobs[0].features.size(), 60U);
  EXPECT_GE(blobs[1].features.size(), 33U);
  for (const int i : blobs[0].features) EXPECT_LT(i, 60);
  for (const int i : blobs[1].features) {
    EXPECT_GE(i, 60);
    EXPECT_LT(i, 100);
  }
  EXPECT_EQ(blobs[0].mask.size(), blobs[0].box.size());
  EXPECT_EQ(blobs[0].mask(120 - blobs[0].box.y, 100 - blobs[0].box.x), 255);
}

TEST(Blobs, DensityIsTheGaussianSumOfEq63) {
  // One feature gives a peak-1 Gaussian; two at the same place give 2; no wrap-around at the
  // border.
  BlobOptions o;
  o.sigma = 5;
  std::vector<cv::KeyPoint> k{cv::KeyPoint(20, 30, 1), cv::KeyPoint(20, 30, 1),
                              cv::KeyPoint(0, 0, 1), cv::KeyPoint(-5, 3, 1)};
  const cv::Mat1f d = feature_density(k, {64, 48}, o);
  EXPECT_NEAR(d(30, 20), 2.0, 1e-4);
  EXPECT_NEAR(d(30, 25), 2 * std::exp(-0.5), 1e-4);
  EXPECT_NEAR(d(0, 0), 1.0, 1e-4);
  EXPECT_NEAR(d(47, 63), 0.0, 1e-4);  // the opposite corner sees nothing of (0, 0)
  EXPECT_TRUE(find_blobs({}, {64, 48}, o).empty());
}

TEST(Blobs, BadInput) {
  expect_error([] { find_blobs({}, {0, 10}); }, "empty image size");
  BlobOptions o;
  o.sigma = 0;
  expect_error([&] { o.validate(); }, "sigma");
  o = {};
  o.threshold = -1;
  expect_error([&] { find_blobs({}, {10, 10}, o); }, "threshold");
  o = {};
  o.min_features = 0;
  expect_error([&] { o.validate(); }, "min_features");
}

}  // namespace
}  // namespace proprio::features
