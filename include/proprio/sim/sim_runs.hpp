#pragma once
// The library calls behind `proprio sim record | calibrate | views` (thesis 3.2.3, 5.1-5.2): each
// does its one job and returns what it did, the text the CLI prints and the --json record
// (docs/formats/schemas/sim_*.schema.json). `sim dataset` is dataset.hpp's.

#include <filesystem>
#include <string>

#include "proprio/core/json_io.hpp"
#include "proprio/core/provenance.hpp"
#include "proprio/sim/calibration.hpp"
#include "proprio/sim/recorder.hpp"
#include "proprio/sim/views.hpp"

namespace proprio::sim {

// NOLINTNEXTLINE(bugprone-exception-escape)
struct SimRun {
  std::string report;   ///< what the CLI prints, lines ending in '\n'
  core::Json document;  ///< the --json record
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
