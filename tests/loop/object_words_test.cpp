// Object words (8.1.2) and top-down recognition (8.4-8.7) on synthetic descriptors with known
// answers.
#include "proprio/loop/object_words.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "proprio/core/random.hpp"

namespace proprio::loop {
namespace {

constexpr int kDim = 8;

// A unit vector along axis a, jittered by `noise` (seeded), renormalised.
Eigen::RowVectorXd around(int a, double noise, core::Rng& rng) {
  Eigen::RowVectorXd v = Eigen::RowVectorXd::Zero(kDim);
  v(a) = 1;
  for (int i = 0; i < kDim; ++i) v(i) += rng.uniform(-noise, noise);
  return v / v.norm();
}

Eigen::MatrixXd cluster_frame(const std::vector<int>& axes, int per_axis, core::Rng& rng) {
  Eigen::MatrixXd x(static_cast<Eigen::Index>(axes.size()) * per_axis, kDim);
  Eigen::Index r = 0;
  for (int a : axes) {
    for (int i = 0; i < per_axis; ++i) x.row(r++) = around(a, 0.05, rng);
  }
  return x;
}

TEST(ObjectWords, UnitDescriptorsHaveUnitLength) {
  cv::Mat d = (cv::Mat_<float>(2, 3) << 3, 4, 0, 0, 0, 0);
  const Eigen::MatrixXd x = unit_descriptors(d);
  EXPECT_NEAR(x(0, 0), 0.6, 1e-12);
  EXPECT_NEAR(x(0, 1), 0.8, 1e-12);
  EXPECT_EQ(x.row(1).norm(), 0.0);  // a zero row stays zero
}

TEST(ObjectWords, MeanShiftFindsTheClusters) {
  core::Rng rng(3);
  const Eigen::MatrixXd x = cluster_frame({0, 3, 5}, 40, rng);
  ObjectWordOptions o;
  o.bandwidth = 0.2;
  const Eigen::MatrixXd w = mean_shift_words(x, o, rng);
  ASSERT_EQ(w.rows(), 3);
  for (int a : {0, 3, 5}) {
    double best = 1e9;
    for (Eigen::Index j = 0; j < w.rows(); ++j) {
      Eigen::RowVectorXd e = Eigen::RowVectorXd::Zero(kDim);
      e(a) = 1;
      best = std::min(best, (w.row(j) - e).norm());
    }
    EXPECT_LT(best, 0.1) << "axis " << a;
  }
}

TEST(ObjectWords, FrameDistributionSumsToOneAndPeaksAtTheNearestWord) {
  Eigen::MatrixXd words = Eigen::MatrixXd::Zero(2, kDim);
  words(0, 0) = 1;
  words(1, 1) = 1;
  core::Rng rng(1);
  const Eigen::MatrixXd x = cluster_frame({1}, 10, rng);
  const Eigen::VectorXd p = frame_word_distribution(words, x, 0.1);
  EXPECT_NEAR(p.sum(), 1.0, 1e-12);
  EXPECT_GT(p(1), 0.99);
}

TEST(ObjectWords, IncrementalMeanMovesEachWordTowardItsNearestDescriptor) {
  core::Rng rng(5);
  ObjectWordOptions o;
  o.bandwidth = 0.2;
  std::vector<Eigen::MatrixXd> frames;
  frames.reserve(6);
  for (int f = 0; f < 4; ++f) frames.push_back(cluster_frame({0, 2}, 15, rng));
  ObjectModel m;
  ASSERT_TRUE(m.first_push(frames, o, rng));
  ASSERT_EQ(m.num_words(), 2);
  const Eigen::MatrixXd before = m.words();
  // One descriptor per frame, exactly on axis 0 and axis 2: w <- (1 w + d) / 2 for each word.
  Eigen::MatrixXd d = Eigen::MatrixXd::Zero(2, kDim);
  d(0, 0) = 1;
  d(1, 2) = 1;
  m.later_push({d, d}, o, rng);
  for (Eigen::Index j = 0; j < 2; ++j) {
    Eigen::Index a = 0;
    before.row(j).maxCoeff(&a);
    const Eigen::Index row = a == 0 ? 0 : 1;
    const Eigen::RowVectorXd expect = (before.row(j) + d.row(row)) / 2;
    EXPECT_NEAR((m.words().row(j) - expect).norm(), 0.0, 1e-12);
  }
  EXPECT_TRUE(m.learned());
}

TEST(ObjectWords, BothDirichletUpdatesPredictTheNextPush) {
  core::Rng rng(7);
  ObjectWordOptions o;
  o.bandwidth = 0.2;
  std::vector<Eigen::MatrixXd> frames;
  frames.reserve(6);
  for (int f = 0; f < 6; ++f) frames.push_back(cluster_frame({0, 2, 4}, 10 + f, rng));
  ObjectModel m;
  ASSERT_TRUE(m.first_push(frames, o, rng));
  std::vector<Eigen::MatrixXd> next;
  next.reserve(6);
  for (int f = 0; f < 6; ++f) next.push_back(cluster_frame({0, 2, 4}, 12, rng));
  const auto ll = m.predictive_log_likelihood(next, o);
  ASSERT_TRUE(ll.has_value());
  EXPECT_TRUE(std::isfinite(ll->first));
  // Before any update both are the same Dirichlet.
  EXPECT_DOUBLE_EQ(ll->first, ll->second);
  o.update = DirichletUpdate::kFiftyFifty;
  m.later_push(next, o, rng);
  const auto ll2 = m.predictive_log_likelihood(next, o);
  ASSERT_TRUE(ll2.has_value());
  EXPECT_NE(ll2->first, ll2->second);  // exact and 50:50 now differ
}

TEST(ObjectWords, TopDownRecognitionFindsTheObjectAmongOthers) {
  core::Rng rng(11);
  ObjectWordOptions o;
  o.bandwidth = 0.2;
  o.density_sigma = 4;
  o.min_features = 5;
  std::vector<Eigen::MatrixXd> frames;
  frames.reserve(6);
  for (int f = 0; f < 5; ++f) frames.push_back(cluster_frame({0, 1}, 12, rng));
  ObjectModel m;
  ASSERT_TRUE(m.first_push(frames, o, rng));
  // The object's descriptors around (40, 30), another object's (axes 5, 6) around (120, 80).
  std::vector<cv::Point2f> pts;
  pts.reserve(80);
  Eigen::MatrixXd x(80, kDim);
  for (int i = 0; i < 40; ++i) {
    const int row = i / 8;
    pts.emplace_back(35.0F + static_cast<float>(i % 8), 25.0F + static_cast<float>(2 * row));
    x.row(i) = around(i % 2, 0.05, rng);
  }
  for (int i = 0; i < 40; ++i) {
    const int row = i / 8;
    pts.emplace_back(115.0F + static_cast<float>(i % 8), 75.0F + static_cast<float>(2 * row));
    x.row(40 + i) = around(5 + (i % 2), 0.05, rng);
  }
  const TopDownResult r = recognise_top_down(m, pts, x, cv::Size(160, 120), o);
  ASSERT_TRUE(r.found) << r.message;
  EXPECT_NEAR(r.centre.x(), 38.5, 4.0);
  EXPECT_NEAR(r.centre.y(), 29.0, 4.0);
  EXPECT_EQ(r.mask(80, 120), 0);
  EXPECT_GE(r.features, 5);
}

TEST(ObjectWords, NothingToRecogniseWithoutAModel) {
  ObjectModel m;
  const TopDownResult r =
      recognise_top_down(m, {cv::Point2f(1, 1)}, Eigen::MatrixXd::Ones(1, kDim), {10, 10}, {});
  EXPECT_FALSE(r.found);
}

}  // namespace
}  // namespace proprio::loop
