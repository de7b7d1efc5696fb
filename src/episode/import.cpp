#include "proprio/episode/import.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdio>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "proprio/core/csv.hpp"
#include "proprio/core/error.hpp"
#include "proprio/core/progress.hpp"
#include "proprio/episode/episode_writer.hpp"
#include "proprio/geometry/camera.hpp"

namespace proprio::episode {
namespace fs = std::filesystem;
namespace {

std::string joint_column(int k) {
  std::string name = "q";  // built in steps: GCC 12's -Wrestrict misfires on "q" + string
  name += std::to_string(k);
  return name;
}

}  // namespace

ArmLog read_arm_log(const fs::path& path) {
  core::CsvReadOptions opt;
  opt.required_columns = {"t", "ee_x", "ee_y", "ee_z"};
  const core::CsvTable table = core::read_csv(path, opt);
  ArmLog log;
  log.source = path;
  while (table.has_column(joint_column(log.joint_count + 1))) ++log.joint_count;
  log.has_touching = table.has_column("touching");
  const size_t ct = table.column("t");
  const size_t cx = table.column("ee_x");
  const size_t cy = table.column("ee_y");
  const size_t cz = table.column("ee_z");
  std::vector<size_t> cq;
  for (int k = 1; k <= log.joint_count; ++k) cq.push_back(table.column(joint_column(k)));
  for (size_t r = 0; r < table.rows.size(); ++r) {
    const double t = table.at(r, ct);
    if (!log.t.empty() && !(t > log.t.back())) {
      throw Error::at_line(path, table.lines[r],
                           "t = " + std::to_string(t) + " is not after the previous sample's " +
                               std::to_string(log.t.back()) + " (time must increase)");
    }
    log.t.push_back(t);
    log.ee.emplace_back(table.at(r, cx), table.at(r, cy), table.at(r, cz));
    Eigen::VectorXd q(log.joint_count);
    for (int k = 0; k < log.joint_count; ++k) q[k] = table.at(r, cq[static_cast<size_t>(k)]);
    log.q.push_back(q);
    bool touching = false;
    if (log.has_touching) {
      const double v = table.at(r, table.column("touching"));
      if (v != 0.0 && v != 1.0) {
        throw Error::at_line(path, table.lines[r],
                             "touching is " + std::to_string(v) + ", expected 0 or 1");
      }
      touching = v == 1.0;
    }
    log.touching.push_back(touching);
  }
  return log;
}

ArmSample sample_arm_log(const ArmLog& log, double t, double period) {
  assert(!log.t.empty() && t >= log.t.front() && t <= log.t.back() && period > 0);
  // k: the last sample at or before t.
  const auto after = std::upper_bound(log.t.begin(), log.t.end(), t);
  const size_t k = static_cast<size_t>(after - log.t.begin()) - 1;
  ArmSample s;
  s.t = t;
  if (k + 1 < log.t.size()) {
    const double a = (t - log.t[k]) / (log.t[k + 1] - log.t[k]);
    s.ee = (1 - a) * log.ee[k] + a * log.ee[k + 1];
    s.q = (1 - a) * log.q[k] + a * log.q[k + 1];
  } else {
    s.ee = log.ee[k];
    s.q = log.q[k];
  }
  // The frame's interval (t - period, t]: samples k down to the first one after t - period.
  const auto first = std::upper_bound(log.t.begin(), log.t.end(), t - period);
  size_t lo = static_cast<size_t>(first - log.t.begin());
  if (lo > k) lo = k;  // no sample inside: hold the last one before t
  for (size_t j = lo; j <= k; ++j) s.touching = s.touching || log.touching[j];
  return s;
}

void ImportOptions::validate() const {
  if (fps) {
    require(std::isfinite(*fps) && *fps > 0 && *fps <= kMaxFps,
            "import: --fps must be in (0, " + std::to_string(static_cast<int>(kMaxFps)) +
                "], not " + std::to_string(*fps));
  }
  require(std::isfinite(time_offset), "import: --time-offset must be finite");
  if (max_frames) require(*max_frames >= 1, "import: --max-frames must be at least 1");
  require(!arm_name.empty(), "import: the arm name must not be empty");
}

ImportResult import_recording(const fs::path& video, const fs::path& arm_log, const fs::path& calib,
                              const fs::path& out, const ImportOptions& options,
                              const core::Provenance& provenance) {
  options.validate();
  const ArmLog log = read_arm_log(arm_log);
  geometry::Camera camera = geometry::read_calib(calib);
  std::error_code ec;
  if (!fs::is_regular_file(video, ec)) throw Error::in_file(video, "no such video file");
  cv::VideoCapture cap;
  if (!cap.open(video.string()) || !cap.isOpened()) {
    throw Error::in_file(video, "cannot open as a video (OpenCV cannot read it)");
  }
  ImportSummary sum;
  sum.fps = options.fps.value_or(cap.get(cv::CAP_PROP_FPS));
  if (!std::isfinite(sum.fps) || sum.fps <= 0 || sum.fps > kMaxFps) {
    throw Error::in_file(video, "does not state a usable frame rate; pass --fps");
  }
  sum.log_samples = static_cast<int>(log.t.size());
  sum.log_start = log.t.front();
  sum.log_end = log.t.back();
  const double period = 1.0 / sum.fps;
  // Frame times and log times are compared with a tolerance, so that a frame meant to fall on
  // the log's first or last sample is not lost to rounding of offset + i / fps.
  const double tol = 1e-9 * std::max(1.0, std::abs(sum.log_end));

  cv::Mat frame;
  if (!cap.read(frame) || frame.empty()) throw Error::in_file(video, "holds no decodable frame");
  const int width = frame.cols;
  const int height = frame.rows;
  if (width > kMaxImageSide || height > kMaxImageSide) {
    throw Error::in_file(video, "frames of " + std::to_string(width) + "x" +
                                    std::to_string(height) + " are larger than supported");
  }
  if (camera.width > 0 && (camera.width != width || camera.height != height)) {
    throw Error::in_file(calib, "is for " + std::to_string(camera.width) + "x" +
                                    std::to_string(camera.height) + " images, the video's are " +
                                    std::to_string(width) + "x" + std::to_string(height));
  }
  cv::Mat K;
  cv::eigen2cv(camera.K, K);
  cv::Mat map1, map2;
  sum.undistorted = camera.has_distortion();
  if (sum.undistorted) {
    // cv::undistort's own maps, computed once for the whole video instead of once per frame.
    cv::initUndistortRectifyMap(K, camera.dist, cv::Mat(), K, frame.size(), CV_16SC2, map1, map2);
  }
  camera.dist.clear();
  camera.width = width;
  camera.height = height;

  EpisodeInfo info;
  info.fps = sum.fps;
  info.width = width;
  info.height = height;
  info.arm_name = options.arm_name;
  info.joint_count = log.joint_count;
  info.storage = options.storage;
  info.provenance.run = provenance;
  info.provenance.source = Source::kReal;
  info.provenance.scenario = options.scenario;
  EpisodeWriter writer(out, info, camera, {}, std::nullopt, {.overwrite = options.overwrite});

  const double reported = cap.get(cv::CAP_PROP_FRAME_COUNT);
  const std::size_t total =
      options.max_frames
          ? static_cast<std::size_t>(*options.max_frames)
          : static_cast<std::size_t>(std::max(0.0, std::isfinite(reported) ? reported : 0.0));
  core::ProgressBar progress(total, "import", options.progress && total > 0);
  sum.stop_reason = "end of video";
  for (int index = 0;; ++index) {
    if (index > 0 && (!cap.read(frame) || frame.empty())) break;  // frame 0 is already read
    ++sum.video_frames_read;
    const double t = options.time_offset + index / sum.fps;
    if (t < sum.log_start - tol) {
      ++sum.dropped_before_log;
      continue;
    }
    if (t > sum.log_end + tol) {
      sum.stop_reason = "end of arm log";
      break;
    }
    if (frame.cols != width || frame.rows != height) {
      throw Error::in_file(video, "frame " + std::to_string(index) + " changes size");
    }
    if (sum.frames_written == 0) sum.first_video_frame = index;
    ArmSample s = sample_arm_log(log, std::clamp(t, sum.log_start, sum.log_end), period);
    s.t = t;
    if (camera.depth(s.ee) > 0) {
      s.ee_image = camera.project(s.ee);
    } else {
      ++sum.behind_camera_frames;
    }
    if (s.touching) {
      if (!sum.first_touch_frame) sum.first_touch_frame = sum.frames_written;
      ++sum.touching_frames;
    }
    cv::Mat image = frame;
    if (sum.undistorted) {
      cv::remap(frame, image, map1, map2, cv::INTER_LINEAR, cv::BORDER_CONSTANT);
    }
    writer.add_frame(image, s);
    ++sum.frames_written;
    progress.tick();
    if (options.max_frames && sum.frames_written >= *options.max_frames) {
      sum.stop_reason = "max_frames reached";
      break;
    }
  }
  if (sum.frames_written == 0) {
    const double last = options.time_offset + (sum.video_frames_read - 1) / sum.fps;
    throw Error::in_file(
        video, "no frame falls within the arm log's time span [" + std::to_string(sum.log_start) +
                   ", " + std::to_string(sum.log_end) + "] s: the video's " +
                   std::to_string(sum.video_frames_read) + " frames are at [" +
                   std::to_string(options.time_offset) + ", " + std::to_string(last) +
                   "] s (frame i at time-offset + i / fps); check --time-offset and --fps");
  }
  progress.finish();
  writer.finish();
  ImportResult r{out, sum, core::result_document("proprio.episode.import", 1, provenance), {}};
  core::fields_into_json(r, r.document);
  r.message = out.string() + ": " + std::to_string(sum.frames_written) + " frames imported";
  return r;
}

std::string ImportResult::brief() const {
  return "episode: " + episode.string() + "\n" + format_import_summary(summary);
}

core::Json to_json(const ImportSummary& s) { return core::fields_to_json(s); }

std::string format_import_summary(const ImportSummary& s) {
  char buf[512];
  std::snprintf(
      buf, sizeof buf,
      "frames: %d written (video frames %d..%d at %g fps; %d before the log dropped)\n"
      "arm log: %d samples over [%.3f, %.3f] s\n"
      "lens distortion: %s\n"
      "first touch: %s\n"
      "stopped: %s\n",
      s.frames_written, s.first_video_frame, s.first_video_frame + s.frames_written - 1, s.fps,
      s.dropped_before_log, s.log_samples, s.log_start, s.log_end,
      s.undistorted ? "removed from every frame" : "none in the calibration",
      s.first_touch_frame ? ("frame " + std::to_string(*s.first_touch_frame)).c_str() : "never",
      s.stop_reason.c_str());
  std::string out = buf;
  if (s.behind_camera_frames > 0) {
    out += "warning: the end-effector is behind the camera in ";
    out += std::to_string(s.behind_camera_frames);
    out += " frames (ee_u, ee_v left empty)\n";
  }
  return out;
}

}  // namespace proprio::episode
