#pragma once
// A real-data check of the geometry module on a chessboard stereo sequence (opencv-doc's
// left01..14 / right01..14, 9x6 inner corners): OpenCV calibrates the pair, our triangulation
// reconstructs the corners, and the reconstruction is scored against what a flat board of known
// square size must give. Shared by `proprio calib stereo`, scripts/demo and the tests.

#include <Eigen/Core>
#include <filesystem>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "proprio/geometry/camera.hpp"

namespace proprio::geometry {

struct StereoCheckOptions {
  /// Folder with image pairs leftNN.EXT / rightNN.EXT (EXT jpg, jpeg or png; NN any digits).
  std::filesystem::path images_dir;
  cv::Size board{9, 6};      ///< inner corners per row (width) and per column (height)
  double square_size = 1.0;  ///< side of a square, in the world unit of the results
  /// stereoCalibrate keeps the intrinsics that calibrateCamera found for each camera and fits only
  /// the relative pose; otherwise it refines them jointly.
  bool fix_intrinsics = true;
  bool refine_triangulation = false;  ///< Levenberg-Marquardt after the linear triangulation
  int min_pairs = 3;                  ///< fewest pairs with the board found in both images

  /// Throws Error when an option is out of range.
  void validate() const;
};

struct StereoPairReport {
  std::string id;  ///< the NN of the file names
  std::filesystem::path left;
  std::filesystem::path right;
  bool found_left = false;
  bool found_right = false;
  int corners = 0;  ///< corners triangulated (0 when the pair was not used)
  /// RMS distance of the board's triangulated corners to their best-fit plane, in squares.
  double planarity_rms = 0.0;
  /// Mean distance between neighbouring corners (rows and columns), in squares (ideal 1).
  double neighbour_mean = 0.0;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.id, {"id", "The NN of the file names"});
    v(self.left, {"left", "The left image"});
    v(self.right, {"right", "The right image"});
    v(self.found_left, {"found_left", "Board found in the left image"});
    v(self.found_right, {"found_right", "Board found in the right image"});
    v(self.corners, {"corners", "Corners triangulated"});
    v(self.planarity_rms, {"planarity_rms", "RMS distance to the board's plane, squares"});
    v(self.neighbour_mean, {"neighbour_mean", "Mean neighbouring-corner distance, squares"});
  }
};

/// One triangulated corner.
struct StereoCorner {
  int pair = 0;    ///< the pair's number (NN)
  int corner = 0;  ///< index in the board, row-major from findChessboardCorners' first corner
  Eigen::Vector2d left_px = Eigen::Vector2d::Zero();   ///< undistorted pixel, left camera
  Eigen::Vector2d right_px = Eigen::Vector2d::Zero();  ///< undistorted pixel, right camera
  Eigen::Vector3d X = Eigen::Vector3d::Zero();         ///< left camera frame, world units
};

struct StereoCheckSummary {
  int pairs_found = 0;  ///< image pairs in the folder
  int pairs_used = 0;   ///< pairs with the board found in both images
  int corners = 0;      ///< corners triangulated
  cv::Size image_size;
  double rms_left_px = 0.0;    ///< calibrateCamera's RMS, left camera
  double rms_right_px = 0.0;   ///< calibrateCamera's RMS, right camera
  double stereo_rms_px = 0.0;  ///< stereoCalibrate's RMS
  double baseline = 0.0;       ///< |t| of the right camera, world units
  /// Reprojection RMS of our triangulated corners over both views, pixels.
  double triangulation_rms_px = 0.0;
  /// Difference between our triangulation and cv::triangulatePoints, world units.
  double max_diff_opencv = 0.0;
  double mean_diff_opencv = 0.0;
  /// RMS over all boards of the distance to the board's plane, and the worst board's, in squares.
  double planarity_rms = 0.0;
  double planarity_worst = 0.0;
  /// Mean neighbouring-corner distance over all boards, in squares, and |that - 1|.
  double neighbour_mean = 0.0;
  double neighbour_error = 0.0;
  std::string message;                      ///< one line: what happened (brief()'s first line)
  [[nodiscard]] std::string brief() const;  ///< a few lines for the CLI

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.pairs_found, {"pairs_found", "Image pairs in the folder"});
    v(self.pairs_used, {"pairs_used", "Pairs with the board in both images"});
    v(self.corners, {"corners", "Corners triangulated"});
    v(std::vector<int>{self.image_size.width, self.image_size.height},
      {"image_size", "Width, height, px"});
    v(self.rms_left_px, {"rms_left_px", "calibrateCamera's RMS, left, px"});
    v(self.rms_right_px, {"rms_right_px", "calibrateCamera's RMS, right, px"});
    v(self.stereo_rms_px, {"stereo_rms_px", "stereoCalibrate's RMS, px"});
    v(self.baseline, {"baseline", "|t| of the right camera"});
    v(self.triangulation_rms_px, {"triangulation_rms_px", "Our corners' reprojection RMS, px"});
    v(self.max_diff_opencv, {"max_diff_opencv", "Largest difference from OpenCV's points"});
    v(self.mean_diff_opencv, {"mean_diff_opencv", "Mean difference from OpenCV's points"});
    v(self.planarity_rms, {"planarity_rms", "RMS distance to the boards' planes, squares"});
    v(self.planarity_worst, {"planarity_worst", "The worst board's, squares"});
    v(self.neighbour_mean, {"neighbour_mean", "Mean neighbouring-corner distance, squares"});
    v(self.neighbour_error, {"neighbour_error", "|neighbour_mean - 1|"});
  }
};

struct StereoCheckResult {
  Camera left;   ///< at the origin (R = I, t = 0)
  Camera right;  ///< pose relative to the left camera
  std::vector<StereoPairReport> pairs;
  std::vector<StereoCorner> corners;
  StereoCheckSummary summary;

  /// Output only: the summary's figures (flat), the cameras and the pairs (not the corners).
  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    StereoCheckSummary::describe(self.summary, v);
    v(self.left, {"left", "The left camera"});
    v(self.right, {"right", "The right camera, relative to the left"});
    v(self.pairs, {"per_pair", "Each pair"});
  }
};

/// Where opencv-doc's sample images are (PROPRIO_OPENCV_SAMPLES at build time), the default
/// images_dir of `proprio calib stereo`.
std::filesystem::path default_stereo_images_dir();

/// Detects the board (findChessboardCorners + cornerSubPix) in every pair, calibrates each camera
/// (calibrateCamera) and then the pair (stereoCalibrate), undistorts the corners
/// (undistort_pixels), triangulates them with triangulate() and scores the result. Throws Error
/// naming the folder or image when the folder has no pairs, an image is unreadable or of another
/// size, or fewer than min_pairs pairs show the board in both images.
StereoCheckResult run_stereo_check(const StereoCheckOptions& options);

}  // namespace proprio::geometry
