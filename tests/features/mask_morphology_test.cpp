#include "proprio/features/mask_morphology.hpp"

#include <gtest/gtest.h>

namespace proprio::features {
namespace {

// A single lit pixel at (x, y) in a w x h mask.
cv::Mat1b dot(int w, int h, int x, int y) {
  cv::Mat1b m(h, w, uchar{0});
  m(y, x) = 255;
  return m;
}

TEST(MaskMorphology, DiscIsAMirrorSymmetricEllipseOfItsRadius) {
  const cv::Mat d = disc(3);
  ASSERT_EQ(d.rows, 7);
  ASSERT_EQ(d.cols, 7);
  EXPECT_EQ(d.at<uchar>(3, 3), 1);  // centre
  EXPECT_EQ(d.at<uchar>(0, 3), 1);  // the radius reached along each axis
  EXPECT_EQ(d.at<uchar>(3, 0), 1);
  EXPECT_EQ(d.at<uchar>(0, 0), 0);  // corners are outside a disc
  EXPECT_EQ(d.at<uchar>(6, 6), 0);
  // Mirror-symmetric about both axes (OpenCV's ellipse is not symmetric under transposition:
  // at radius 3 its rows and columns differ by a pixel at the rim).
  for (int r = 0; r < 7; ++r) {
    for (int c = 0; c < 7; ++c) {
      EXPECT_EQ(d.at<uchar>(r, c), d.at<uchar>(6 - r, c));
      EXPECT_EQ(d.at<uchar>(r, c), d.at<uchar>(r, 6 - c));
    }
  }
  EXPECT_EQ(cv::countNonZero(disc(0)), 1);
}

TEST(MaskMorphology, DilatedGrowsADotIntoTheDiscAndLeavesTheInputAlone) {
  const cv::Mat1b m = dot(21, 21, 10, 10);
  const cv::Mat g = dilated(m, 4);
  EXPECT_EQ(cv::countNonZero(g), cv::countNonZero(disc(4)));
  EXPECT_EQ(g.at<uchar>(10, 14), 255);
  EXPECT_EQ(g.at<uchar>(10, 15), 0);
  EXPECT_EQ(cv::countNonZero(m), 1);  // a new matrix, the input unchanged
  const cv::Mat same = dilated(m, 0);
  EXPECT_EQ(cv::countNonZero(same != m), 0);
  EXPECT_NE(same.data, m.data);  // a copy, not a view
}

TEST(MaskMorphology, ErodedUndoesDilatedAwayFromTheBorder) {
  const cv::Mat1b m = dot(31, 31, 15, 15);
  const cv::Mat back = eroded(dilated(m, 5), 5);
  EXPECT_EQ(cv::countNonZero(back != m), 0);
}

TEST(MaskMorphology, OutsideOffShrinksAMaskCutByTheFrame) {
  const cv::Mat1b full(10, 10, uchar{255});
  EXPECT_EQ(cv::countNonZero(eroded(full, 2)), 100);  // outside counts as on: nothing lost
  const cv::Mat shrunk = eroded(full, 2, /*outside_off=*/true);
  EXPECT_EQ(cv::countNonZero(shrunk), 36);  // a 2 px frame lost on every side
  EXPECT_EQ(shrunk.at<uchar>(2, 2), 255);
  EXPECT_EQ(shrunk.at<uchar>(1, 5), 0);
}

}  // namespace
}  // namespace proprio::features
