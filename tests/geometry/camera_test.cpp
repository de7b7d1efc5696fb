#include "proprio/geometry/camera.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

#include "proprio/core/error.hpp"
#include "proprio/core/files.hpp"
#include "proprio/geometry/point_files.hpp"

namespace proprio::geometry {
namespace {
namespace fs = std::filesystem;

Camera example_camera() {
  Camera c;
  c.K << 520.0, 0.5, 321.0, 0.0, 515.0, 239.0, 0.0, 0.0, 1.0;
  c.R = (Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized())).toRotationMatrix();
  c.t = Eigen::Vector3d(0.1, -0.2, 1.5);
  c.width = 640;
  c.height = 480;
  return c;
}

TEST(Camera, ProjectionAgreesWithCameraFrame) {
  const Camera c = example_camera();
  const Eigen::Vector3d X(0.05, 0.02, 0.1);
  const Eigen::Vector3d Xc = c.R * X + c.t;
  const Eigen::Vector2d expect(
      c.K(0, 0) * Xc.x() / Xc.z() + c.K(0, 1) * Xc.y() / Xc.z() + c.K(0, 2),
      c.K(1, 1) * Xc.y() / Xc.z() + c.K(1, 2));
  EXPECT_LT((c.project(X) - expect).norm(), 1e-9);
  EXPECT_NEAR(c.depth(c.center()), 0.0, 1e-12);
}

TEST(Camera, DecomposeRecoversKRtFromAnyScaleAndSign) {
  const Camera c = example_camera();
  for (double s : {1.0, 3.7, -0.02}) {
    const Camera d = decompose_projection(s * c.P());
    EXPECT_LT((d.K - c.K).norm(), 1e-8) << "scale " << s;
    EXPECT_LT((d.R - c.R).norm(), 1e-10);
    EXPECT_LT((d.t - c.t).norm(), 1e-10);
    EXPECT_NEAR(d.R.determinant(), 1.0, 1e-12);
  }
}

TEST(Camera, UndistortInvertsOpenCVsDistortion) {
  Camera c = example_camera();
  c.K(0, 1) = 0.0;                                  // OpenCV's distortion model has no skew
  c.dist = {-0.28, 0.10, -0.0006, 0.0013, -0.024};  // a wide lens (opencv-doc's left camera)
  std::vector<cv::Point3d> world;
  world.reserve(40);
  for (int i = 0; i < 40; ++i) world.emplace_back(-0.25 + 0.0125 * i, 0.15 * std::sin(i), 0.05);
  cv::Mat K, R, rvec, tvec;
  cv::eigen2cv(c.K, K);
  cv::eigen2cv(c.R, R);
  cv::Rodrigues(R, rvec);
  cv::eigen2cv(c.t, tvec);
  std::vector<cv::Point2d> distorted;
  cv::projectPoints(world, rvec, tvec, K, c.dist, distorted);
  std::vector<Eigen::Vector2d> measured;
  measured.reserve(distorted.size());
  for (const auto& p : distorted) measured.emplace_back(p.x, p.y);
  const auto ideal = undistort_pixels(c, measured);
  ASSERT_EQ(ideal.size(), world.size());
  double max_shift = 0.0;
  for (size_t i = 0; i < world.size(); ++i) {
    const Eigen::Vector2d expect = c.project({world[i].x, world[i].y, world[i].z});
    EXPECT_LT((ideal[i] - expect).norm(), 1e-6) << i;
    max_shift = std::max(max_shift, (measured[i] - expect).norm());
  }
  EXPECT_GT(max_shift, 0.5);  // the distortion was not negligible
  c.dist.clear();
  EXPECT_EQ(undistort_pixels(c, measured), measured);
}

TEST(Camera, DecomposeRejectsSingular) {
  Matrix34d P = Matrix34d::Zero();
  P(0, 0) = 1;
  EXPECT_THROW(decompose_projection(P), Error);
}

class CalibFileTest : public ::testing::Test {
 protected:
  fs::path path_ =
      fs::temp_directory_path() /
      ("proprio_calib_test_" +
       std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + ".yml");
  void TearDown() override { fs::remove(path_); }
  std::string error_reading(const std::string& text) {
    core::write_file_atomic(path_, text);
    try {
      read_calib(path_);
    } catch (const Error& e) {
      return e.what();
    }
    return "no error";
  }
};

TEST_F(CalibFileTest, RoundTrip) {
  Camera c = example_camera();
  c.dist = {0.1, -0.05, 0.001, 0.002, 0.01};
  write_calib(path_, c);
  const Camera d = read_calib(path_);
  EXPECT_LT((d.K - c.K).norm(), 1e-12);
  EXPECT_LT((d.R - c.R).norm(), 1e-12);
  EXPECT_LT((d.t - c.t).norm(), 1e-12);
  EXPECT_EQ(d.dist, c.dist);
  EXPECT_EQ(d.width, 640);
  EXPECT_EQ(d.height, 480);
}

TEST_F(CalibFileTest, OnlyPIsDecomposed) {
  const Camera c = example_camera();
  const Matrix34d P = 2.0 * c.P();
  std::string text =
      "%YAML:1.0\n---\nP: !!opencv-matrix\n   rows: 3\n   cols: 4\n   dt: d\n   data: [";
  for (int r = 0; r < 3; ++r) {
    for (int k = 0; k < 4; ++k) text += (r + k > 0 ? ", " : "") + std::to_string(P(r, k));
  }
  text += "]\n";
  const Camera d = read_calib((core::write_file_atomic(path_, text), path_));
  EXPECT_LT((d.R - c.R).norm(), 1e-4);
}

TEST_F(CalibFileTest, BadFilesNameTheProblem) {
  const std::string p = path_.string();
  EXPECT_EQ(error_reading("%YAML:1.0\n---\nfoo: 1\n"), p + ": missing 'P'");
  EXPECT_EQ(error_reading("%YAML:1.0\n---\ncamera_matrix: !!opencv-matrix\n   rows: 2\n   cols: 2\n"
                          "   dt: d\n   data: [1, 0, 0, 1]\n"),
            p + ": 'camera_matrix' is 2x2, expected 3x3");
  EXPECT_EQ(error_reading("%YAML:1.0\n---\nP: !!opencv-matrix\n   rows: 3\n   cols: 4\n   dt: d\n"
                          "   data: [.NaN, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0]\n"),
            p + ": 'P' holds NaN or inf");
  EXPECT_NE(error_reading("this is: [not yaml").find(p + ": "), std::string::npos);
  Camera c = example_camera();
  c.R(0, 0) += 0.1;
  write_calib(path_, c);
  EXPECT_THROW(read_calib(path_), Error);
  EXPECT_THROW(read_calib(path_.string() + ".missing"), Error);
}

// Found by fuzz_triangulate: OpenCV 4.6's YAML parser loops for ever when text follows the
// top-level collection and starts with a '-' that is not "---". Such layouts are refused before it
// parses.
TEST_F(CalibFileTest, LayoutsThatHangOpenCvAreRefused) {
  const std::string p = path_.string();
  EXPECT_EQ(error_reading("%YAML:1.\n---L:1\n--\n-"),
            p + ":2: not a calibration (its map must begin on the line after '---')");
  EXPECT_EQ(error_reading("%YAML:1.0\n---\na: 1\n...\n-"),
            p + ":5: text after the end of the document ('...')");
  EXPECT_EQ(error_reading("%YAML:1.0\n---\n[1]\n-\n-"),
            p + ": not a calibration (the top level is not a map)");
  EXPECT_EQ(error_reading("%YAML:1.0\n---\n- 1\n...\n-"),
            p + ": not a calibration (the top level is not a map)");
  EXPECT_EQ(error_reading("%YAML:1.0\n  a: 1\n-\n-"),
            p + ":2: not a calibration (its keys must start at column 0)");
  EXPECT_EQ(error_reading("%YAML:1.0\n---\na: 1\n---\nb: 2\n"),
            p + ":4: more than one YAML document (a calibration is one map)");
  // What OpenCV writes, with comments, CRLF line ends and a closing "..." still reads.
  const Camera c = example_camera();
  write_calib(path_, c);
  std::string text = core::read_file(path_);
  text += "# a comment\n...\n# after the end\n";
  std::string crlf;
  for (const char ch : text) {
    if (ch == '\n') crlf += '\r';
    crlf += ch;
  }
  for (const std::string& t : {text, crlf}) {
    core::write_file_atomic(path_, t);
    EXPECT_TRUE(read_calib(path_).P().isApprox(c.P(), 1e-9));
  }
}

// Issue 16: a point CSV cut in the middle of a number ("12.5" becomes "12") was accepted.
TEST_F(CalibFileTest, APointFileCutShortIsRefused) {
  core::write_file_atomic(path_, "u1,v1,u2,v2\n1,2,3,4\n5,6,7,8.2\n");
  EXPECT_EQ(read_pixel_pairs_csv(path_).x2.back().y(), 8.2);
  core::write_file_atomic(path_, "u1,v1,u2,v2\n1,2,3,4\n5,6,7,8");
  try {
    (void)read_pixel_pairs_csv(path_);
    FAIL() << "accepted a file cut short";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()).rfind(path_.string() + ":3: the last line does not end", 0), 0U)
        << e.what();
  }
}

// Issue 16: a deeply nested value in an otherwise valid calib.yml crashed OpenCV's parser (its
// recursion overflowed the stack); 1e200 as a translation and image_width "abc" were accepted.
TEST_F(CalibFileTest, HostileValuesAreRefused) {
  const std::string p = path_.string();
  Camera c = example_camera();
  write_calib(path_, c);
  const std::string valid = core::read_file(path_);
  EXPECT_EQ(error_reading(valid + "deep: " + std::string(100000, '[') + "\n"),
            p + ":" + std::to_string(1 + std::count(valid.begin(), valid.end(), '\n')) +
                ": nested deeper than 64 levels");
  std::string block = valid + "deep:\n";
  for (int i = 1; i < 200; ++i) block += std::string(static_cast<std::size_t>(i), ' ') + "a:\n";
  EXPECT_NE(error_reading(block).find("nested deeper than"), std::string::npos);
  // Found by fuzz_calib: OpenCV's parser threw std::length_error (exit 1) on this key.
  EXPECT_EQ(error_reading("%YAML:1.0\n---\nP: !!opencv-matrix\n   rows: 3\n   :lcso 4\n"
                          "   dt: d\n   data: [520, 0, 321, 52, 0, 515, 239, -103, 0, 0, 1, 1.5]\n")
                .rfind(p + ": not an OpenCV YAML file", 0),
            0U);
  // Found by fuzz_calib: a top level that is a list made OpenCV assert (cv::Exception, exit 1).
  EXPECT_EQ(error_reading("%YAML:1.0\n-at_versio [ 52.0$ 0., 321.,ata0\n"),
            p + ": not a calibration (the top level is not a map)");
  // Found by fuzz_calib: "rows: Y3" made OpenCV allocate 64 GB before reading the data.
  EXPECT_EQ(
      error_reading("%YAML:1.0\n---\nP: !!opencv-matrix\n   rows: Y3\n   cols: 4\n"
                    "   dt: d\n   data: [519, 0, 321, 52, 0, 515, 239, -103, 0, 0, 11, .5]\n"),
      p + ": 'P' is not a matrix (rows, cols and data disagree)");
  // Issue 16: OpenCV's parse errors came out as its function's name ("parseValue"), no line.
  EXPECT_EQ(error_reading("%YAML:1.0\n---\na: {b: [1, 2,\n"),
            p + ":3: not an OpenCV YAML file: Missing , between the elements");
  c.t = Eigen::Vector3d(1e200, 0, 0);
  write_calib(path_, c);
  const std::string far = core::read_file(path_);
  EXPECT_NE(error_reading(far).find("absurd calibration: |t| = 1e+200"), std::string::npos)
      << error_reading(far);
  std::string text = valid;
  text.replace(text.find("image_width: 640"), 16, "image_width: \"abc\"");
  EXPECT_EQ(error_reading(text), p + ": 'image_width' is not an integer");
  text = valid;
  text.replace(text.find("image_height: 480"), 17, "image_height: 2000000");
  EXPECT_EQ(error_reading(text), p + ": 'image_height' = 2000000 is outside [0, 1000000]");
}

}  // namespace
}  // namespace proprio::geometry

namespace proprio::geometry {
namespace {

TEST_F(CalibFileTest, CarriesFormatVersionAndProvenance) {
  const auto prov = core::Provenance::current(std::vector<std::string>{"proprio", "calib"}, 3);
  write_calib(path_, example_camera(), prov);
  const std::string text = core::read_file(path_);
  EXPECT_NE(text.find("format_version: 1"), std::string::npos) << text;
  EXPECT_NE(text.find("command_line: proprio calib\n"), std::string::npos) << text;
  EXPECT_NE(text.find("seed: \"3\""), std::string::npos) << text;
  EXPECT_NE(text.find("opencv_version"), std::string::npos);
  EXPECT_LT((read_calib(path_).R - example_camera().R).norm(), 1e-12);
}

TEST_F(CalibFileTest, RefusesANewerFormatVersion) {
  write_calib(path_, example_camera());
  std::string text = core::read_file(path_);
  text.replace(text.find("format_version: 1"), 17, "format_version: 9");
  EXPECT_EQ(error_reading(text),
            path_.string() + ": format_version 9 is not supported (this build reads 1..1)");
}

}  // namespace
}  // namespace proprio::geometry
