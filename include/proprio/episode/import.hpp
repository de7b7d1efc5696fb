#pragma once
// Turning a real robot's recording (a video, a timestamped arm log, a calibration) into an
// episode.

#include <Eigen/Core>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "proprio/core/fields.hpp"
#include "proprio/core/json_io.hpp"
#include "proprio/core/provenance.hpp"
#include "proprio/episode/arm_sample.hpp"
#include "proprio/episode/episode_info.hpp"

namespace proprio::episode {

/// A real arm's log: CSV with a header holding `t` (seconds, strictly increasing) and
/// `ee_x,ee_y,ee_z` (metres, robot frame), optionally q1..qN (rad) and `touching` (0/1); other
/// columns are ignored.
struct ArmLog {
  std::filesystem::path source;
  std::vector<double> t;
  std::vector<Eigen::Vector3d> ee;
  std::vector<Eigen::VectorXd> q;  ///< each of size joint_count
  std::vector<bool> touching;      ///< all false when the log has no touching column
  int joint_count = 0;
  bool has_touching = false;
};

/// Reads and validates an arm log. Throws Error naming the file and line.
ArmLog read_arm_log(const std::filesystem::path& path);

/// The arm's state for a frame taken at time `t` (log clock) with frame period `period` (1/fps):
/// ee and q interpolated linearly between the log samples around t; touching set when any log
/// sample in the frame's interval (t - period, t] touches, or, when none falls inside it (a log
/// slower than the video), when the last sample before t does. ee_image is left empty.
/// Precondition: log.t.front() <= t <= log.t.back().
ArmSample sample_arm_log(const ArmLog& log, double t, double period);

struct ImportOptions {
  /// Frame rate of the video, frames per second; none = the rate the video file states.
  std::optional<double> fps;
  /// Log time of the video's first frame, seconds: frame i is at time_offset + i / fps.
  double time_offset = 0.0;
  /// Write at most this many frames; none = all.
  std::optional<int> max_frames;
  std::string arm_name = "real";
  std::optional<std::string> scenario;
  FrameStorage storage = FrameStorage::kPng;
  bool overwrite = false;
  bool progress = false;  ///< a progress bar on stderr

  /// Throws Error when a value is out of range.
  void validate() const;
};

/// What import_recording did.
struct ImportSummary {
  int video_frames_read = 0;   ///< frames decoded from the video
  int frames_written = 0;      ///< frames of the episode
  int dropped_before_log = 0;  ///< leading frames earlier than the log's first sample
  int first_video_frame = 0;   ///< video index of the episode's frame 0
  double fps = 0.0;
  double log_start = 0.0;  ///< the log's time span, seconds
  double log_end = 0.0;
  int log_samples = 0;
  bool undistorted = false;  ///< the calibration had lens distortion, removed from every frame
  int touching_frames = 0;
  std::optional<int> first_touch_frame;
  int behind_camera_frames = 0;  ///< frames whose end-effector projects behind the camera
  std::string stop_reason;       ///< "end of video", "end of arm log" or "max_frames reached"

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.video_frames_read, {"video_frames_read", "Frames decoded from the video"});
    v(self.frames_written, {"frames_written", "Frames of the episode"});
    v(self.dropped_before_log, {"dropped_before_log", "Leading frames before the log's start"});
    v(self.first_video_frame, {"first_video_frame", "Video index of the episode's frame 0"});
    v(self.fps, {"fps", "Frame rate, frames per second"});
    v(std::vector<double>{self.log_start, self.log_end},
      {"log_span_s", "The log's time span [start, end], s"});
    v(self.log_samples, {"log_samples", "Samples in the arm log"});
    v(self.undistorted, {"undistorted", "Lens distortion was removed"});
    v(self.touching_frames, {"touching_frames", "Frames with the arm touching"});
    v(self.first_touch_frame ? core::Json(*self.first_touch_frame) : core::Json(nullptr),
      {"first_touch_frame", "The first touch (null: none)"});
    v(self.behind_camera_frames, {"behind_camera_frames", "Frames with ee behind the camera"});
    v(self.stop_reason, {"stop_reason", "Why reading stopped"});
  }
};

// NOLINTNEXTLINE(bugprone-exception-escape)
struct ImportResult {
  std::filesystem::path episode;  ///< the episode directory written
  ImportSummary summary;
  /// The record (format "proprio.episode.import"): the episode and the summary's fields.
  core::Json document;
  /// One line: "DIR: N frames imported".
  std::string message;

  /// "episode: DIR", then the summary's lines (format_import_summary).
  [[nodiscard]] std::string brief() const;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.episode, {"episode", "The episode directory written"});
    ImportSummary::describe(self.summary, v);
  }
};

/// The summary's fields as JSON (to add to a result document).
core::Json to_json(const ImportSummary& s);
/// Human-readable lines, "key: value".
std::string format_import_summary(const ImportSummary& s);

/// Imports a recording into episode directory `out`. Frames before the log's first sample are
/// dropped; reading stops at the first frame after the log's last sample (frames are never
/// extrapolated); it is an error when no frame falls within the log's span. Lens distortion of
/// `calib` is removed from every frame (cv::undistort with the same camera matrix), and the
/// written calib.yml has none; ee_u, ee_v are the projection of ee through P = K [R | t]
/// (empty where the end-effector is behind the camera). Writes atomically (EpisodeWriter).
/// Throws Error naming the file at fault.
ImportResult import_recording(const std::filesystem::path& video,
                              const std::filesystem::path& arm_log,
                              const std::filesystem::path& calib, const std::filesystem::path& out,
                              const ImportOptions& options, const core::Provenance& provenance);

}  // namespace proprio::episode
