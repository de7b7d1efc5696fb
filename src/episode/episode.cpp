#include "proprio/episode/episode.hpp"

#include <cassert>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "layout.hpp"
#include "proprio/core/error.hpp"
#include "proprio/geometry/image_file.hpp"
#include "video_cursor.hpp"

namespace proprio::episode {
namespace {

std::string size_str(int w, int h) { return std::to_string(w) + "x" + std::to_string(h); }

void check_size(const cv::Mat& m, const EpisodeInfo& info, const std::filesystem::path& file) {
  if (m.cols != info.width || m.rows != info.height) {
    throw Error::in_file(file, "is " + size_str(m.cols, m.rows) + ", expected " +
                                   size_str(info.width, info.height) +
                                   " (episode.json's image size)");
  }
}

cv::Mat to_bgr(cv::Mat m) {
  if (m.channels() == 1) cv::cvtColor(m, m, cv::COLOR_GRAY2BGR);
  return m;
}

cv::Mat read_png(const std::filesystem::path& file, int flags) {
  return geometry::read_image(file, flags);
}

cv::Mat read_ids16(const std::filesystem::path& file, const EpisodeInfo& info, const char* what) {
  cv::Mat m = read_png(file, cv::IMREAD_UNCHANGED);
  if (m.type() != CV_16UC1) {
    throw Error::in_file(
        file, std::string("is not a 16-bit single-channel image (") + what + " must be)");
  }
  check_size(m, info, file);
  return m;
}

}  // namespace

const ObjectInfo* Episode::object(int id) const {
  for (const auto& o : objects_) {
    if (o.id == id) return &o;
  }
  return nullptr;
}

namespace {

/// Frame i of one camera: from its video when the episode stores one, else from its PNG folder.
cv::Mat read_frame(const std::shared_ptr<detail::VideoCursor>& video,
                   const std::filesystem::path& video_file, const std::filesystem::path& dir,
                   const char* subdir, const EpisodeInfo& info, int i) {
  if (video) {
    cv::Mat m = to_bgr(video->read(i));
    check_size(m, info, video_file);
    return m;
  }
  const auto file = image_path(dir, subdir, i);
  cv::Mat m = read_png(file, cv::IMREAD_COLOR);
  check_size(m, info, file);
  return m;
}

}  // namespace

cv::Mat Episode::frame(int i) const {
  assert(i >= 0 && i < frame_count());
  return read_frame(video_, dir_ / info_.video_file, dir_, detail::kFramesDir, info_, i);
}

cv::Mat Episode::frame_right(int i) const {
  assert(info_.stereo && i >= 0 && i < frame_count());
  return read_frame(video_right_, dir_ / info_.video_file_right, dir_, detail::kFramesRightDir,
                    info_, i);
}

cv::Mat Episode::mask(int i) const {
  assert(info_.has_masks && i >= 0 && i < frame_count());
  const auto file = image_path(dir_, detail::kMasksDir, i);
  cv::Mat m = read_ids16(file, info_, "masks");
  const auto unknown = detail::unknown_mask_ids(m, objects_);
  if (!unknown.empty()) {
    throw Error::in_file(file, "holds object id" + std::string(unknown.size() == 1 ? " " : "s ") +
                                   detail::list_ids(unknown) + " that objects.json lacks");
  }
  return m;
}

cv::Mat Episode::depth(int i) const {
  assert(info_.has_depth && i >= 0 && i < frame_count());
  return read_ids16(image_path(dir_, detail::kDepthDir, i), info_, "depth images");
}

std::vector<double> Episode::frame_times() const {
  std::vector<double> t;
  t.reserve(arm_.size());
  for (const auto& s : arm_) t.push_back(s.t);
  return t;
}

std::optional<int> Episode::first_touch_frame() const {
  for (size_t i = 0; i < arm_.size(); ++i) {
    if (arm_[i].touching) return static_cast<int>(i);
  }
  return std::nullopt;
}

std::optional<Eigen::Vector2d> Episode::ee_image(int i) const {
  assert(i >= 0 && i < frame_count());
  const ArmSample& s = arm_[static_cast<size_t>(i)];
  if (s.ee_image) return s.ee_image;
  if (camera_.depth(s.ee) <= 0.0) return std::nullopt;
  if (!camera_.has_distortion()) return camera_.project(s.ee);
  // The frames show the lens distortion: project the way OpenCV models it.
  cv::Mat K, R, t, rvec;
  cv::eigen2cv(camera_.K, K);
  cv::eigen2cv(camera_.R, R);
  cv::eigen2cv(camera_.t, t);
  cv::Rodrigues(R, rvec);
  const std::vector<cv::Point3d> X = {{s.ee.x(), s.ee.y(), s.ee.z()}};
  std::vector<cv::Point2d> x;
  cv::projectPoints(X, rvec, t, K, camera_.dist, x);
  return Eigen::Vector2d(x[0].x, x[0].y);
}

std::vector<std::optional<Eigen::Vector2d>> Episode::ee_image_track() const {
  std::vector<std::optional<Eigen::Vector2d>> out;
  out.reserve(arm_.size());
  for (int i = 0; i < frame_count(); ++i) out.push_back(ee_image(i));
  return out;
}

Episode read_episode(const std::filesystem::path& dir) {
  detail::ProblemSink sink(true, 1);
  CheckOptions options;
  options.decode_images = false;
  detail::Loaded loaded = detail::load_episode(dir, sink, options);
  // The sink throws at the first problem, so everything is here.
  assert(loaded.info && loaded.camera && loaded.arm);
  Episode e;
  e.dir_ = dir;
  e.info_ = std::move(*loaded.info);
  e.camera_ = std::move(*loaded.camera);
  e.right_ = std::move(loaded.right_camera);
  e.arm_ = std::move(*loaded.arm);
  e.objects_ = std::move(loaded.objects);
  if (e.info_.storage == FrameStorage::kVideo) {
    e.video_ = std::make_shared<detail::VideoCursor>(dir / e.info_.video_file);
    if (e.info_.stereo) {
      e.video_right_ = std::make_shared<detail::VideoCursor>(dir / e.info_.video_file_right);
    }
  }
  return e;
}

}  // namespace proprio::episode
