#pragma once
// Writing small synthetic episodes (episode::EpisodeWriter) for the tests of the modules that
// read episodes: each test draws its own frames; the camera, the episode's description and the
// writing are here.

#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "proprio/core/provenance.hpp"
#include "proprio/episode/episode_writer.hpp"
#include "proprio/geometry/camera.hpp"

namespace proprio::test {

/// A camera 1 m above the table looking straight down (world z up, camera z down, image y along
/// world -y): focal length `focal` and principal point (cx, cy), pixels. Its image size is left
/// 0: EpisodeWriter takes the episode's.
inline geometry::Camera overhead_camera(double focal, double cx, double cy) {
  geometry::Camera c;
  c.K << focal, 0.0, cx, 0.0, focal, cy, 0.0, 0.0, 1.0;
  c.R << 1, 0, 0, 0, -1, 0, 0, 0, -1;
  c.t = Eigen::Vector3d(0.0, 0.0, 1.0);
  return c;
}

/// What a synthetic episode says of itself: `width` x `height` frames at `fps`, arm "synthetic"
/// without joints, ground-truth masks, object 1 the target, made by a run of `command` with
/// `seed`. Tests change what differs.
inline episode::EpisodeInfo synthetic_info(int width, int height, const std::string& command,
                                           std::uint64_t seed, double fps = 25.0) {
  episode::EpisodeInfo info;
  info.fps = fps;
  info.width = width;
  info.height = height;
  info.arm_name = "synthetic";
  info.joint_count = 0;
  info.has_masks = true;
  info.target = 1;
  info.provenance.run = core::Provenance::current({command}, seed);
  return info;
}

/// The arm at frame i of an episode at `fps` (time i / fps), no joints, the end effector at `ee`
/// (metres, robot frame), its image position unknown and not touching.
inline episode::ArmSample arm_at(int i, double fps, const Eigen::Vector3d& ee) {
  episode::ArmSample a;
  a.t = i / fps;
  a.q = Eigen::VectorXd(0);
  a.ee = ee;
  return a;
}

/// One frame of a synthetic episode: the image, the arm's state and what else is stored.
struct SyntheticFrame {
  cv::Mat image;
  episode::ArmSample arm;
  episode::FrameExtras extras;
};

/// Writes an episode of `frames` frames to `dir`, frame i being `frame(i)`, and returns `dir`.
inline std::filesystem::path write_synthetic_episode(
    const std::filesystem::path& dir, const episode::EpisodeInfo& info,
    const geometry::Camera& camera, const std::vector<episode::ObjectInfo>& objects, int frames,
    const std::function<SyntheticFrame(int)>& frame,
    const std::optional<geometry::Camera>& right_camera = std::nullopt) {
  episode::EpisodeWriter w(dir, info, camera, objects, right_camera);
  for (int i = 0; i < frames; ++i) {
    const SyntheticFrame f = frame(i);
    w.add_frame(f.image, f.arm, f.extras);
  }
  w.finish();
  return dir;
}

}  // namespace proprio::test
