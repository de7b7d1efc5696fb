#pragma once
// The library calls behind `proprio sim record | calibrate | views` (thesis 3.2.3, 5.1-5.2): each
// does its one job and returns what it did, the text the CLI prints and the --json record
// (docs/formats/schemas/sim_*.schema.json). `sim dataset` is dataset.hpp's.

#include <filesystem>
#include <string>
#include <vector>

#include "proprio/core/fields.hpp"
#include "proprio/core/json_io.hpp"
#include "proprio/core/provenance.hpp"
#include "proprio/sim/calibration.hpp"
#include "proprio/sim/recorder.hpp"
#include "proprio/sim/views.hpp"

namespace proprio::sim {

/// `sim record`'s record (after the provenance).
// NOLINTNEXTLINE(bugprone-exception-escape)
struct SimRecordRecord {
  std::filesystem::path episode;
  std::string scenario;
  RecordSwitches switches;
  RecordSummary summary;
  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.episode, {"episode", "The episode written"});
    v(self.scenario, {"scenario", "The scripted scenario"});
    v(self.switches, {"switches", "The disturbances switched on"});
    v(self.summary.frames, {"frames", "Frames recorded"});
    v(self.summary.seconds, {"seconds", "Wall clock"});
    v(self.summary.fps, {"fps", "Frames per second recorded"});
    v(core::or_null(self.summary.first_touch_frame),
      {"first_touch_frame", "The first frame the hand touches the target (null: none)"});
    v(self.summary.target_moved, {"target_moved_m", "How far the target moved, m"});
  }
};

/// `sim calibrate`'s record.
struct SimCalibrateRecord {
  std::filesystem::path calib;
  int grid = 0;
  SimCalibrationSummary summary;
  double rms_px = 0;         ///< the DLT's reprojection RMS
  double true_error_px = 0;  ///< against the true camera
  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.calib, {"calib", "The calibration written"});
    v(self.grid, {"grid", "Marker grid points per side"});
    v(self.summary.grid_points, {"grid_points", "Points of the grid"});
    v(self.summary.used, {"used", "Pairs given to the DLT"});
    v(self.summary.unreachable, {"unreachable", "Skipped: no inverse kinematics solution"});
    v(self.summary.not_detected, {"not_detected", "Skipped: marker not seen"});
    v(self.rms_px, {"rms_px", "Reprojection RMS, px"});
    v(self.true_error_px, {"true_error_px", "Mean image distance to the true camera's, px"});
  }
};

/// `sim views`' record.
struct SimViewsRecord {
  std::filesystem::path out;
  std::vector<std::string> objects;
  int per_object = 0;
  int images = 0;
  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.out, {"out", "The folder-per-object views written"});
    v(self.objects, {"objects", "The objects"});
    v(self.per_object, {"per_object", "Images per object"});
    v(self.images, {"images", "Images written"});
  }
};

/// What a sim command did, under the Summary convention (core::Summary): brief() is what the CLI
/// prints, `message` its first line.
// NOLINTNEXTLINE(bugprone-exception-escape)
struct SimRun {
  std::string report;   ///< brief()'s text: lines, each ending in '\n'
  core::Json document;  ///< the --json record
  std::string message;  ///< one line: brief()'s first
  [[nodiscard]] std::string brief() const { return report; }
};

/// Records one episode into `out` (record_episode with the default catalogue).
SimRun run_sim_record(const RecordOptions& options, const std::filesystem::path& out,
                      const core::Provenance& provenance);

/// Calibrates the simulated camera (marker grid + DLT, 3.2.3) and writes calib.yml to `out`
/// with the image size of the options.
SimRun run_sim_calibrate(const SimCalibrationOptions& options, const std::filesystem::path& out,
                         const core::Provenance& provenance);

/// Renders the folder-per-object views into `out` (render_views with the default catalogue).
SimRun run_sim_views(const ViewsOptions& options, const std::filesystem::path& out,
                     const core::Provenance& provenance);

}  // namespace proprio::sim
