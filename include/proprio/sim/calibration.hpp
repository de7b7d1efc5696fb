#pragma once
// The simulated robot-camera calibration (thesis 3.2.3): the arm carries the coloured marker on
// its end-effector through a 3D grid of its workspace, the marker is found in every rendered
// image by a colour threshold (the centre of the smallest circle around the largest blob, which
// a partly hidden sphere does not bias as its centroid would), and the DLT (eqs 3.10-3.11) fits the
// projection matrix P from the end-effector positions (robot frame, metres) to the marker pixels.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "proprio/geometry/dlt.hpp"
#include "proprio/sim/scene_description.hpp"

namespace proprio::sim {

struct SimCalibrationOptions {
  /// The grid: `grid` points per axis over the box [lo, hi] (robot frame, metres).
  int grid = 5;
  Eigen::Vector3d lo{0.14, -0.14, 0.04};
  Eigen::Vector3d hi{0.30, 0.14, 0.22};
  int width = 640;  ///< image size, pixels
  int height = 480;
  /// Fewest marker pixels for a detection (smaller blobs, e.g. a marker hidden behind the arm,
  /// are skipped).
  int min_marker_pixels = 12;
  /// Throws Error when an option is out of range.
  void validate() const;
};

struct SimCalibrationSummary {
  int grid_points = 0;   ///< points of the grid
  int unreachable = 0;   ///< skipped: no inverse kinematics solution
  int not_detected = 0;  ///< skipped: marker not seen (hidden or outside the image)
  int used = 0;          ///< pairs given to the DLT
  std::string message;
  /// What a person reads: the message.
  [[nodiscard]] std::string brief() const { return message; }
};

struct SimCalibrationResult {
  geometry::DltResult dlt;       ///< the fitted P (rms_px: reprojection RMS of the fit)
  geometry::Camera true_camera;  ///< the simulator's camera
  /// Mean image distance between the used workspace points projected with the fitted P and with
  /// the true camera, pixels.
  double true_error_px = 0.0;
  std::vector<Eigen::Vector3d> world;   ///< the used end-effector positions
  std::vector<Eigen::Vector2d> pixels;  ///< their marker centres
  SimCalibrationSummary summary;
};

/// Runs the calibration in `scene` (default_scene() when not given; it must contain the arm).
/// Throws Error when too few points are found for the DLT.
SimCalibrationResult calibrate_simulated(const SimCalibrationOptions& options,
                                         SceneDescription scene = default_scene());

}  // namespace proprio::sim
