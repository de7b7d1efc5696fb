#include "proprio/sim/sim_runs.hpp"

#include <cstdio>

#include "proprio/geometry/camera.hpp"
#include "proprio/sim/object_catalogue.hpp"

#include "proprio/core/text.hpp"

namespace proprio::sim {
namespace {}  // namespace

SimRun run_sim_record(const RecordOptions& options, const std::filesystem::path& out,
                      const core::Provenance& provenance) {
  const auto catalogue = ObjectCatalogue::load_default();
  const RecordSummary s = record_episode(out, options, provenance, catalogue);
  SimRun r;
  r.report = core::printf_string(
      "episode: %s\n%s\nframes: %d\nseconds: %.3f\nfps: %.2f\nfirst touch: %s\n", out.c_str(),
      s.message.c_str(), s.frames, s.seconds, s.fps,
      s.first_touch_frame ? std::to_string(*s.first_touch_frame).c_str() : "none");
  core::Json& doc = r.document;
  doc = core::result_document("proprio.sim.record", 1, provenance);
  doc["episode"] = out.string();
  doc["scenario"] = options.scenario;
  doc["switches"] = options.switches();
  doc["frames"] = s.frames;
  doc["seconds"] = s.seconds;
  doc["fps"] = s.fps;
  doc["first_touch_frame"] = s.first_touch_frame ? core::Json(*s.first_touch_frame) : core::Json();
  doc["target_moved_m"] = s.target_moved;
  return r;
}

SimRun run_sim_calibrate(const SimCalibrationOptions& options, const std::filesystem::path& out,
                         const core::Provenance& provenance) {
  const SimCalibrationResult c = calibrate_simulated(options);
  geometry::Camera cam = c.dlt.camera;
  cam.width = options.width;
  cam.height = options.height;
  geometry::write_calib(out, cam, provenance);
  SimRun r;
  r.report = core::printf_string(
                 "%s (%d unreachable, %d marker not seen)\nrms_px: %.4f\ntrue_error_px: %.4f\n",
                 c.summary.message.c_str(), c.summary.unreachable, c.summary.not_detected,
                 c.dlt.rms_px, c.true_error_px) +
             core::printf_string("calibration: %s\n", out.c_str());
  core::Json& doc = r.document;
  doc = core::result_document("proprio.sim.calibrate", 1, provenance);
  doc["calib"] = out.string();
  doc["grid"] = options.grid;
  doc["grid_points"] = c.summary.grid_points;
  doc["used"] = c.summary.used;
  doc["unreachable"] = c.summary.unreachable;
  doc["not_detected"] = c.summary.not_detected;
  doc["rms_px"] = c.dlt.rms_px;
  doc["true_error_px"] = c.true_error_px;
  return r;
}

SimRun run_sim_views(const ViewsOptions& options, const std::filesystem::path& out,
                     const core::Provenance& provenance) {
  const auto catalogue = ObjectCatalogue::load_default();
  const ViewsSummary s = render_views(out, options, catalogue);
  SimRun r;
  r.report = core::printf_string("views: %s\n%s\n", out.c_str(), s.message.c_str());
  core::Json& doc = r.document;
  doc = core::result_document("proprio.sim.views", 1, provenance);
  doc["out"] = out.string();
  doc["objects"] = options.objects;
  doc["per_object"] = options.per_object;
  doc["images"] = s.images;
  return r;
}

}  // namespace proprio::sim
