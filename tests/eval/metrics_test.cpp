// Mask metrics, the KS test (known answers from scipy.stats.ks_2samp 1.10) and the bootstrap.
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "proprio/eval/mask_metrics.hpp"
#include "proprio/eval/statistics.hpp"

namespace proprio::eval {
namespace {

TEST(MaskMetrics, KnownCounts) {
  cv::Mat1b truth(10, 10, uchar(0)), result(10, 10, uchar(0));
  truth(cv::Rect(0, 0, 5, 4)).setTo(255);   // 20 pixels
  result(cv::Rect(0, 0, 5, 2)).setTo(255);  // 10 inside the truth
  result(cv::Rect(6, 6, 2, 3)).setTo(255);  // 6 outside
  const MaskMetrics m = compare_masks(result, truth);
  EXPECT_EQ(m.true_positives, 10);
  EXPECT_EQ(m.false_positives, 6);
  EXPECT_EQ(m.false_negatives, 10);
  EXPECT_DOUBLE_EQ(m.precision, 10.0 / 16.0);
  EXPECT_DOUBLE_EQ(m.recall, 10.0 / 20.0);
  EXPECT_DOUBLE_EQ(m.jaccard, 10.0 / 26.0);
  EXPECT_DOUBLE_EQ(m.tanimoto(), 16.0 / 26.0);
  EXPECT_DOUBLE_EQ(m.l2, std::sqrt(16.0 / 100.0));  // RMS of the 0/1 difference image
}

TEST(MaskMetrics, EdgeCases) {
  const cv::Mat1b empty(4, 4, uchar(0)), full(4, 4, uchar(255));
  const MaskMetrics none = compare_masks(empty, full);
  EXPECT_EQ(none.precision, 0.0);  // nothing segmented
  EXPECT_EQ(none.recall, 0.0);
  EXPECT_EQ(none.jaccard, 0.0);
  EXPECT_EQ(none.l2, 1.0);
  const MaskMetrics same = compare_masks(full, full);
  EXPECT_EQ(same.jaccard, 1.0);
  EXPECT_EQ(same.l2, 0.0);
  EXPECT_EQ(compare_masks(empty, empty).jaccard, 1.0);
}

TEST(KsTest, MatchesScipyExact) {
  const std::vector<double> a = {0.1, 0.4, 0.35, 0.8, 0.95, 0.5, 0.62};
  const std::vector<double> b = {0.2, 0.9, 0.85, 0.99, 0.7, 0.75, 0.88, 0.93};
  const KsResult r = ks_two_sample(a, b);
  EXPECT_TRUE(r.exact);
  EXPECT_NEAR(r.statistic, 0.5892857142857143, 1e-12);
  EXPECT_NEAR(r.p_value, 0.11810411810411808, 1e-9);
  // Ties across the samples.
  const KsResult t = ks_two_sample({1, 2, 2, 3, 3, 3}, {2, 3, 3, 4, 4});
  EXPECT_NEAR(t.statistic, 0.4, 1e-12);
  EXPECT_NEAR(t.p_value, 0.6883116883116883, 1e-9);
}

TEST(KsTest, MatchesScipyOnLargerSamples) {
  const std::vector<double> x = {2.041,  -2.556, 0.418, -0.568, -0.453, -0.216, -2.02,  -0.232,
                                 -0.865, 3.323,  0.226, -0.353, -0.281, -0.668, -1.055, -0.391,
                                 0.482,  -0.239, 0.958, -0.2,   0.024,  1.546,  0.545,  -0.505,
                                 -0.183, 0.541,  1.935, -0.27,  -0.244, 1.002,  -0.886, -0.292,
                                 0.883,  0.58,   0.092, 0.67,   -2.828, 1.021,  -0.96,  -1.669};
  const std::vector<double> y = {
      0.776,  1.201,  0.055,  -0.576, 0.526,  0.447, 1.906,  1.247, 0.694, 1.612,  0.294,
      -0.426, 1.084,  1.083,  0.285,  -0.283, 0.729, -1.994, 1.19,  0.991, -1.139, 0.561,
      -0.464, 1.257,  -1.534, -0.414, 1.21,   1.656, -1.658, 0.002, 0.828, -0.109, 2.091,
      -0.691, 0.855,  -0.548, 1.906,  0.478,  0.128, -1.218, 2.182, 1.253, 1.254,  1.638,
      0.849,  -0.139, -0.3,   -0.3,   1.87,   -0.96, -0.096, 0.179, 0.725, 1.075,  -0.749};
  const KsResult exact = ks_two_sample(x, y);
  EXPECT_NEAR(exact.statistic, 0.2840909090909091, 1e-12);
  EXPECT_NEAR(exact.p_value, 0.03776214780183412, 1e-8);
  const KsResult asymptotic = ks_two_sample(x, y, 0);
  EXPECT_FALSE(asymptotic.exact);
  // scipy.stats.kstwobign.sf(sqrt(n1 n2 / (n1 + n2)) D) (scipy's own method="asymp" uses the
  // one-sample distribution at round(en) instead: 0.0390 here).
  EXPECT_NEAR(asymptotic.p_value, 0.047600853864032525, 1e-10);
  EXPECT_NEAR(kolmogorov_sf(1.0), 0.26999967167735456, 1e-12);
  EXPECT_NEAR(kolmogorov_sf(0.5), 0.9639452436648751, 1e-12);
}

TEST(KsTest, EmptyAndIdenticalSamples) {
  const KsResult e = ks_two_sample({}, {1.0});
  EXPECT_EQ(e.statistic, 0.0);
  EXPECT_EQ(e.p_value, 1.0);
  const KsResult same = ks_two_sample({1, 2, 3}, {1, 2, 3});
  EXPECT_EQ(same.statistic, 0.0);
  EXPECT_NEAR(same.p_value, 1.0, 1e-12);
}

TEST(Bootstrap, IntervalHoldsTheMeanAndIsSeeded) {
  std::vector<double> v;
  for (int i = 0; i < 50; ++i) v.push_back((i * 37 % 50) / 50.0);
  const Interval a = bootstrap_mean_interval(v, 0.95, 2000, 7);
  const Interval b = bootstrap_mean_interval(v, 0.95, 2000, 7);
  EXPECT_EQ(a.lower, b.lower);
  EXPECT_EQ(a.upper, b.upper);
  EXPECT_LT(a.lower, mean(v));
  EXPECT_GT(a.upper, mean(v));
  // About 1.96 standard errors either side.
  const double se = stddev(v) / std::sqrt(50.0);
  EXPECT_NEAR(a.upper - a.lower, 2 * 1.96 * se, 0.25 * 2 * 1.96 * se);
  const Interval one = bootstrap_mean_interval({0.3}, 0.95, 100, 1);
  EXPECT_EQ(one.lower, 0.3);
  EXPECT_EQ(one.upper, 0.3);
}

}  // namespace
}  // namespace proprio::eval
