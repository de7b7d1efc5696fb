#include "proprio/features/colour_words.hpp"

#include <gtest/gtest.h>

#include <opencv2/core.hpp>

#include "proprio/core/error.hpp"

namespace proprio::features {
namespace {

TEST(ColourWords, KnownColoursFallInTheirBins) {
  const ColourWordOptions o;  // 12 hues x 2 saturations + 4 greys = 28 words
  ASSERT_EQ(o.count(), 28);
  EXPECT_EQ(colour_word({0, 0, 255}, o), 0 * 2 + 1);      // red, vivid: hue 0
  EXPECT_EQ(colour_word({0, 255, 0}, o), 4 * 2 + 1);      // green: 120 degrees
  EXPECT_EQ(colour_word({255, 0, 0}, o), 8 * 2 + 1);      // blue: 240 degrees
  EXPECT_EQ(colour_word({0, 255, 255}, o), 2 * 2 + 1);    // yellow: 60 degrees
  EXPECT_EQ(colour_word({160, 160, 255}, o), 0 * 2 + 0);  // pale red: S 0.37, the lower level
  EXPECT_EQ(colour_word({0, 0, 0}, o), 24);               // black: the darkest grey
  EXPECT_EQ(colour_word({128, 128, 128}, o), 26);         // mid grey
  EXPECT_EQ(colour_word({255, 255, 255}, o), 27);         // white
  EXPECT_EQ(colour_word({200, 215, 210}, o), 27);         // S 0.07: grey whatever its hue
}

TEST(ColourWords, EachKeypointReadsTheMeanOfItsPatch) {
  // Left half red, right half blue: keypoints well inside a half read its colour; those by the
  // border read the mean of their 7 x 7 patch: 4 red columns and 3 blue ones are a purple of hue
  // 315 degrees (bin 10), 3 red and 4 blue one of 285 degrees (bin 9).
  cv::Mat3b image(20, 40, cv::Vec3b(0, 0, 255));
  image(cv::Rect(20, 0, 20, 20)).setTo(cv::Vec3b(255, 0, 0));
  const std::vector<cv::KeyPoint> k = {{cv::Point2f(5, 10), 8},
                                       {cv::Point2f(34, 10), 8},
                                       {cv::Point2f(19.4F, 10), 8},
                                       {cv::Point2f(20.4F, 10), 8}};
  ColourWordOptions o;
  const auto w = colour_words(image, k, o);
  ASSERT_EQ(w.size(), 4U);
  EXPECT_EQ(w[0], 1);
  EXPECT_EQ(w[1], 17);
  EXPECT_EQ(w[2], 10 * 2 + 1);
  EXPECT_EQ(w[3], 9 * 2 + 1);
  o.radius = 0;  // no patch: the keypoint's own (rounded) pixel
  const auto own = colour_words(image, k, o);
  EXPECT_EQ(own[2], 1);
  EXPECT_EQ(own[3], 17);
  EXPECT_EQ(image(10, 19), cv::Vec3b(0, 0, 255));  // the caller's image left as it was
}

TEST(ColourWords, TurningTheImageTurnsNoWord) {
  cv::Mat3b image(30, 30);
  cv::randu(image, cv::Scalar::all(0), cv::Scalar::all(255));
  std::vector<cv::KeyPoint> k;
  std::vector<cv::KeyPoint> turned;
  for (int y = 2; y < 30; y += 5) {
    for (int x = 1; x < 30; x += 4) {
      k.emplace_back(cv::Point2f(static_cast<float>(x), static_cast<float>(y)), 8);
      // cv::ROTATE_90_CLOCKWISE maps (x, y) to (rows - 1 - y, x).
      turned.emplace_back(cv::Point2f(static_cast<float>(29 - y), static_cast<float>(x)), 8);
    }
  }
  cv::Mat3b rotated;
  cv::rotate(image, rotated, cv::ROTATE_90_CLOCKWISE);
  const ColourWordOptions o;
  EXPECT_EQ(colour_words(image, k, o), colour_words(rotated, turned, o));
}

TEST(ColourWords, GreyImagesGiveGreyWordsAndBadInputThrows) {
  const cv::Mat1b grey(10, 10, uchar{200});
  const ColourWordOptions o;
  const auto w = colour_words(grey, {cv::KeyPoint(cv::Point2f(4, 4), 8)}, o);
  EXPECT_EQ(w, std::vector<std::int32_t>{27});  // 200 * 4 / 256 = 3
  EXPECT_TRUE(colour_words(grey, {}, o).empty());
  EXPECT_THROW(colour_words(grey, {cv::KeyPoint(cv::Point2f(10, 4), 8)}, o), Error);
  EXPECT_THROW(colour_words(cv::Mat(), {}, o), Error);
  EXPECT_THROW(colour_words(cv::Mat(4, 4, CV_32F), {}, o), Error);
  ColourWordOptions bad;
  bad.hue_bins = 0;
  EXPECT_THROW(bad.validate(), Error);
  bad = {};
  bad.grey_below = 1.5;
  EXPECT_THROW(colour_words(grey, {}, bad), Error);
}

TEST(ColourWords, CountsOverAMaskAreEachPixelsPatchWord) {
  // Left half red, right half blue, as above. A mask of columns 5-14 (well inside the red) counts
  // 10 x 20 red pixels; one of columns 5-24 adds the border's purples (columns 17-22, whose 7 x 7
  // patches straddle it) and blue; every count equals colour_words at that pixel.
  cv::Mat3b image(20, 40, cv::Vec3b(0, 0, 255));
  image(cv::Rect(20, 0, 20, 20)).setTo(cv::Vec3b(255, 0, 0));
  const ColourWordOptions o;
  cv::Mat1b mask(image.size(), uchar{0});
  mask(cv::Rect(5, 0, 10, 20)).setTo(255);
  std::vector<double> want(28, 0.0);
  want[1] = 200;
  EXPECT_EQ(colour_word_counts(image, mask, o), want);
  mask(cv::Rect(5, 0, 20, 20)).setTo(255);
  std::vector<cv::KeyPoint> k;
  for (int y = 0; y < 20; ++y) {
    for (int x = 5; x < 25; ++x) {
      k.emplace_back(cv::Point2f(static_cast<float>(x), static_cast<float>(y)), 8);
    }
  }
  want.assign(28, 0.0);
  for (const std::int32_t w : colour_words(image, k, o)) want[static_cast<std::size_t>(w)] += 1;
  const auto counts = colour_word_counts(image, mask, o);
  EXPECT_EQ(counts, want);
  EXPECT_GT(counts[17], 0);          // blue
  EXPECT_GT(counts[10 * 2 + 1], 0);  // the border's purple
  EXPECT_EQ(colour_word_counts(image, cv::Mat1b(image.size(), uchar{0}), o),
            std::vector<double>(28, 0.0));
  EXPECT_THROW(colour_word_counts(image, cv::Mat1b(10, 10, uchar{255}), o), Error);
  EXPECT_THROW(colour_word_counts(image, cv::Mat1f(image.size(), 1.0F), o), Error);
  EXPECT_THROW(colour_word_counts(cv::Mat(), cv::Mat(), o), Error);
}

TEST(ColourWords, DocumentsNumberColourWordsAfterTheVocabulary) {
  EXPECT_EQ(with_colour_words({3, 0, 99}, {27, 0, 5}, 100),
            (std::vector<std::int32_t>{3, 0, 99, 127, 100, 105}));
  EXPECT_TRUE(with_colour_words({}, {}, 100).empty());
  EXPECT_THROW(with_colour_words({1, 2}, {1}, 100), Error);
  EXPECT_THROW(with_colour_words({1}, {-1}, 100), Error);
}

}  // namespace
}  // namespace proprio::features
