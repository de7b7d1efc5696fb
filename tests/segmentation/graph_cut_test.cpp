// Graph cuts: the max-flow value is the minimum energy (brute force on tiny grids), a noisy disc
// is recovered, real images (opencv-doc) cut along their edges, bad input is refused.
#include "proprio/segmentation/graph_cut.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <random>

#include "proprio/core/error.hpp"

namespace proprio::segmentation {
namespace {

double jaccard(const cv::Mat1b& a, const cv::Mat1b& b) {
  const double inter = cv::countNonZero(a & b);
  const double uni = cv::countNonZero(a | b);
  return uni == 0 ? 1.0 : inter / uni;
}

// A random problem on a w x h grid; seeds where `seeded`.
GraphCutProblem random_problem(int w, int h, unsigned seed, bool seeded) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<float> u(0.f, 3.f);
  std::uniform_int_distribution<int> pix(0, 255);
  GraphCutProblem p;
  p.image = cv::Mat3b(h, w);
  p.cost_object = cv::Mat1f(h, w);
  p.cost_background = cv::Mat1f(h, w);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      p.image.at<cv::Vec3b>(y, x) = cv::Vec3b(pix(gen), pix(gen), pix(gen));
      p.cost_object(y, x) = u(gen);
      p.cost_background(y, x) = u(gen);
    }
  }
  if (seeded) {
    p.seeds = cv::Mat1b(h, w, kSeedFree);
    p.seeds(0, 0) = kSeedObject;
    p.seeds(h - 1, w - 1) = kSeedBackground;
  }
  return p;
}

class BruteForce : public ::testing::TestWithParam<std::tuple<int, bool>> {};

TEST_P(BruteForce, FlowEqualsTheMinimumEnergyOverAllLabellings) {
  const auto [connectivity, seeded] = GetParam();
  for (unsigned seed = 1; seed <= 4; ++seed) {
    const int w = 4, h = 3;
    const GraphCutProblem p = random_problem(w, h, seed, seeded);
    GraphCutOptions o;
    o.connectivity = connectivity;
    o.smoothness = 1.5;
    o.max_side = 0;
    const GraphCutResult r = graph_cut(p, o);
    double best = std::numeric_limits<double>::infinity();
    cv::Mat1b mask(h, w);
    for (int bits = 0; bits < (1 << (w * h)); ++bits) {
      for (int i = 0; i < w * h; ++i) mask(i / w, i % w) = ((bits >> i) & 1) ? 255 : 0;
      best = std::min(best, cut_energy(p, o, mask));
    }
    EXPECT_NEAR(r.summary.flow, best, 1e-9) << "seed " << seed;
    EXPECT_NEAR(cut_energy(p, o, r.mask), best, 1e-9) << "the returned cut is a minimum one";
    if (seeded) {
      EXPECT_EQ(r.mask(0, 0), 255);
      EXPECT_EQ(r.mask(h - 1, w - 1), 0);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Grids, BruteForce,
                         ::testing::Combine(::testing::Values(4, 8), ::testing::Bool()));

TEST(GraphCut, WithoutPairwiseTermItIsTheUnaryDecision) {
  const GraphCutProblem p = random_problem(30, 20, 9, false);
  GraphCutOptions o;
  o.smoothness = 0;
  const GraphCutResult r = graph_cut(p, o);
  const cv::Mat1b expected = p.cost_object < p.cost_background;
  // Ties (equal rounded costs) may go either way; random floats make them vanishingly rare.
  EXPECT_EQ(cv::countNonZero(r.mask != expected), 0);
}

// A disc whose probability is barely above the background's, under heavy noise.
struct NoisyDisc {
  cv::Mat1b truth;
  cv::Mat1f probability;
};

NoisyDisc noisy_disc(int w, int h, double noise, unsigned seed) {
  NoisyDisc d;
  d.truth = cv::Mat1b(h, w, uchar(0));
  cv::circle(d.truth, {w / 2, h / 2}, h / 4, cv::Scalar(255), cv::FILLED);
  std::mt19937 gen(seed);
  std::normal_distribution<float> n(0.f, static_cast<float>(noise));
  d.probability = cv::Mat1f(h, w);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const float base = d.truth(y, x) ? 0.65f : 0.35f;
      d.probability(y, x) = std::clamp(base + n(gen), 0.f, 1.f);
    }
  }
  return d;
}

TEST(GraphCut, RecoversANoisyDisc) {
  const NoisyDisc d = noisy_disc(160, 120, 0.3, 3);
  GraphCutProblem p;
  unary_from_probability(d.probability, p.cost_object, p.cost_background);
  GraphCutOptions o;
  o.smoothness = 3.0;
  const GraphCutResult r = graph_cut(p, o);
  const cv::Mat1b thresholded = d.probability > 0.5f;
  EXPECT_LT(jaccard(thresholded, d.truth), 0.6) << "the noise is heavy";
  EXPECT_GT(jaccard(r.mask, d.truth), 0.95);
  EXPECT_FALSE(r.summary.reduced);
  EXPECT_GT(r.summary.flow, 0);
}

TEST(GraphCut, ReducedGridAgreesWithTheFullOne) {
  const NoisyDisc d = noisy_disc(640, 480, 0.3, 5);
  GraphCutProblem p;
  unary_from_probability(d.probability, p.cost_object, p.cost_background);
  GraphCutOptions full;
  full.smoothness = 3.0;
  full.max_side = 0;
  GraphCutOptions small = full;
  small.max_side = 320;
  const GraphCutResult a = graph_cut(p, full);
  const GraphCutResult b = graph_cut(p, small);
  EXPECT_TRUE(b.summary.reduced);
  EXPECT_EQ(b.summary.width, 320);
  EXPECT_EQ(b.summary.height, 240);
  EXPECT_EQ(b.mask.size(), d.truth.size());
  EXPECT_GT(jaccard(a.mask, d.truth), 0.97);
  EXPECT_GT(jaccard(b.mask, d.truth), 0.97);
  std::printf(
      "640x480 8-connected: build %.3f s, flow %.3f s; at 320x240: build %.3f s, flow %.3f s\n",
      a.summary.seconds_build, a.summary.seconds_flow, b.summary.seconds_build,
      b.summary.seconds_flow);
}

// Real photographs: a disc of baboon.jpg pasted on fruits.jpg, a weak noisy cue for the disc. The
// contrast term puts the boundary on the photographs' real edge, which a plain Potts term
// (no image) follows less well.
TEST(GraphCut, RealImagesCutAlongTheEdge) {
  const std::string dir = PROPRIO_OPENCV_SAMPLES;
  cv::Mat fruits = cv::imread(dir + "/fruits.jpg");
  cv::Mat baboon = cv::imread(dir + "/baboon.jpg");
  ASSERT_FALSE(fruits.empty());
  ASSERT_FALSE(baboon.empty());
  cv::resize(fruits, fruits, {320, 240});
  cv::resize(baboon, baboon, {320, 240});
  cv::Mat1b truth(240, 320, uchar(0));
  cv::circle(truth, {150, 120}, 70, cv::Scalar(255), cv::FILLED);
  cv::Mat image = fruits.clone();
  baboon.copyTo(image, truth);
  // The cue: a blurred disc that is offset and wider than the truth, plus noise.
  const NoisyDisc noise = noisy_disc(320, 240, 0.25, 11);
  cv::Mat1f cue(240, 320, 0.4f);
  cv::circle(cue, {160, 125}, 80, cv::Scalar(0.6), cv::FILLED);
  cv::GaussianBlur(cue, cue, {0, 0}, 10);
  cue += noise.probability - 0.5f + 0.0f;
  cv::Mat1f p;
  cv::min(cv::max(cue, 0.0), 1.0, p);

  GraphCutProblem with_image;
  unary_from_probability(p, with_image.cost_object, with_image.cost_background);
  with_image.image = image;
  GraphCutProblem potts = with_image;
  potts.image = cv::Mat();
  GraphCutOptions o;
  o.smoothness = 4.0;
  const double j_contrast = jaccard(graph_cut(with_image, o).mask, truth);
  const double j_potts = jaccard(graph_cut(potts, o).mask, truth);
  std::printf("real images: Jaccard %.3f with contrast, %.3f Potts\n", j_contrast, j_potts);
  EXPECT_GT(j_contrast, 0.8);
  EXPECT_GT(j_contrast, j_potts + 0.05);
}

TEST(GraphCut, HardSeedsWinOverUnaryCosts) {
  GraphCutProblem p;
  p.cost_object = cv::Mat1f(10, 10, 5.f);  // everything prefers background
  p.cost_background = cv::Mat1f(10, 10, 0.f);
  p.seeds = cv::Mat1b(10, 10, kSeedFree);
  p.seeds(4, 4) = kSeedObject;
  GraphCutOptions o;
  const GraphCutResult r = graph_cut(p, o);
  EXPECT_EQ(r.mask(4, 4), 255);
  EXPECT_EQ(cv::countNonZero(r.mask), 1);
}

TEST(GraphCut, ContrastBetaOfAKnownImage) {
  // A 2x1 image: one pair, |d|^2 = 3 * 10^2 = 300; beta = 1 / (2 * 300).
  cv::Mat3b img(1, 2);
  img(0, 0) = cv::Vec3b(0, 0, 0);
  img(0, 1) = cv::Vec3b(10, 10, 10);
  EXPECT_NEAR(contrast_beta(img, 4), 1.0 / 600.0, 1e-12);
  EXPECT_EQ(contrast_beta(cv::Mat3b(5, 5, cv::Vec3b(7, 7, 7)), 8), 0.0);
}

TEST(GraphCut, BadInputIsRefused) {
  GraphCutOptions o;
  GraphCutProblem p;
  EXPECT_THROW(graph_cut(p, o), Error);  // empty grid
  p.cost_object = cv::Mat1f(10, 10, 1.f);
  p.cost_background = cv::Mat1f(10, 12, 1.f);
  try {
    graph_cut(p, o);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("different size"), std::string::npos) << e.what();
  }
  p.cost_background = cv::Mat1f(10, 10, 1.f);
  p.cost_object(3, 3) = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(graph_cut(p, o), Error);
  p.cost_object(3, 3) = -1.f;
  EXPECT_THROW(graph_cut(p, o), Error);
  p.cost_object(3, 3) = 1.f;
  p.seeds = cv::Mat1b(10, 10, uchar(3));
  EXPECT_THROW(graph_cut(p, o), Error);
  cv::Mat1f bad(4, 4, 0.5f);
  bad(1, 1) = 1.5f;
  cv::Mat1f a, b;
  EXPECT_THROW(unary_from_probability(bad, a, b), Error);
  GraphCutOptions bo;
  bo.connectivity = 6;
  EXPECT_THROW(bo.validate(), Error);
  bo = {};
  bo.smoothness = -1;
  EXPECT_THROW(bo.validate(), Error);
  bo = {};
  bo.max_side = 3;
  EXPECT_THROW(bo.validate(), Error);
}

}  // namespace
}  // namespace proprio::segmentation

namespace proprio::segmentation {
namespace {

TEST(MlGraphCut, WithoutSmoothnessItIsTheThresholdedMap) {
  const NoisyDisc d = noisy_disc(120, 90, 0.2, 21);
  const cv::Mat1f map = d.probability * 0.4f;  // not normalised: the max is what counts
  MlGraphCutOptions o;
  o.graph_cut.smoothness = 0;
  o.mask_fraction = 0.6;
  double mx = 0;
  cv::minMaxLoc(map, nullptr, &mx);
  const cv::Mat1b expected = map > 0.6 * mx;
  const cv::Mat1b got = ml_graph_cut(cv::Mat3b(map.size(), cv::Vec3b(0, 0, 0)), map, o).mask;
  EXPECT_LE(cv::countNonZero(got != expected), 2);  // ties at exactly f may go either way
}

TEST(MlGraphCut, SmoothsANoisyMapTowardsTheObject) {
  const NoisyDisc d = noisy_disc(160, 120, 0.25, 23);
  MlGraphCutOptions o;
  o.mask_fraction = 0.5;
  const cv::Mat1b cut =
      ml_graph_cut(cv::Mat1b(d.probability.size(), uchar(0)), d.probability, o).mask;
  double mx = 0;
  cv::minMaxLoc(d.probability, nullptr, &mx);
  const cv::Mat1b thresholded = d.probability >= 0.5 * mx;
  EXPECT_GT(jaccard(cut, d.truth), jaccard(thresholded, d.truth) + 0.1);
  // A zero map is no object; mismatched sizes are an error.
  EXPECT_EQ(cv::countNonZero(ml_graph_cut(cv::Mat1b(10, 10), cv::Mat1f(10, 10, 0.f), o).mask), 0);
  EXPECT_THROW(ml_graph_cut(cv::Mat1b(10, 11), cv::Mat1f(10, 10, 0.f), o), Error);
  o.mask_fraction = 0;
  EXPECT_THROW(o.validate(), Error);
}

}  // namespace
}  // namespace proprio::segmentation
