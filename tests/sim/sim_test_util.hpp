#pragma once
// Shared helpers for the sim tests: small scenes, temporary files, quadrant test images.

#include <filesystem>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <string>

#include "../support/temp_dir.hpp"
#include "proprio/sim/object_catalogue.hpp"
#include "proprio/sim/scene_description.hpp"

namespace proprio::sim::test {

namespace fs = std::filesystem;

/// A per-process temporary directory for test files, removed when the process exits.
inline fs::path temp_dir() {
  static const proprio::test::TempDir kDir("proprio_", "sim_test");
  return kDir.path();
}

/// An image in four coloured quadrants (BGR): top-left red, top-right green, bottom-left blue,
/// bottom-right yellow; tells orientation and mirroring apart.
inline cv::Mat quadrant_image(int width = 200, int height = 160) {
  cv::Mat img(height, width, CV_8UC3);
  img(cv::Rect(0, 0, width / 2, height / 2)).setTo(cv::Scalar(0, 0, 255));
  img(cv::Rect(width / 2, 0, width - width / 2, height / 2)).setTo(cv::Scalar(0, 255, 0));
  img(cv::Rect(0, height / 2, width / 2, height - height / 2)).setTo(cv::Scalar(255, 0, 0));
  img(cv::Rect(width / 2, height / 2, width - width / 2, height - height / 2))
      .setTo(cv::Scalar(0, 255, 255));
  return img;
}

/// Colour class of a BGR pixel: 'r', 'g', 'b', 'y' or '?' (by which channels dominate, so that
/// shading does not matter).
inline char colour_class(const cv::Vec3b& p) {
  const int b = p[0];
  const int g = p[1];
  const int r = p[2];
  if (r > 2 * g + 10 && r > 2 * b + 10) return 'r';
  if (g > 2 * r + 10 && g > 2 * b + 10) return 'g';
  if (b > 2 * r + 10 && b > 2 * g + 10) return 'b';
  if (r > 2 * b + 10 && g > 2 * b + 10) return 'y';
  return '?';
}

/// The default scene without the arm's dependence on the tree: arm included (data/models/arm.xml),
/// one small camera.
inline SceneDescription small_scene(int width = 320, int height = 240) {
  SceneDescription d = default_scene();
  d.cameras.at(0).width = width;
  d.cameras.at(0).height = height;
  return d;
}

/// The ten catalogue objects spread over the workspace, apart from each other and from the arm at
/// rest, none hiding another from the default camera.
inline void add_all_objects(SceneDescription& d) {
  struct Place {
    const char* type;
    double x, y, yaw;
  };
  const Place places[] = {{"book", 0.25, -0.25, 0.2},      {"mug", 0.50, -0.25, 1.0},
                          {"bottle", 0.70, -0.22, 0.0},    {"spirit-level", 0.45, -0.03, 0.1},
                          {"rabbit", 0.72, 0.0, -1.3},     {"cd", 0.18, 0.05, 0.5},
                          {"calculator", 0.72, 0.2, -0.3}, {"giraffe", 0.48, 0.18, -1.2},
                          {"bike", 0.25, 0.3, 0.3},        {"box", 0.70, 0.40, 0.6}};
  for (const Place& p : places) {
    PlacedObject o;
    o.type = p.type;
    o.position = {p.x, p.y};
    o.yaw = p.yaw;
    d.objects.push_back(o);
  }
}

}  // namespace proprio::sim::test
