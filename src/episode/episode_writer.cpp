#include "proprio/episode/episode_writer.hpp"

#include <cassert>
#include <cmath>
#include <future>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "layout.hpp"
#include "parse.hpp"
#include "proprio/core/error.hpp"
#include "proprio/episode/episode.hpp"

namespace proprio::episode {
namespace fs = std::filesystem;

void EpisodeWriterOptions::validate() const {
  require(
      png_compression >= 0 && png_compression <= 9,
      "episode writer: png_compression must be in [0, 9], not " + std::to_string(png_compression));
  require(video_fourcc.size() == 4,
          "episode writer: video_fourcc must have 4 characters, not '" + video_fourcc + "'");
}

namespace {

std::string size_str(int w, int h) { return std::to_string(w) + "x" + std::to_string(h); }

/// Checks everything about info and objects that can be checked before the first frame, with the
/// same parser the reader uses (so that what is written reads back).
void validate_setup(const EpisodeInfo& info, const std::vector<ObjectInfo>& objects,
                    const fs::path& dir) {
  EpisodeInfo probe = info;
  probe.frame_count = 1;
  detail::ProblemSink sink(true, 1);
  detail::parse_episode_info(to_json(probe), dir / detail::kEpisodeJson, sink);
  if (!objects.empty()) {
    detail::parse_objects(objects_to_json(objects), dir / detail::kObjectsJson, sink);
  }
  const bool needs_objects = info.has_masks || info.target;
  if (needs_objects && objects.empty()) {
    throw Error::in_file(dir, "an episode with masks or a target needs its objects (objects.json)");
  }
  if (info.target) {
    bool found = false;
    for (const auto& o : objects) {
      if (o.id == *info.target) {
        found = o.role == ObjectRole::kTarget;
        if (!found) throw Error::in_file(dir, "the target object must have the role 'target'");
      }
    }
    if (!found) {
      throw Error::in_file(dir,
                           "target " + std::to_string(*info.target) + " is not among the objects");
    }
  } else {
    for (const auto& o : objects) {
      if (o.role == ObjectRole::kTarget) {
        throw Error::in_file(dir, "object " + std::to_string(o.id) +
                                      " has the role 'target' but the episode has no target");
      }
    }
  }
}

void check_image(const cv::Mat& m, const EpisodeInfo& info, const fs::path& dir, int i,
                 const char* what, bool ids16) {
  const std::string where = std::string(what) + " of frame " + std::to_string(i);
  if (m.empty()) throw Error::in_file(dir, where + " is missing (episode declares it)");
  if (m.cols != info.width || m.rows != info.height) {
    throw Error::in_file(dir, where + " is " + size_str(m.cols, m.rows) + ", expected " +
                                  size_str(info.width, info.height));
  }
  if (ids16 && m.type() != CV_16UC1) {
    throw Error::in_file(dir, where + " must be CV_16UC1");
  }
  if (!ids16 && m.type() != CV_8UC3 && m.type() != CV_8UC1) {
    throw Error::in_file(dir, where + " must be 8-bit BGR or grey (CV_8UC3 or CV_8UC1)");
  }
}

}  // namespace

EpisodeWriter::EpisodeWriter(fs::path dir, EpisodeInfo info, geometry::Camera camera,
                             std::vector<ObjectInfo> objects,
                             std::optional<geometry::Camera> right_camera,
                             EpisodeWriterOptions options)
    : staged_(std::move(dir), options.overwrite),
      info_(std::move(info)),
      camera_(std::move(camera)),
      objects_(std::move(objects)),
      right_(std::move(right_camera)),
      options_(std::move(options)) {
  options_.validate();
  const fs::path& final_dir = staged_.final_path();
  if (info_.storage == FrameStorage::kVideo) {
    if (info_.video_file.empty()) info_.video_file = "frames.avi";
    if (info_.stereo && info_.video_file_right.empty()) info_.video_file_right = "frames_right.avi";
  }
  validate_setup(info_, objects_, final_dir);
  if (info_.stereo != right_.has_value()) {
    throw Error::in_file(final_dir, info_.stereo ? "a stereo episode needs the right camera"
                                                 : "a right camera given for a mono episode");
  }
  for (geometry::Camera* cam : {&camera_, right_ ? &*right_ : nullptr}) {
    if (!cam) continue;
    if (cam->width != 0 && (cam->width != info_.width || cam->height != info_.height)) {
      throw Error::in_file(final_dir, "the camera is for " + size_str(cam->width, cam->height) +
                                          " images, the episode's are " +
                                          size_str(info_.width, info_.height));
    }
    cam->width = info_.width;
    cam->height = info_.height;
  }
  const fs::path& stage = staged_.staging_path();
  if (info_.storage == FrameStorage::kPng) {
    fs::create_directory(stage / detail::kFramesDir);
    if (info_.stereo) fs::create_directory(stage / detail::kFramesRightDir);
  }
  if (info_.has_masks) fs::create_directory(stage / detail::kMasksDir);
  if (info_.has_depth) fs::create_directory(stage / detail::kDepthDir);
  arm_csv_.open(stage / detail::kArmCsv, std::ios::binary);
  if (!arm_csv_) throw Error::in_file(stage / detail::kArmCsv, "cannot write");
  std::string header;
  for (const auto& h : arm_csv_header(info_.joint_count)) {
    if (!header.empty()) header += ',';
    header += h;
  }
  arm_csv_ << header << '\n';
}

EpisodeWriter::~EpisodeWriter() {
  // Release the writers before staged_ removes the directory they write into.
  video_.reset();
  video_right_.reset();
  arm_csv_.close();
}

void EpisodeWriter::write_image(const std::string& subdir, const cv::Mat& image) {
  const fs::path file = image_path(staged_.staging_path(), subdir, count_);
  // With no parameters OpenCV's PNG encoder takes its speed-tuned path (SUB filter, zlib level 1,
  // Z_RLE); naming any level, even 1, makes libpng try every filter on every row: 1.5x the time
  // for colour frames, 2x for 16-bit masks, for the same size. So level 1 names no level.
  std::vector<int> params;
  if (options_.png_compression != 1)
    params = {cv::IMWRITE_PNG_COMPRESSION, options_.png_compression};
  bool ok = false;
  try {
    ok = cv::imwrite(file.string(), image, params);
  } catch (const cv::Exception& e) {
    throw Error::in_file(file, "cannot write: " + e.err);
  }
  if (!ok) throw Error::in_file(file, "cannot write");
}

void EpisodeWriter::add_frame(const cv::Mat& image, const ArmSample& arm,
                              const FrameExtras& extras) {
  assert(!finished_);
  const fs::path& dir = staged_.final_path();
  const std::string where = "arm sample of frame " + std::to_string(count_);
  check_image(image, info_, dir, count_, "image", false);
  if (arm.q.size() != info_.joint_count) {
    throw Error::in_file(dir, where + " has " + std::to_string(arm.q.size()) +
                                  " joints, expected " + std::to_string(info_.joint_count));
  }
  if (!std::isfinite(arm.t) || !arm.q.allFinite() || !arm.ee.allFinite() ||
      (arm.ee_image && !arm.ee_image->allFinite())) {
    throw Error::in_file(dir, where + " holds NaN or inf");
  }
  if (count_ > 0 && !(arm.t > last_t_)) {
    throw Error::in_file(dir, where + ": time " + std::to_string(arm.t) +
                                  " s is not after the previous frame's " +
                                  std::to_string(last_t_) + " s");
  }
  if (info_.has_masks)
    check_image(extras.mask, info_, dir, count_, "mask", true);
  else if (!extras.mask.empty())
    throw Error::in_file(dir, "a mask given, the episode has none");
  if (info_.has_depth)
    check_image(extras.depth, info_, dir, count_, "depth image", true);
  else if (!extras.depth.empty())
    throw Error::in_file(dir, "a depth image given, the episode has none");
  if (info_.stereo)
    check_image(extras.right_image, info_, dir, count_, "right image", false);
  else if (!extras.right_image.empty())
    throw Error::in_file(dir, "a right image given for a mono episode");
  if (info_.has_masks) {
    const auto unknown = detail::unknown_mask_ids(extras.mask, objects_);
    if (!unknown.empty()) {
      throw Error::in_file(dir, "mask of frame " + std::to_string(count_) + " holds id" +
                                    (unknown.size() == 1 ? " " : "s ") + detail::list_ids(unknown) +
                                    " that the objects lack");
    }
  }

  // The mask and depth PNGs are encoded on a second thread while the frame is written: PNG
  // encoding is most of the writing time of a simulated recording. (A std::async future joins
  // in its destructor, also when the frame's write throws.)
  std::future<void> extras_written;
  if (info_.has_masks || info_.has_depth) {
    extras_written = std::async(std::launch::async, [&] {
      if (info_.has_masks) write_image(detail::kMasksDir, extras.mask);
      if (info_.has_depth) write_image(detail::kDepthDir, extras.depth);
    });
  }
  if (info_.storage == FrameStorage::kPng) {
    write_image(detail::kFramesDir, image);
    if (info_.stereo) write_image(detail::kFramesRightDir, extras.right_image);
  } else {
    const auto write_video = [&](std::unique_ptr<cv::VideoWriter>& writer, const std::string& name,
                                 const cv::Mat& m) {
      const fs::path file = staged_.staging_path() / name;
      if (!writer) {
        const auto& f = options_.video_fourcc;
        writer = std::make_unique<cv::VideoWriter>(
            file.string(), cv::VideoWriter::fourcc(f[0], f[1], f[2], f[3]), info_.fps,
            cv::Size(info_.width, info_.height), true);
        if (!writer->isOpened()) {
          throw Error::in_file(file, "cannot open a video writer with codec '" + f + "'");
        }
      }
      cv::Mat bgr = m;
      if (bgr.channels() == 1) cv::cvtColor(m, bgr, cv::COLOR_GRAY2BGR);
      writer->write(bgr);
    };
    write_video(video_, info_.video_file, image);
    if (info_.stereo) write_video(video_right_, info_.video_file_right, extras.right_image);
  }
  if (extras_written.valid()) extras_written.get();
  arm_csv_ << detail::format_arm_row(count_, arm);
  if (!arm_csv_) throw Error::in_file(staged_.staging_path() / detail::kArmCsv, "write failed");
  last_t_ = arm.t;
  ++count_;
}

void EpisodeWriter::finish() {
  assert(!finished_);
  const fs::path& stage = staged_.staging_path();
  if (count_ == 0) {
    throw Error::in_file(staged_.final_path(), "no frames were added: an episode has at least one");
  }
  video_.reset();
  video_right_.reset();
  arm_csv_.flush();
  arm_csv_.close();
  if (!arm_csv_) throw Error::in_file(stage / detail::kArmCsv, "write failed");
  info_.frame_count = count_;
  geometry::write_calib(stage / detail::kCalib, camera_);
  if (right_) geometry::write_calib(stage / detail::kCalibRight, *right_);
  if (!objects_.empty())
    core::write_json_atomic(stage / detail::kObjectsJson, objects_to_json(objects_));
  core::write_json_atomic(stage / detail::kEpisodeJson, to_json(info_));
  // Read it back: a writer never commits what the reader would refuse.
  const auto problems = check_episode(stage, {.decode_images = false, .max_problems_per_file = 1});
  // Every input was checked on the way in: a refusal here is the writer's bug, not bad input.
  const std::string first = problems.empty() ? std::string() : problems.front().message;
  ensure(problems.empty(), "episode writer produced an invalid episode: " + first);
  staged_.commit();
  finished_ = true;
}

}  // namespace proprio::episode
