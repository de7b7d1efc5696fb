#include "proprio/geometry/image_file.hpp"

#include <gtest/gtest.h>

#include <filesystem>

#include "../support/temp_dir.hpp"
#include "proprio/core/error.hpp"
#include "proprio/core/files.hpp"
#include "proprio/core/image_header.hpp"

namespace proprio::geometry {
namespace {
namespace fs = std::filesystem;
const fs::path kSamples = PROPRIO_OPENCV_SAMPLES;

// Real data: every PNG, JPEG and BMP of opencv-doc's samples has the size its header says, and
// the header is read without decoding.
TEST(ImageFile, HeadersOfRealImagesMatchTheDecodedSize) {
  int checked = 0;
  for (const auto& e : fs::directory_iterator(kSamples)) {
    const auto ext = e.path().extension().string();
    if (ext != ".png" && ext != ".jpg" && ext != ".bmp") continue;
    const core::ImageHeader h = core::read_image_header(e.path());
    const cv::Mat m = read_image(e.path(), cv::IMREAD_UNCHANGED);
    EXPECT_EQ(h.width, m.cols) << e.path();
    EXPECT_EQ(h.height, m.rows) << e.path();
    ++checked;
  }
  EXPECT_GT(checked, 20);
}

TEST(ImageFile, WhatTheCodecCannotDecodeIsOneLineNamingTheFile) {
  test::TempDir dir("proprio_image_file_");
  cv::Mat image(30, 40, CV_8UC3, cv::Scalar(10, 20, 30));
  std::vector<uchar> bytes;
  ASSERT_TRUE(cv::imencode(".jpg", image, bytes));
  // The header is intact, the entropy-coded data is cut: the codec fails, not the header.
  const fs::path cut = dir.path() / "cut.jpg";
  core::write_file_atomic(cut, std::string(bytes.begin(), bytes.begin() + 200));
  ::testing::internal::CaptureStderr();
  try {
    (void)read_image(cut);
    FAIL() << "a JPEG cut short was decoded";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()),
              cut.string() + ": cannot decode the 8-bit colour JPEG (corrupt data)");
  }
  // libjpeg's own "Premature end of JPEG file" went to the debug log, not to stderr.
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
  const cv::Mat left = read_image(kSamples / "left01.jpg", cv::IMREAD_GRAYSCALE);
  EXPECT_EQ(left.type(), CV_8UC1);
  EXPECT_EQ(left.size(), cv::Size(640, 480));
  try {
    (void)read_image(dir.path() / "missing.png");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), (dir.path() / "missing.png").string() + ": no such file");
  }
  // A PNG whose IHDR promises 50,000 x 50,000 pixels: refused from its 60 bytes.
  ASSERT_TRUE(cv::imencode(".png", image, bytes));
  std::string big(bytes.begin(), bytes.end());
  big[16] = big[20] = 0;
  big[17] = big[21] = static_cast<char>(0x00);
  big[18] = big[22] = static_cast<char>(0xC3);
  big[19] = big[23] = static_cast<char>(0x50);
  const fs::path huge = dir.path() / "huge.png";
  core::write_file_atomic(huge, big);
  EXPECT_THROW((void)read_image(huge), Error);
}

}  // namespace
}  // namespace proprio::geometry
