#pragma once
// Test helpers: temporary directories and small synthetic episodes written with EpisodeWriter.

#include <gtest/gtest.h>

#include <filesystem>
#include <opencv2/imgproc.hpp>
#include <string>

#include "../support/synthetic_episode.hpp"
#include "../support/temp_dir.hpp"
#include "proprio/core/files.hpp"
#include "proprio/episode/episode_writer.hpp"

namespace proprio::episode::testing {
namespace fs = std::filesystem;

/// A fresh empty directory named after the running test, removed by the destructor.
class TempDir : public proprio::test::TempDir {
 public:
  TempDir() : proprio::test::TempDir("proprio_episode_") {}
};

/// A camera 1 m above the table, looking straight down (world z up, camera z down).
inline geometry::Camera overhead_camera(int width, int height) {
  return test::overhead_camera(60.0, (width - 1) / 2.0, (height - 1) / 2.0);
}

struct SyntheticSpec {
  int frames = 5;
  int width = 64;
  int height = 48;
  int joints = 2;
  bool masks = true;
  bool depth = false;
  bool stereo = false;
  FrameStorage storage = FrameStorage::kPng;
  int first_touch = 3;          ///< frames from here on touch; -1: never
  bool store_ee_image = false;  ///< write ee_u, ee_v (else left empty)
};

/// Objects of the synthetic episodes: 1 the target (a "mug"), 2 the arm, 3 another object.
inline std::vector<ObjectInfo> synthetic_objects() {
  return {{1, "mug", ObjectRole::kTarget},
          {2, "katana", ObjectRole::kArm},
          {3, "book", ObjectRole::kObject}};
}

inline EpisodeInfo synthetic_info(const SyntheticSpec& spec) {
  EpisodeInfo info = test::synthetic_info(spec.width, spec.height, "episode_test", 42, 30.0);
  info.arm_name = "katana";
  info.joint_count = spec.joints;
  info.storage = spec.storage;
  info.has_masks = spec.masks;
  info.has_depth = spec.depth;
  info.stereo = spec.stereo;
  info.provenance.source = Source::kSimulated;
  info.provenance.scenario = "push";
  info.provenance.switches = {{"clutter", true}, {"objects", 3}};
  return info;
}

/// Frame i: a gradient with a bright square that moves one pixel per frame.
inline cv::Mat synthetic_frame(const SyntheticSpec& spec, int i, int shift = 0) {
  cv::Mat m(spec.height, spec.width, CV_8UC3);
  for (int r = 0; r < m.rows; ++r) {
    for (int c = 0; c < m.cols; ++c) {
      m.at<cv::Vec3b>(r, c) = cv::Vec3b(static_cast<uchar>(4 * c), static_cast<uchar>(5 * r),
                                        static_cast<uchar>(40 * i + shift));
    }
  }
  cv::rectangle(m, cv::Rect(10 + i, 10, 8, 8), cv::Scalar(255, 255, 255), cv::FILLED);
  return m;
}

inline cv::Mat synthetic_mask(const SyntheticSpec& spec, int i) {
  cv::Mat m(spec.height, spec.width, CV_16UC1, cv::Scalar(0));
  cv::rectangle(m, cv::Rect(10 + i, 10, 8, 8), cv::Scalar(1), cv::FILLED);
  cv::rectangle(m, cv::Rect(40, 30, 6, 6), cv::Scalar(3), cv::FILLED);
  cv::rectangle(m, cv::Rect(0, 0, 4 + i, 4), cv::Scalar(2), cv::FILLED);
  return m;
}

inline cv::Mat synthetic_depth(const SyntheticSpec& spec, int i) {
  cv::Mat m(spec.height, spec.width, CV_16UC1, cv::Scalar(1000));
  cv::rectangle(m, cv::Rect(10 + i, 10, 8, 8), cv::Scalar(900), cv::FILLED);
  return m;
}

inline ArmSample synthetic_sample(const SyntheticSpec& spec, int i) {
  ArmSample s;
  s.t = 0.1 + i / 30.0;
  s.q = Eigen::VectorXd::LinSpaced(spec.joints, 0.1 * i, 0.2 * i + 0.3);
  s.ee = Eigen::Vector3d(0.01 * i - 0.02, 0.05, 0.1);
  s.touching = spec.first_touch >= 0 && i >= spec.first_touch;
  if (spec.store_ee_image) s.ee_image = Eigen::Vector2d(10.5 + i, 20.25);
  return s;
}

/// Writes a synthetic episode to `dir` and returns it.
inline fs::path write_synthetic(const fs::path& dir, const SyntheticSpec& spec = {}) {
  const auto cam = overhead_camera(spec.width, spec.height);
  std::optional<geometry::Camera> right;
  if (spec.stereo) {
    right = cam;
    right->t.x() -= 0.1;
  }
  return test::write_synthetic_episode(
      dir, synthetic_info(spec), cam, synthetic_objects(), spec.frames,
      [&spec](int i) {
        test::SyntheticFrame f{synthetic_frame(spec, i), synthetic_sample(spec, i), {}};
        if (spec.masks) f.extras.mask = synthetic_mask(spec, i);
        if (spec.depth) f.extras.depth = synthetic_depth(spec, i);
        if (spec.stereo) f.extras.right_image = synthetic_frame(spec, i, 7);
        return f;
      },
      right);
}

/// Every message of a problem list joined by newlines (for failure output and searching).
template <typename Problems>
std::string joined(const Problems& problems) {
  std::string s;
  for (const auto& p : problems) {
    s += p.message;
    s += '\n';
  }
  return s;
}

}  // namespace proprio::episode::testing
