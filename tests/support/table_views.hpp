#pragma once
// Synthetic views of the table for the push planner's tests and benchmarks (bench/ includes this
// header too, so that it needs neither GoogleTest nor the tests' paths): a camera looking straight
// down, objects as squares of grid features, and objects drawn as checkered squares.

#include <Eigen/Core>
#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

#include "proprio/geometry/camera.hpp"

namespace proprio::test {

/// 640 x 480, 1 m above (0.25, 0), looking down; image x = world x, image y = -world y.
inline geometry::Camera down_camera() {
  geometry::Camera c;
  c.K << 600, 0, 320, 0, 600, 240, 0, 0, 1;
  c.R = Eigen::Vector3d(1, -1, -1).asDiagonal();
  c.t = -c.R * Eigen::Vector3d(0.25, 0.0, 1.0);
  c.width = 640;
  c.height = 480;
  return c;
}

/// Grid features (6 px apart, size 12) covering a square of half side `h` (m) centred at table
/// point `c`, like the dense features of an object on the table.
inline void add_feature_square(std::vector<cv::KeyPoint>& f, const geometry::Camera& cam,
                               const Eigen::Vector2d& c, double h) {
  const Eigen::Vector2d a = cam.project(Eigen::Vector3d(c.x() - h, c.y() + h, 0));
  const Eigen::Vector2d b = cam.project(Eigen::Vector3d(c.x() + h, c.y() - h, 0));
  for (double v = a.y(); v <= b.y(); v += 6) {
    for (double u = a.x(); u <= b.x(); u += 6) {
      f.emplace_back(static_cast<float>(u), static_cast<float>(v), 12.0F);
    }
  }
}

/// A checkered square (4 px cells of 40 and 220) of half side `h` (m) centred at table point `c`,
/// drawn into `img` (8-bit, grey or BGR).
inline void draw_checkered_square(cv::Mat& img, const geometry::Camera& cam,
                                  const Eigen::Vector2d& c, double h) {
  const Eigen::Vector2d a = cam.project(Eigen::Vector3d(c.x() - h, c.y() + h, 0));
  const Eigen::Vector2d b = cam.project(Eigen::Vector3d(c.x() + h, c.y() - h, 0));
  for (int v = static_cast<int>(a.y()); v <= static_cast<int>(b.y()); ++v) {
    for (int u = static_cast<int>(a.x()); u <= static_cast<int>(b.x()); ++u) {
      const std::uint8_t g = ((u / 4 + v / 4) % 2) != 0 ? 40 : 220;
      if (img.channels() == 3) {
        img.at<cv::Vec3b>(v, u) = cv::Vec3b(g, g, g);
      } else {
        img.at<std::uint8_t>(v, u) = g;
      }
    }
  }
}

}  // namespace proprio::test
