#include "proprio/geometry/stereo_check.hpp"

#include <gtest/gtest.h>

#include <Eigen/LU>
#include <filesystem>

#include "proprio/core/error.hpp"
#include "proprio/core/files.hpp"

namespace proprio::geometry {
namespace {
namespace fs = std::filesystem;

const fs::path kSamples = PROPRIO_OPENCV_SAMPLES;

std::string error_of(const StereoCheckOptions& o) {
  try {
    run_stereo_check(o);
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

// A temporary folder removed at the end of the test.
struct TempDir {
  fs::path path = fs::temp_directory_path() /
                  ("proprio_stereo_" +
                   std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
  TempDir() {
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() { fs::remove_all(path); }
};

TEST(StereoCheck, OpenCVChessboards) {
  StereoCheckOptions o;
  o.images_dir = kSamples;
  const StereoCheckResult r = run_stereo_check(o);
  const auto& s = r.summary;
  // left01..14 / right01..14 without 10; the board is found in every image.
  EXPECT_EQ(s.pairs_found, 13);
  EXPECT_EQ(s.pairs_used, 13);
  EXPECT_EQ(s.corners, 13 * 54);
  ASSERT_EQ(r.pairs.size(), 13u);
  for (const auto& p : r.pairs) {
    EXPECT_TRUE(p.found_left && p.found_right) << p.id;
    EXPECT_EQ(p.corners, 54) << p.id;
    EXPECT_NEAR(p.neighbour_mean, 1.0, 0.02) << p.id;
  }
  EXPECT_EQ(r.pairs.front().id, "01");
  EXPECT_EQ(r.pairs.back().id, "14");
  EXPECT_EQ(s.image_size, cv::Size(640, 480));

  // OpenCV's calibration fits these images to about half a pixel.
  EXPECT_LT(s.rms_left_px, 0.6);
  EXPECT_LT(s.rms_right_px, 0.6);
  EXPECT_LT(s.stereo_rms_px, 0.6);
  // The left camera is the origin; the right one sits a few squares to its side.
  EXPECT_TRUE(r.left.R.isIdentity(0.0));
  EXPECT_TRUE(r.left.t.isZero(0.0));
  EXPECT_NEAR(r.right.R.determinant(), 1.0, 1e-9);
  EXPECT_GT(s.baseline, 2.0);
  EXPECT_LT(s.baseline, 5.0);
  EXPECT_LT(r.right.t.x(), 0.0);  // the right camera's centre is at +x in the left frame

  // Our linear triangulation is OpenCV's to rounding.
  EXPECT_LT(s.max_diff_opencv, 1e-9);
  EXPECT_LE(s.mean_diff_opencv, s.max_diff_opencv);
  EXPECT_LT(s.triangulation_rms_px, 0.3);
  // The metric reconstruction: flat boards with squares of the right size.
  EXPECT_LT(s.neighbour_error, 0.01);
  EXPECT_LT(s.planarity_rms, 0.05);
  EXPECT_LT(s.planarity_worst, 0.1);
  ASSERT_EQ(r.corners.size(), 702u);
  // Corners lie in front of both cameras and reproject onto their pixels.
  for (const auto& c : r.corners) {
    EXPECT_GT(r.left.depth(c.X), 0.0);
    EXPECT_GT(r.right.depth(c.X), 0.0);
    EXPECT_LT((r.left.project(c.X) - c.left_px).norm(), 2.0);
  }
}

TEST(StereoCheck, RefinementAndUnits) {
  StereoCheckOptions o;
  o.images_dir = kSamples;
  o.refine_triangulation = true;
  o.square_size = 0.025;  // any unit: the figures in squares stay the same
  const StereoCheckResult r = run_stereo_check(o);
  EXPECT_LT(r.summary.neighbour_error, 0.01);
  EXPECT_NEAR(r.summary.baseline / 0.025, 3.3, 0.5);
  StereoCheckOptions linear = o;
  linear.refine_triangulation = false;
  const StereoCheckResult l = run_stereo_check(linear);
  EXPECT_LE(r.summary.triangulation_rms_px, l.summary.triangulation_rms_px);
  EXPECT_GT(r.summary.max_diff_opencv, 0.0);  // refined points move off the linear ones
}

TEST(StereoCheck, BadFoldersAreErrors) {
  StereoCheckOptions o;
  o.images_dir = "/nonexistent/stereo";
  EXPECT_EQ(error_of(o), "/nonexistent/stereo: no such directory");

  TempDir tmp;
  o.images_dir = tmp.path;
  EXPECT_EQ(error_of(o), tmp.path.string() + ": no leftNN/rightNN image pairs");

  // One good pair is not enough for a calibration.
  fs::copy_file(kSamples / "left01.jpg", tmp.path / "left01.jpg");
  fs::copy_file(kSamples / "right01.jpg", tmp.path / "right01.jpg");
  fs::copy_file(kSamples / "left02.jpg", tmp.path / "left02.jpg");  // no right02: ignored
  EXPECT_EQ(
      error_of(o),
      tmp.path.string() + ": the 9x6 board was found in both images of 1 pairs, need at least 3");

  core::write_file_atomic(tmp.path / "right02.jpg", "not a JPEG");
  EXPECT_EQ(error_of(o), (tmp.path / "right02.jpg").string() + ": not an image proprio reads (PNG, JPEG, BMP or PNM)");

  o.square_size = -1.0;
  EXPECT_THROW(run_stereo_check(o), Error);
}

}  // namespace
}  // namespace proprio::geometry
