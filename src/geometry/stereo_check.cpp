#include "proprio/geometry/stereo_check.hpp"

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <regex>

#include "proprio/core/error.hpp"
#include "proprio/geometry/image_file.hpp"
#include "proprio/geometry/triangulation.hpp"

namespace proprio::geometry {
namespace fs = std::filesystem;
namespace {

struct Detection {
  bool found = false;
  std::vector<cv::Point2f> corners;
};

Detection detect(const fs::path& path, cv::Size board, cv::Size& image_size) {
  const cv::Mat gray = read_image(path, cv::IMREAD_GRAYSCALE);
  if (image_size.area() == 0) {
    image_size = gray.size();
  } else if (gray.size() != image_size) {
    throw Error::in_file(path, "image is " + std::to_string(gray.cols) + "x" +
                                   std::to_string(gray.rows) + ", the first one was " +
                                   std::to_string(image_size.width) + "x" +
                                   std::to_string(image_size.height));
  }
  Detection d;
  d.found = cv::findChessboardCorners(gray, board, d.corners,
                                      cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE);
  if (d.found) {
    cv::cornerSubPix(gray, d.corners, {11, 11}, {-1, -1},
                     cv::TermCriteria(cv::TermCriteria::EPS | cv::TermCriteria::COUNT, 30, 0.01));
  }
  return d;
}

Camera to_camera(const cv::Mat& K, const cv::Mat& dist, cv::Size size) {
  Camera c;
  cv::cv2eigen(K, c.K);
  c.dist.assign(dist.begin<double>(), dist.end<double>());
  c.width = size.width;
  c.height = size.height;
  return c;
}

std::vector<Eigen::Vector2d> to_eigen(const std::vector<cv::Point2f>& pts) {
  std::vector<Eigen::Vector2d> out(pts.size());
  for (size_t i = 0; i < pts.size(); ++i) out[i] = {pts[i].x, pts[i].y};
  return out;
}

// RMS distance of the points to their least-squares plane.
double plane_fit_rms(const std::vector<Eigen::Vector3d>& pts) {
  Eigen::MatrixXd A(static_cast<Eigen::Index>(pts.size()), 3);
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& p : pts) mean += p;
  mean /= static_cast<double>(pts.size());
  for (size_t i = 0; i < pts.size(); ++i) A.row(static_cast<Eigen::Index>(i)) = pts[i] - mean;
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(A);
  return svd.singularValues()(2) / std::sqrt(static_cast<double>(pts.size()));
}

}  // namespace

std::filesystem::path default_stereo_images_dir() { return PROPRIO_OPENCV_SAMPLES_DIR; }

void StereoCheckOptions::validate() const {
  require(board.width >= 2 && board.height >= 2 && board.width <= 100 && board.height <= 100,
          "stereo check: the board needs 2 to 100 inner corners per side");
  require(std::isfinite(square_size) && square_size > 0.0,
          "stereo check: the square size must be positive");
  require(min_pairs >= 1, "stereo check: min_pairs must be at least 1");
}

std::string StereoCheckSummary::brief() const {
  char buf[1024];
  std::snprintf(
      buf, sizeof buf,
      "pairs: %d found, %d used (board in both images), %d corners, images %dx%d\n"
      "calibration RMS: left %.4f px, right %.4f px, stereo %.4f px; baseline %.4g\n"
      "triangulation: reprojection RMS %.4f px; vs cv::triangulatePoints max %.3g, mean %.3g\n"
      "board planarity: RMS %.4f squares (worst board %.4f)\n"
      "neighbouring corners: mean distance %.5f squares (error %.3f%%)",
      pairs_found, pairs_used, corners, image_size.width, image_size.height, rms_left_px,
      rms_right_px, stereo_rms_px, baseline, triangulation_rms_px, max_diff_opencv,
      mean_diff_opencv, planarity_rms, planarity_worst, neighbour_mean, 100.0 * neighbour_error);
  return buf;
}

StereoCheckResult run_stereo_check(const StereoCheckOptions& options) {
  options.validate();
  const fs::path& dir = options.images_dir;
  if (!fs::is_directory(dir)) throw Error::in_file(dir, "no such directory");

  // Pair leftNN.* with rightNN.*, in numeric order.
  const std::regex pattern(R"((left|right)(\d+)\.(jpg|jpeg|png))", std::regex::icase);
  std::map<int, std::pair<std::string, std::pair<fs::path, fs::path>>> by_number;
  for (const auto& entry : fs::directory_iterator(dir)) {
    std::smatch m;
    const std::string name = entry.path().filename().string();
    if (!entry.is_regular_file() || !std::regex_match(name, m, pattern)) continue;
    auto& slot = by_number[std::stoi(m[2].str())];
    slot.first = m[2].str();
    const bool left = (m[1].str()[0] == 'l' || m[1].str()[0] == 'L');
    (left ? slot.second.first : slot.second.second) = entry.path();
  }
  StereoCheckResult result;
  auto& s = result.summary;
  std::vector<std::vector<cv::Point2f>> image_left;
  std::vector<std::vector<cv::Point2f>> image_right;
  std::vector<int> used_numbers;
  std::vector<size_t> used_reports;
  for (const auto& [number, slot] : by_number) {
    const auto& [left, right] = slot.second;
    if (left.empty() || right.empty()) continue;
    StereoPairReport report;
    report.id = slot.first;
    report.left = left;
    report.right = right;
    const Detection dl = detect(left, options.board, s.image_size);
    const Detection dr = detect(right, options.board, s.image_size);
    report.found_left = dl.found;
    report.found_right = dr.found;
    if (dl.found && dr.found) {
      image_left.push_back(dl.corners);
      image_right.push_back(dr.corners);
      used_numbers.push_back(number);
      used_reports.push_back(result.pairs.size());
    }
    result.pairs.push_back(report);
  }
  s.pairs_found = static_cast<int>(result.pairs.size());
  s.pairs_used = static_cast<int>(image_left.size());
  if (s.pairs_found == 0) throw Error::in_file(dir, "no leftNN/rightNN image pairs");
  if (s.pairs_used < options.min_pairs) {
    throw Error::in_file(dir, "the " + std::to_string(options.board.width) + "x" +
                                  std::to_string(options.board.height) +
                                  " board was found in both images of " +
                                  std::to_string(s.pairs_used) + " pairs, need at least " +
                                  std::to_string(options.min_pairs));
  }

  // The board in its own frame: corner (row i, column j) at (j, i, 0) squares.
  std::vector<cv::Point3f> board_points;
  for (int i = 0; i < options.board.height; ++i) {
    for (int j = 0; j < options.board.width; ++j) {
      board_points.emplace_back(static_cast<float>(j * options.square_size),
                                static_cast<float>(i * options.square_size), 0.0f);
    }
  }
  const std::vector<std::vector<cv::Point3f>> object(image_left.size(), board_points);
  cv::Mat K1, D1, K2, D2, R, T, E, F;
  std::vector<cv::Mat> rvecs, tvecs;
  s.rms_left_px = cv::calibrateCamera(object, image_left, s.image_size, K1, D1, rvecs, tvecs);
  s.rms_right_px = cv::calibrateCamera(object, image_right, s.image_size, K2, D2, rvecs, tvecs);
  s.stereo_rms_px = cv::stereoCalibrate(
      object, image_left, image_right, K1, D1, K2, D2, s.image_size, R, T, E, F,
      options.fix_intrinsics ? cv::CALIB_FIX_INTRINSIC : cv::CALIB_USE_INTRINSIC_GUESS,
      cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 100, 1e-10));
  result.left = to_camera(K1, D1, s.image_size);
  result.right = to_camera(K2, D2, s.image_size);
  cv::cv2eigen(R, result.right.R);
  cv::cv2eigen(T, result.right.t);
  s.baseline = result.right.t.norm();
  const Matrix34d P1 = result.left.P();
  const Matrix34d P2 = result.right.P();
  cv::Mat P1cv, P2cv;
  cv::eigen2cv(P1, P1cv);
  cv::eigen2cv(P2, P2cv);

  TriangulationOptions topt;
  topt.refine = options.refine_triangulation;
  double sq_reprojection = 0.0;
  double sum_diff = 0.0;
  double sq_planarity = 0.0;
  double sum_neighbour = 0.0;
  long neighbours = 0;
  const int cols = options.board.width;
  for (size_t k = 0; k < image_left.size(); ++k) {
    const auto x1 = undistort_pixels(result.left, to_eigen(image_left[k]));
    const auto x2 = undistort_pixels(result.right, to_eigen(image_right[k]));
    const BatchTriangulation tri = triangulate(P1, P2, x1, x2, topt);

    // The same points by OpenCV.
    cv::Mat a(2, static_cast<int>(x1.size()), CV_64F), b(2, static_cast<int>(x2.size()), CV_64F);
    for (size_t i = 0; i < x1.size(); ++i) {
      a.at<double>(0, static_cast<int>(i)) = x1[i].x();
      a.at<double>(1, static_cast<int>(i)) = x1[i].y();
      b.at<double>(0, static_cast<int>(i)) = x2[i].x();
      b.at<double>(1, static_cast<int>(i)) = x2[i].y();
    }
    cv::Mat X4;
    cv::triangulatePoints(P1cv, P2cv, a, b, X4);
    X4.convertTo(X4, CV_64F);

    StereoPairReport& report = result.pairs[used_reports[k]];
    report.corners = static_cast<int>(x1.size());
    for (size_t i = 0; i < x1.size(); ++i) {
      const int c = static_cast<int>(i);
      const Eigen::Vector3d Xcv(X4.at<double>(0, c) / X4.at<double>(3, c),
                                X4.at<double>(1, c) / X4.at<double>(3, c),
                                X4.at<double>(2, c) / X4.at<double>(3, c));
      const double diff = (Xcv - tri.points[i]).norm();
      s.max_diff_opencv = std::max(s.max_diff_opencv, diff);
      sum_diff += diff;
      sq_reprojection += tri.rms_px[i] * tri.rms_px[i];
      result.corners.push_back({used_numbers[k], c, x1[i], x2[i], tri.points[i]});
    }
    const double planarity = plane_fit_rms(tri.points) / options.square_size;
    report.planarity_rms = planarity;
    s.planarity_worst = std::max(s.planarity_worst, planarity);
    sq_planarity += planarity * planarity * static_cast<double>(x1.size());

    double board_sum = 0.0;
    int board_count = 0;
    // Corner (row r, column c) of the board, in the row-major order of tri.points.
    const auto corner = [&](int r, int c) -> const Eigen::Vector3d& {
      const size_t at = static_cast<size_t>(r) * static_cast<size_t>(cols) + static_cast<size_t>(c);
      return tri.points[at];
    };
    for (int i = 0; i < options.board.height; ++i) {
      for (int j = 0; j < cols; ++j) {
        const Eigen::Vector3d& p = corner(i, j);
        if (j + 1 < cols) {
          board_sum += (corner(i, j + 1) - p).norm();
          ++board_count;
        }
        if (i + 1 < options.board.height) {
          board_sum += (corner(i + 1, j) - p).norm();
          ++board_count;
        }
      }
    }
    report.neighbour_mean = board_sum / board_count / options.square_size;
    sum_neighbour += board_sum;
    neighbours += board_count;
  }
  s.corners = static_cast<int>(result.corners.size());
  s.triangulation_rms_px = std::sqrt(sq_reprojection / s.corners);
  s.mean_diff_opencv = sum_diff / s.corners;
  s.planarity_rms = std::sqrt(sq_planarity / s.corners);
  s.neighbour_mean = sum_neighbour / static_cast<double>(neighbours) / options.square_size;
  s.neighbour_error = std::abs(s.neighbour_mean - 1.0);
  result.summary.message = core::first_line(result.summary.brief());
  return result;
}

}  // namespace proprio::geometry
