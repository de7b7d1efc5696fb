// The touch frame's GrabCut refinement of M-L's mask (refine_touch_outline, private to the
// module): a known answer on a flat scene, the arm's pixels, and the guards that keep GrabCut
// from the inputs it throws on.
#include "../../src/segmentation/touch_refine.hpp"

#include <gtest/gtest.h>

#include <opencv2/core.hpp>

namespace proprio::segmentation {
namespace {

constexpr int kSize = 80;
const cv::Rect kObject(30, 30, 20, 20);  // the red square's true place
const cv::Vec3b kTable(128, 128, 128);
const cv::Vec3b kRed(30, 30, 220);

// The grey table with the red square, a little noise so that the colour mixtures have spread.
cv::Mat3b scene() {
  cv::Mat3b img(kSize, kSize, kTable);
  img(kObject).setTo(kRed);
  cv::Mat noise(img.size(), CV_8SC3);
  cv::RNG rng(7);
  rng.fill(noise, cv::RNG::UNIFORM, -6, 7);
  cv::Mat3b out;
  cv::add(img, noise, out, cv::noArray(), CV_8UC3);
  return out;
}

// A map of 1 over `r` and 0 elsewhere, and its mask.
std::pair<cv::Mat1f, cv::Mat1b> map_over(const cv::Rect& r) {
  cv::Mat1f map(kSize, kSize, 0.0F);
  map(r).setTo(1.0F);
  return {map, map > 0.5F};
}

double jaccard(const cv::Mat1b& a, const cv::Mat1b& b) {
  return static_cast<double>(cv::countNonZero(a & b)) / cv::countNonZero(a | b);
}

// A mask 4 px too big on every side (band 6 px): the table in it goes to 0, the square stays at
// the peak, pixels beyond the band are not touched, and OpenCV's generator is put back.
TEST(TouchRefine, TrimsTheTableFromAMaskTooBig) {
  const cv::Mat3b img = scene();
  auto [map, mask] = map_over(cv::Rect(26, 26, 28, 28));
  cv::Mat1b truth(kSize, kSize, uchar{0});
  truth(kObject).setTo(255);
  const double before = jaccard(mask, truth);
  cv::theRNG().state = 12345;
  refine_touch_outline(map, mask, img, {}, 6, false);
  EXPECT_EQ(cv::theRNG().state, 12345U);
  const cv::Mat1b after = map > 0.5F;
  EXPECT_LT(before, 0.55);
  EXPECT_GT(jaccard(after, truth), 0.95);
  EXPECT_EQ(cv::countNonZero(after & ~mask), 0);  // the band outside the mask had nothing red
  // Every value is 0 or the peak.
  EXPECT_EQ(cv::countNonZero((map != 0.0F) & (map != 1.0F)), 0);
  // The same inputs give the same map.
  auto [again, mask_again] = map_over(cv::Rect(26, 26, 28, 28));
  refine_touch_outline(again, mask_again, img, {}, 6, false);
  EXPECT_EQ(cv::norm(map, again, cv::NORM_INF), 0.0);
}

// The arm model's pixels: left alone, unless settle_arm, when the mask's pixels in it are
// settled by colour too (here the table's grey: out).
TEST(TouchRefine, SettlesTheArmsPixelsOnlyWhenAsked) {
  const cv::Mat3b img = scene();
  cv::Mat1b arm(kSize, kSize, uchar{0});
  arm(cv::Rect(26, 26, 28, 4)).setTo(255);  // across the mask's top edge, grey in the image
  auto [kept, mask] = map_over(cv::Rect(26, 26, 28, 28));
  refine_touch_outline(kept, mask, img, arm, 6, false);
  EXPECT_EQ(cv::countNonZero((kept > 0.5F) & arm), cv::countNonZero(mask & arm));
  auto [settled, mask2] = map_over(cv::Rect(26, 26, 28, 28));
  refine_touch_outline(settled, mask2, img, arm, 6, true);
  EXPECT_EQ(cv::countNonZero((settled > 0.5F) & arm), 0);
}

// Inputs GrabCut cannot take leave the map as it was (and do not throw): a mask over the whole
// frame (no background samples), a mask the band erodes away (nothing certainly object), an
// empty mask.
TEST(TouchRefine, LeavesTheMapWhenGrabCutHasTooFewSamples) {
  const cv::Mat3b img = scene();
  for (const cv::Rect r : {cv::Rect(0, 0, kSize, kSize), cv::Rect(38, 38, 6, 6), cv::Rect()}) {
    auto [map, mask] = map_over(r);
    const cv::Mat1f before = map.clone();
    EXPECT_NO_THROW(refine_touch_outline(map, mask, img, {}, 6, false)) << r;
    EXPECT_EQ(cv::norm(map, before, cv::NORM_INF), 0.0) << r;
  }
}

}  // namespace
}  // namespace proprio::segmentation
