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
  r.document = core::result_document("proprio.sim.record", 1, provenance);
  core::fields_into_json(SimRecordRecord{out, options.scenario, options.switches(), s}, r.document);
  r.message = core::first_line(r.brief());
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
  r.document = core::result_document("proprio.sim.calibrate", 1, provenance);
  core::fields_into_json(
      SimCalibrateRecord{out, options.grid, c.summary, c.dlt.rms_px, c.true_error_px}, r.document);
  r.message = core::first_line(r.brief());
  return r;
}

SimRun run_sim_views(const ViewsOptions& options, const std::filesystem::path& out,
                     const core::Provenance& provenance) {
  const auto catalogue = ObjectCatalogue::load_default();
  const ViewsSummary s = render_views(out, options, catalogue);
  SimRun r;
  r.report = core::printf_string("views: %s\n%s\n", out.c_str(), s.message.c_str());
  r.document = core::result_document("proprio.sim.views", 1, provenance);
  core::fields_into_json(SimViewsRecord{out, options.objects, options.per_object, s.images},
                         r.document);
  r.message = core::first_line(r.brief());
  return r;
}

}  // namespace proprio::sim
