#pragma once
// A small synthetic push episode for the baseline, evaluation and CLI tests: a grey arm slides in
// from the left at a constant speed, touches a textured disc (the target) and pushes it along;
// with a moving background blocks ("people") jump about the upper third. Ground-truth masks, the
// end-effector's image position and the touching flag are exact.

#include <cmath>
#include <filesystem>
#include <opencv2/imgproc.hpp>
#include <random>
#include <string>

#include "../support/synthetic_episode.hpp"
#include "../support/temp_dir.hpp"
#include "proprio/episode/episode_writer.hpp"

namespace proprio::segmentation::testing {
namespace fs = std::filesystem;

/// A fresh empty directory named after the running test, removed by the destructor.
class ScratchDir : public proprio::test::TempDir {
 public:
  ScratchDir() : proprio::test::TempDir("proprio_baseline_") {}
};

struct PushSpec {
  int width = 160;
  int height = 120;
  int frames = 16;
  bool touch = true;  ///< false: the arm stops short of the object
  bool moving_background = false;
  int object_x = 95;  ///< disc centre at frame 0, pixels
  int radius = 16;
  int arm_start = 40;  ///< arm tip at frame 0
  int arm_speed = 4;   ///< pixels a frame
  std::string object = "mug";
  unsigned seed = 1;
  bool masks = true;
};

/// Arm tip x in frame i (it stops short of the object when !touch).
inline int arm_tip(const PushSpec& s, int i) {
  int tip = s.arm_start + s.arm_speed * i;
  if (!s.touch) tip = std::min(tip, s.object_x - s.radius - 12);
  return tip;
}

/// Object centre x in frame i: pushed once the tip reaches its left edge.
inline int object_centre(const PushSpec& s, int i) {
  const int tip = arm_tip(s, i);
  return std::max(s.object_x, tip + s.radius);
}

/// The first frame where the tip reaches the disc (-1: never).
inline int push_first_touch(const PushSpec& s) {
  for (int i = 0; i < s.frames; ++i) {
    if (arm_tip(s, i) + s.radius >= s.object_x) return i;
  }
  return -1;
}

inline cv::Mat3b block_texture(int w, int h, int block, unsigned seed) {
  std::mt19937 gen(seed);
  std::uniform_int_distribution<int> u(30, 225);
  cv::Mat3b small((h + block - 1) / block, (w + block - 1) / block);
  for (auto& p : small) p = cv::Vec3b(u(gen), u(gen), u(gen));
  cv::Mat3b big;
  cv::resize(small, big, cv::Size(small.cols * block, small.rows * block), 0, 0, cv::INTER_NEAREST);
  return big(cv::Rect(0, 0, w, h)).clone();
}

inline fs::path write_push_episode(const fs::path& dir, const PushSpec& s) {
  episode::EpisodeInfo info = test::synthetic_info(s.width, s.height, "baseline_test", s.seed);
  info.arm_name = "test-arm";
  info.has_masks = s.masks;
  info.provenance.source = episode::Source::kSimulated;
  info.provenance.scenario = "push";
  info.provenance.switches = {{"background", s.moving_background ? "moving" : "static"},
                              {"object", s.object}};
  geometry::Camera cam;
  cam.K << 100.0, 0.0, s.width / 2.0, 0.0, 100.0, s.height / 2.0, 0.0, 0.0, 1.0;
  cam.R = Eigen::Matrix3d::Identity();
  cam.t = Eigen::Vector3d(0.0, 0.0, 1.0);
  std::vector<episode::ObjectInfo> objects = {{1, s.object, episode::ObjectRole::kTarget},
                                              {2, "arm", episode::ObjectRole::kArm}};
  const cv::Mat3b backdrop = block_texture(s.width * 2, s.height, 10, s.seed);
  const cv::Mat3b object_texture = block_texture(2 * s.radius + 1, 2 * s.radius + 1, 5, s.seed + 7);
  const int y0 = s.height / 2;
  const int first_touch = push_first_touch(s);
  return test::write_synthetic_episode(dir, info, cam, objects, s.frames, [&](int i) {
    cv::Mat3b img = backdrop(cv::Rect(0, 0, s.width, s.height)).clone();
    if (s.moving_background) {
      // "People" (blocks) appear at random places in the upper third.
      std::mt19937 people(s.seed * 1000 + i);
      std::uniform_int_distribution<int> px(0, s.width - 14), py(0, s.height / 3 - 22);
      for (int k = 0; k < 3; ++k) {
        img(cv::Rect(px(people), py(people), 12, 20)).setTo(cv::Vec3b(20, 40, 200));
      }
    }
    cv::Mat1w mask(s.height, s.width, ushort(0));
    const int cx = object_centre(s, i);
    cv::Mat1b disc(s.height, s.width, uchar(0));
    cv::circle(disc, {cx, y0}, s.radius, cv::Scalar(255), cv::FILLED);
    const cv::Rect box(cx - s.radius, y0 - s.radius, 2 * s.radius + 1, 2 * s.radius + 1);
    const cv::Rect inside = box & cv::Rect(0, 0, s.width, s.height);
    object_texture(cv::Rect(inside.x - box.x, inside.y - box.y, inside.width, inside.height))
        .copyTo(img(inside), disc(inside));
    mask.setTo(1, disc);
    const int tip = arm_tip(s, i);
    const cv::Rect arm(0, y0 - 6, std::max(1, tip), 12);
    img(arm & cv::Rect(0, 0, s.width, s.height)).setTo(cv::Vec3b(128, 128, 128));
    mask(arm & cv::Rect(0, 0, s.width, s.height)).setTo(2);
    test::SyntheticFrame f{img, test::arm_at(i, 25.0, Eigen::Vector3d::Zero()), {}};
    f.arm.ee_image = Eigen::Vector2d(tip, y0);
    f.arm.touching = first_touch >= 0 && i >= first_touch;
    if (s.masks) f.extras.mask = mask;
    return f;
  });
}

}  // namespace proprio::segmentation::testing
