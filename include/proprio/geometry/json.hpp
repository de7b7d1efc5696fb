#pragma once
// JSON forms of the geometry results, as the calib verbs write them (schemas in
// docs/formats/schemas/calib_*.schema.json). Matrices are arrays of rows.

#include <Eigen/Core>

#include "proprio/core/json_io.hpp"
#include "proprio/geometry/camera.hpp"
#include "proprio/geometry/dlt.hpp"
#include "proprio/geometry/stereo_check.hpp"
#include "proprio/geometry/triangulation.hpp"
#include "proprio/geometry/uncertainty_map.hpp"

namespace proprio::geometry {

core::Json matrix_to_json(const Eigen::MatrixXd& m);

/// K, dist, R, t, P, centre and image size.
core::Json to_json(const Camera& camera);
/// rms_px, points, max_residual_px, residuals_px, P, camera, summary.
core::Json to_json(const DltResult& result);
core::Json to_json(const BatchTriangulationSummary& summary);
/// Slice, ranges, grid, noise and the summary, the sigmas multiplied by `unit_scale`.
core::Json to_json(const UncertaintyMap& map, double unit_scale, const std::string& unit);
/// Summary figures, cameras and per-pair reports (not the corners).
core::Json to_json(const StereoCheckResult& result);

}  // namespace proprio::geometry
