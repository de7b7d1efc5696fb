#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include <opencv2/calib3d.hpp>
#include <opencv2/features2d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "../support/hex_bytes.hpp"
#include "proprio/features/features.hpp"
#include "proprio/features/sift.hpp"
#include "proprio/features/vocabulary.hpp"
#include "test_util.hpp"

namespace proprio::features {
namespace {

using test::expect_error;

const std::string kSamples = PROPRIO_OPENCV_SAMPLES;

TEST(DenseSift, GridCountAndPlacement) {
  DenseSiftOptions o;  // step 8, 16 px patches, margin 8
  const auto grid = dense_grid({100, 80}, o);
  // x in 8, 16, ..., 88 (11 points: 91 would leave less than 8 px); y in 8, ..., 64 (8 points).
  ASSERT_EQ(grid.size(), 11U * 8U);
  EXPECT_FLOAT_EQ(grid.front().pt.x, 8);
  EXPECT_FLOAT_EQ(grid.front().pt.y, 8);
  EXPECT_FLOAT_EQ(grid[1].pt.x, 16);
  EXPECT_FLOAT_EQ(grid.back().pt.x, 88);
  EXPECT_FLOAT_EQ(grid.back().pt.y, 64);
  EXPECT_FLOAT_EQ(grid.front().size, 16.0F / 6);
  o.margin = 0;
  o.step = 10;
  EXPECT_EQ(dense_grid({101, 51}, o).size(), 11U * 6U);
  EXPECT_TRUE(dense_grid({16, 16}, DenseSiftOptions{}).empty());
}

// Session 31: rotate_sift_descriptors is dense_sift of the turned image (an exact permutation),
// and with_right_angle_turns makes a bag of words that does not change when the image turns.
TEST(DenseSift, QuarterTurnIsAPermutationOfTheDescriptor) {
  const cv::Mat full = cv::imread(kSamples + "/box.png", cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(full.empty());
  ASSERT_GE(std::min(full.rows, full.cols), 161);
  // 161 px square, step 4, margin 8: the turned grid falls on the grid (160 - 8 = 152 = 8 + 36 x
  // 4).
  const cv::Mat img = full(cv::Rect(0, 0, 161, 161)).clone();
  DenseSiftOptions o;
  o.step = 4;
  const Features a = dense_sift(img, o);
  cv::Mat turned;
  cv::rotate(img, turned, cv::ROTATE_90_COUNTERCLOCKWISE);
  const Features b = dense_sift(turned, o);
  ASSERT_EQ(a.size(), b.size());
  const cv::Mat a1 = rotate_sift_descriptors(a.descriptors, 1);
  const int n = img.cols;
  int matched = 0;
  double err = 0;
  double err_unturned = 0;
  int off_by_one = 0;
  for (int i = 0; i < a.size(); ++i) {
    const cv::Point2f p = a.keypoints[static_cast<std::size_t>(i)].pt;
    const cv::Point2f q(p.y, static_cast<float>(n - 1) - p.x);  // where the turn takes p
    for (int j = 0; j < b.size(); ++j) {
      if (cv::norm(b.keypoints[static_cast<std::size_t>(j)].pt - q) < 0.01) {
        err = std::max(err, cv::norm(a1.row(i), b.descriptors.row(j), cv::NORM_INF));
        cv::Mat differ;
        cv::absdiff(a1.row(i), b.descriptors.row(j), differ);
        off_by_one += cv::countNonZero(differ > 0.5F);
        err_unturned = std::max(err_unturned,
                                cv::norm(a.descriptors.row(i), b.descriptors.row(j), cv::NORM_INF));
        ++matched;
        break;
      }
    }
  }
  EXPECT_EQ(matched, a.size());
  EXPECT_LE(err, 1.0);  // the same descriptor, to OpenCV's rounding to whole units
  EXPECT_LT(off_by_one, a.size() * 128 / 100);  // and that rarely (< 1 % of the values)
  EXPECT_GT(err_unturned, 10.0);                // upright SIFT does change with the turn
  // Four quarter turns: the identity; two: the same as two single ones.
  EXPECT_EQ(cv::norm(rotate_sift_descriptors(a.descriptors, 4), a.descriptors, cv::NORM_INF), 0);
  EXPECT_EQ(cv::norm(rotate_sift_descriptors(a.descriptors, -1),
                     rotate_sift_descriptors(a.descriptors, 3), cv::NORM_INF),
            0);
  EXPECT_EQ(cv::norm(rotate_sift_descriptors(a1, 1), rotate_sift_descriptors(a.descriptors, 2),
                     cv::NORM_INF),
            0);

  // The bag of words of the four turns is the same for the image and the turned image; the
  // plain bags differ.
  const Vocabulary vocabulary(a.descriptors.rowRange(0, 40).clone());
  const auto histogram = [&](const cv::Mat& d) {
    std::vector<int> h(static_cast<std::size_t>(vocabulary.size()), 0);
    for (const int w : bag_of_words(vocabulary, d)) ++h[static_cast<std::size_t>(w)];
    return h;
  };
  EXPECT_EQ(histogram(with_right_angle_turns(a.descriptors)),
            histogram(with_right_angle_turns(b.descriptors)));
  EXPECT_NE(histogram(a.descriptors), histogram(b.descriptors));
  EXPECT_EQ(with_right_angle_turns(a.descriptors).rows, 4 * a.size());
  EXPECT_TRUE(with_right_angle_turns(cv::Mat()).empty());
  test::expect_error([] { (void)rotate_sift_descriptors(cv::Mat(2, 64, CV_32F), 1); }, "128");
}

TEST(DenseSift, OneDescriptorPerGridPoint) {
  const cv::Mat img = cv::imread(kSamples + "/box.png", cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(img.empty());
  const auto f = dense_sift(img);
  const auto grid = dense_grid(img.size());
  ASSERT_EQ(f.size(), static_cast<int>(grid.size()));
  EXPECT_EQ(f.descriptors.rows, f.size());
  EXPECT_EQ(f.descriptors.cols, 128);
  EXPECT_EQ(f.descriptors.type(), CV_32F);
  EXPECT_TRUE(cv::checkRange(f.descriptors));
  EXPECT_GT(cv::norm(f.descriptors), 0);
  // Colour input gives the same as its grey version.
  const cv::Mat colour = cv::imread(kSamples + "/box.png", cv::IMREAD_COLOR);
  cv::Mat grey;
  cv::cvtColor(colour, grey, cv::COLOR_BGR2GRAY);
  EXPECT_EQ(cv::norm(dense_sift(colour).descriptors, dense_sift(grey).descriptors), 0);
  // Too small for one patch: no features, no error.
  const auto none = dense_sift(cv::Mat(10, 10, CV_8U, cv::Scalar(0)));
  EXPECT_TRUE(none.empty());
  EXPECT_EQ(none.descriptors.cols, 128);
}

TEST(Sift, GraffitiMatchesAgreeWithTheTrueHomography) {
  const cv::Mat a = cv::imread(kSamples + "/graf1.png", cv::IMREAD_GRAYSCALE);
  const cv::Mat b = cv::imread(kSamples + "/graf3.png", cv::IMREAD_GRAYSCALE);
  cv::FileStorage fs(kSamples + "/H1to3p.xml", cv::FileStorage::READ);
  cv::Mat H;
  fs["H13"] >> H;
  ASSERT_FALSE(a.empty());
  ASSERT_FALSE(b.empty());
  ASSERT_EQ(H.size(), cv::Size(3, 3));
  SiftOptions o;
  o.max_features = 2000;
  const auto fa = detect_sift(a, o);
  const auto fb = detect_sift(b, o);
  ASSERT_GT(fa.size(), 500);
  ASSERT_GT(fb.size(), 500);
  ASSERT_LE(fa.size(), 2000 + 50);  // OpenCV keeps ties at the cut
  // Lowe's ratio test, then the true homography: most surviving matches land within 3 px
  // (graf3 is seen 40 degrees off graf1: SIFT keeps about two thirds; chance would be ~0).
  cv::BFMatcher matcher(cv::NORM_L2);
  std::vector<std::vector<cv::DMatch>> knn;
  matcher.knnMatch(fa.descriptors, fb.descriptors, knn, 2);
  int kept = 0;
  int good = 0;
  for (const auto& m : knn) {
    if (m.size() < 2 || m[0].distance > 0.7F * m[1].distance) continue;
    ++kept;
    const auto& p = fa.keypoints[static_cast<std::size_t>(m[0].queryIdx)].pt;
    const auto& q = fb.keypoints[static_cast<std::size_t>(m[0].trainIdx)].pt;
    const cv::Mat x = H * (cv::Mat_<double>(3, 1) << p.x, p.y, 1.0);
    const double u = x.at<double>(0) / x.at<double>(2);
    const double v = x.at<double>(1) / x.at<double>(2);
    if (std::hypot(u - q.x, v - q.y) < 3.0) ++good;
  }
  EXPECT_GT(good, 100);
  EXPECT_GT(good, 0.55 * kept) << good << " of " << kept;
}

TEST(Sift, BadInput) {
  expect_error([] { detect_sift(cv::Mat()); }, "empty image");
  expect_error([] { dense_sift(cv::Mat()); }, "empty image");
  expect_error([] { detect_sift(cv::Mat(20, 20, CV_32F, cv::Scalar(0))); }, "8-bit");
  expect_error([] { dense_sift(cv::Mat(20, 20, CV_8UC2, cv::Scalar(0))); }, "channels");
  SiftOptions s;
  s.max_features = -1;
  expect_error([&] { s.validate(); }, "max_features");
  DenseSiftOptions d;
  d.step = 0;
  expect_error([&] { dense_sift(cv::Mat(40, 40, CV_8U, cv::Scalar(0)), d); }, "step");
  d = {};
  d.size = 0;
  expect_error([&] { d.validate(); }, "size");
  // A flat image has no interest points: an empty result, not an error.
  const auto flat = detect_sift(cv::Mat(64, 64, CV_8U, cv::Scalar(128)));
  EXPECT_TRUE(flat.empty());
  EXPECT_EQ(flat.descriptors.cols, 128);
}

TEST(FeaturesFile, ReadsAndWritesTheBytesOfVersion1) {
  // Files as the first version of the writer saved them (docs/formats/vocabulary.md): no
  // features, and one keypoint with descriptor 0, 1, ..., 127. The second is pinned by its
  // header (magic, version, CRC-32 of the rest, size) and its payload laid out by hand.
  const auto path = test::temp_path("v1.features");
  const std::string empty = proprio::test::bytes_from_hex(
      "5052464541545331010000005d10ba310c000000000000000000000000000000"
      "80000000");
  test::spill(path, empty);
  EXPECT_TRUE(read_features(path).empty());
  write_features(path, Features{});
  EXPECT_EQ(test::slurp(path), empty);

  std::string one =
      proprio::test::bytes_from_hex("5052464541545331010000007402a4ff2802000000000000");
  auto append = [&one](const auto v) { one.append(reinterpret_cast<const char*>(&v), sizeof v); };
  append(std::uint64_t{1});
  append(std::uint32_t{128});
  for (const float v : {1.5f, 2.25f, 3.0f, 90.0f, 0.5f}) append(v);
  append(std::int32_t{2});
  append(std::int32_t{-1});
  for (int i = 0; i < 128; ++i) append(static_cast<float>(i));
  test::spill(path, one);
  const Features f = read_features(path);
  ASSERT_EQ(f.size(), 1);
  const auto& k = f.keypoints[0];
  EXPECT_EQ(k.pt, cv::Point2f(1.5f, 2.25f));
  EXPECT_EQ(k.size, 3.0f);
  EXPECT_EQ(k.angle, 90.0f);
  EXPECT_EQ(k.response, 0.5f);
  EXPECT_EQ(k.octave, 2);
  EXPECT_EQ(k.class_id, -1);
  EXPECT_EQ(f.descriptors.at<float>(0, 127), 127.0f);
  write_features(path, f);
  EXPECT_EQ(test::slurp(path), one);
}

TEST(FeaturesFile, RoundTripAndCorruption) {
  const cv::Mat img = cv::imread(kSamples + "/box.png", cv::IMREAD_GRAYSCALE);
  const auto f = detect_sift(img);
  ASSERT_GT(f.size(), 10);
  const auto path = test::temp_path("box.features");
  write_features(path, f);
  const auto g = read_features(path);
  ASSERT_EQ(g.size(), f.size());
  EXPECT_EQ(cv::norm(f.descriptors, g.descriptors, cv::NORM_INF), 0);
  for (int i = 0; i < f.size(); ++i) {
    const auto& a = f.keypoints[static_cast<std::size_t>(i)];
    const auto& b = g.keypoints[static_cast<std::size_t>(i)];
    EXPECT_EQ(a.pt, b.pt);
    EXPECT_EQ(a.size, b.size);
    EXPECT_EQ(a.angle, b.angle);
    EXPECT_EQ(a.octave, b.octave);
  }
  // Empty features round-trip too.
  write_features(path, Features{});
  EXPECT_TRUE(read_features(path).empty());

  write_features(path, f);
  const std::string bytes = test::slurp(path);
  test::spill(path, bytes.substr(0, bytes.size() / 2));
  expect_error([&] { read_features(path); }, "truncated");
  std::string flipped = bytes;
  flipped[bytes.size() - 5] ^= 0x40;
  test::spill(path, flipped);
  expect_error([&] { read_features(path); }, "checksum");
  test::spill(path, "hello");
  expect_error([&] { read_features(path); }, "not a features file");
  expect_error([&] { read_features(test::temp_path("missing.features")); }, "missing.features");
  // NaN descriptors are refused on writing.
  Features bad = f;
  bad.descriptors.at<float>(3, 7) = std::numeric_limits<float>::quiet_NaN();
  expect_error([&] { write_features(path, bad); }, "non-finite");
}

}  // namespace
}  // namespace proprio::features
