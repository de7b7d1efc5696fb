#pragma once
// The library calls behind `proprio calib ...` (thesis 3.2-3.4; docs/formats/calib.md): each
// reads its files, does the one job, writes its outputs and returns what it did, the text the CLI
// prints and the record it writes for --json (docs/formats/schemas/calib_*.schema.json). Errors
// name the file, and the line of a point file, they came from.

#include <filesystem>
#include <string>
#include <vector>

#include "proprio/core/json_io.hpp"
#include "proprio/core/provenance.hpp"
#include "proprio/geometry/backprojection.hpp"
#include "proprio/geometry/camera.hpp"
#include "proprio/geometry/dlt.hpp"
#include "proprio/geometry/stereo_check.hpp"
#include "proprio/geometry/uncertainty_map.hpp"

namespace proprio::geometry {

/// "NAME: fx .. fy .. cx .. cy .. skew ..; centre (x, y, z)" and a newline.
std::string describe_camera(const std::string& name, const Camera& camera);

// NOLINTNEXTLINE(bugprone-exception-escape)
struct CalibRun {
  std::string report;                 ///< what the CLI prints on stdout
  std::vector<std::string> warnings;  ///< what it prints on stderr (the run still succeeded)
  core::Json document;                ///< the --json record
};

struct CalibDltOptions {
  std::filesystem::path points;  ///< CSV X,Y,Z,u,v (world units, pixels; required)
  std::filesystem::path out;     ///< calib.yml to write (required)
  int width = 0;                 ///< image size recorded in calib.yml; both or neither
  int height = 0;
  void validate() const;
};
/// DLT (eqs 3.7-3.11) from >= 6 non-coplanar pairs; warns when points lie behind the camera.
CalibRun run_calib_dlt(const CalibDltOptions& options, const core::Provenance& provenance);

struct CalibTriangulateOptions {
  std::filesystem::path calib1, calib2;  ///< the two cameras (required)
  std::filesystem::path points;          ///< CSV u1,v1,u2,v2 (required)
  std::filesystem::path out;             ///< CSV X,Y,Z to write (required)
  bool refine = false;                   ///< Levenberg-Marquardt on the reprojection errors
  bool distorted = false;                ///< the pixels are as measured: undistort first
  void validate() const;
};
/// Triangulates every pixel pair (3.4.1); a pair that cannot be is an Error naming its line.
CalibRun run_calib_triangulate(const CalibTriangulateOptions& options,
                               const core::Provenance& provenance);

struct CalibBackprojectOptions {
  std::filesystem::path calib;   ///< the camera (required)
  std::filesystem::path points;  ///< CSV u,v (required)
  Plane plane;                   ///< n.X = kappa, world frame (default: the table z = 0)
  std::filesystem::path out;     ///< CSV X,Y,Z to write (required)
  bool distorted = false;
  void validate() const;
};
/// Back-projects every pixel onto the plane (eqs 3.13-3.17); errors name the pixel's line.
CalibRun run_calib_backproject(const CalibBackprojectOptions& options,
                               const core::Provenance& provenance);

struct CalibUncertaintyOptions {
  std::filesystem::path calib1, calib2;  ///< the two cameras (required)
  std::filesystem::path out;             ///< heat-map PNG to write (required, .png)
  UncertaintyMapOptions map;
  UncertaintyRenderOptions render;
  void validate() const;
};
/// The visual-uncertainty map of a workspace slice (3.4.2), rendered to PNG.
CalibRun run_calib_uncertainty(const CalibUncertaintyOptions& options,
                               const core::Provenance& provenance);

struct CalibStereoOptions {
  StereoCheckOptions check;   ///< images (empty: opencv-doc's), board, square, refinement
  std::filesystem::path out;  ///< folder to write left.yml, right.yml, corners.csv (required)
  void validate() const;
};
/// Calibrates a stereo pair from chessboards and checks proprio's triangulation against it.
CalibRun run_calib_stereo(const CalibStereoOptions& options, const core::Provenance& provenance);

}  // namespace proprio::geometry
