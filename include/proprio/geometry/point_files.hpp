#pragma once
// The point CSV files of the calib verbs (docs/formats/calib.md). Reading checks the header
// exactly and every value (core::read_csv); errors name the file and line.

#include <Eigen/Core>
#include <filesystem>
#include <vector>

#include "proprio/geometry/stereo_check.hpp"

namespace proprio::geometry {

/// 3D-2D pairs for DLT: header X,Y,Z,u,v (world units; pixels).
struct Correspondences {
  std::filesystem::path source;
  std::vector<Eigen::Vector3d> world;
  std::vector<Eigen::Vector2d> pixels;
  std::vector<long> lines;  ///< the source line of each pair
};
Correspondences read_correspondences_csv(const std::filesystem::path& path);

/// Pixel pairs for triangulation: header u1,v1,u2,v2 (pixels in camera 1 and camera 2).
struct PixelPairs {
  std::filesystem::path source;
  std::vector<Eigen::Vector2d> x1;
  std::vector<Eigen::Vector2d> x2;
  std::vector<long> lines;
};
PixelPairs read_pixel_pairs_csv(const std::filesystem::path& path);

/// Pixels of one camera: header u,v.
struct PixelList {
  std::filesystem::path source;
  std::vector<Eigen::Vector2d> pixels;
  std::vector<long> lines;
};
PixelList read_pixels_csv(const std::filesystem::path& path);

/// Writes world points atomically: header X,Y,Z.
void write_points_csv(const std::filesystem::path& path,
                      const std::vector<Eigen::Vector3d>& points);

/// Writes the stereo check's corners atomically: header pair,corner,u1,v1,u2,v2,X,Y,Z
/// (undistorted pixels; left camera frame).
void write_stereo_corners_csv(const std::filesystem::path& path,
                              const std::vector<StereoCorner>& corners);

}  // namespace proprio::geometry
