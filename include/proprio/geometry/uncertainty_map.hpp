#pragma once
// A map of a stereo pair's visual uncertainty over a planar slice of the workspace (thesis 3.4.2,
// Figure 3-5): at each cell the linearised covariance of the triangulated point
// (triangulation_covariance) summarised by the standard deviation along its worst direction.

#include <Eigen/Core>
#include <array>
#include <opencv2/core.hpp>
#include <string>

#include "proprio/geometry/camera.hpp"

namespace proprio::geometry {

struct UncertaintyMapOptions {
  /// World axis normal to the slice (0 = x, 1 = y, 2 = z) and its value there (world units). The
  /// default is the horizontal plane z = 0 of the robot frame; for a stereo rig in the left
  /// camera's frame (y down) the horizontal slice is axis 1.
  int slice_axis = 2;
  double slice_at = 0.0;
  /// Ranges of the two in-slice axes, in increasing axis order (x then y for a z slice, x then z
  /// for a y slice, y then z for an x slice), world units, min < max.
  Eigen::Vector2d range_a{-1.0, 1.0};
  Eigen::Vector2d range_b{-1.0, 1.0};
  int cells_a = 200;      ///< grid cells along the first in-slice axis
  int cells_b = 200;      ///< and along the second
  double sigma_px = 1.0;  ///< pixel noise standard deviation per axis, both cameras (Sigma = s^2 I)
  /// Leave out cells that project outside either image (needs the image size in both cameras).
  bool visible_only = true;

  /// Throws Error when an option is out of range.
  void validate() const;
};

struct UncertaintyMapSummary {
  int cells = 0;
  int valid_cells = 0;
  int behind_camera = 0;  ///< cells behind either camera
  int outside_image = 0;  ///< cells in front of both but outside an image (visible_only)
  int unobservable = 0;   ///< cells on the baseline
  /// Over valid cells, world units.
  double min_sigma = 0.0;
  double median_sigma = 0.0;
  double max_sigma = 0.0;
  Eigen::Vector3d best_point = Eigen::Vector3d::Zero();  ///< the cell centre with min_sigma
};

struct UncertaintyMap {
  UncertaintyMapOptions options;
  /// sqrt of the largest eigenvalue of Cov(X) per cell (world units); row r is the r-th value of
  /// the second axis from its minimum, column c the c-th of the first. 0 where !valid.
  Eigen::ArrayXXd sigma;
  Eigen::Array<bool, Eigen::Dynamic, Eigen::Dynamic> valid;
  std::array<Eigen::Vector3d, 2> camera_centres;
  UncertaintyMapSummary summary;

  /// World point at the centre of cell (row, col).
  [[nodiscard]] Eigen::Vector3d cell_centre(int row, int col) const;
};

/// Computes the map for two cameras (ideal projections P = K [R | t]; distortion plays no part).
/// Throws Error when no cell is valid.
UncertaintyMap compute_uncertainty_map(const Camera& camera1, const Camera& camera2,
                                       const UncertaintyMapOptions& options = {});

struct UncertaintyRenderOptions {
  double unit_scale = 1000.0;  ///< multiplies world units into the legend's unit (m -> mm)
  std::string unit = "mm";
  std::string world_unit = "m";  ///< the axes' unit
  int map_width_px = 480;        ///< the map area's width; its height follows the ranges' aspect
  /// The colour scale is logarithmic from the smallest value to this percentile (the baseline
  /// region's values explode and would wash out the rest); larger values get the top colour.
  double clip_percentile = 99.0;

  /// Throws Error when an option is out of range.
  void validate() const;
};

/// Renders the map as a BGR heat-map image (cv::COLORMAP_TURBO; invalid cells dark grey) with axes,
/// the camera centres when they fall inside the ranges, a title and a labelled colour bar.
cv::Mat render_uncertainty_map(const UncertaintyMap& map,
                               const UncertaintyRenderOptions& options = {});

}  // namespace proprio::geometry
