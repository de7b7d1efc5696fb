#pragma once
// The library calls behind `proprio calib ...` (thesis 3.2-3.4; docs/formats/calib.md): each
// reads its files, does the one job, writes its outputs and returns what it did, the text the CLI
// prints and the record it writes for --json (docs/formats/schemas/calib_*.schema.json). Errors
// name the file, and the line of a point file, they came from.

#include <filesystem>
#include <string>
#include <vector>

#include "proprio/core/json_io.hpp"
#include "proprio/core/json_members.hpp"
#include "proprio/core/provenance.hpp"
#include "proprio/geometry/backprojection.hpp"
#include "proprio/geometry/camera.hpp"
#include "proprio/geometry/dlt.hpp"
#include "proprio/geometry/stereo_check.hpp"
#include "proprio/geometry/uncertainty_map.hpp"

namespace proprio::geometry {

/// "NAME: fx .. fy .. cx .. cy .. skew ..; centre (x, y, z)" and a newline.
std::string describe_camera(const std::string& name, const Camera& camera);

/// The records of the calib commands (their `document`, after the provenance). A record that
/// carries a library type's JSON (to_json of a DLT fit, a triangulation summary, an uncertainty
/// map, a stereo check) takes over its keys.
// NOLINTNEXTLINE(bugprone-exception-escape)
struct CalibDltRecord {
  std::filesystem::path points_file;
  std::filesystem::path calib;  ///< the calibration written
  core::Json fit;               ///< to_json(DltResult)
  core::Json camera;            ///< to_json(Camera)
  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.points_file, {"points_file", "The correspondences"});
    v(self.calib, {"calib", "The calibration written"});
    core::describe_json_members(self.fit, v);
    v(self.camera, {"camera", "The camera"});
  }
};

// NOLINTNEXTLINE(bugprone-exception-escape)
struct CalibTriangulateRecord {
  std::filesystem::path points_file;
  std::filesystem::path out;
  bool distorted_input = false;
  core::Json summary;  ///< to_json(TriangulationSummary)
  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.points_file, {"points_file", "The pixel pairs"});
    v(self.out, {"out", "The points written"});
    v(self.distorted_input, {"distorted_input", "Whether the pixels were undistorted first"});
    core::describe_json_members(self.summary, v);
  }
};

/// A plane n . X = kappa.
struct PlaneRecord {
  std::vector<double> n;
  double kappa = 0;
  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.n, {"n", "Its normal"});
    v(self.kappa, {"kappa", "Its offset, n . X = kappa"});
  }
};

struct CalibBackprojectRecord {
  std::filesystem::path points_file;
  std::filesystem::path out;
  PlaneRecord plane;
  std::size_t points = 0;
  bool distorted_input = false;
  double min_incidence_cos = 1.0;  ///< of the most grazing ray
  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.points_file, {"points_file", "The pixels"});
    v(self.out, {"out", "The points written"});
    v(self.plane, {"plane", "The plane"});
    v(self.points, {"points", "Points back-projected"});
    v(self.distorted_input, {"distorted_input", "Whether the pixels were undistorted first"});
    v(self.min_incidence_cos, {"min_incidence_cos", "Cosine of the most grazing ray"});
  }
};

// NOLINTNEXTLINE(bugprone-exception-escape)
struct CalibUncertaintyRecord {
  std::filesystem::path calib1;
  std::filesystem::path calib2;
  std::filesystem::path out;
  core::Json map;  ///< to_json(UncertaintyMap, ...)
  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.calib1, {"calib1", "The first camera"});
    v(self.calib2, {"calib2", "The second camera"});
    v(self.out, {"out", "The image written"});
    core::describe_json_members(self.map, v);
  }
};

// NOLINTNEXTLINE(bugprone-exception-escape)
struct CalibStereoRecord {
  std::filesystem::path images;
  std::vector<int> board;  ///< inner corners: width, height
  double square_size = 1.0;
  bool refined = false;
  std::filesystem::path out;
  core::Json check;  ///< to_json(StereoCheckResult)
  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.images, {"images", "The stereo sequence"});
    v(self.board, {"board", "Inner corners per row and per column"});
    v(self.square_size, {"square_size", "Side of a square"});
    v(self.refined, {"refined", "Whether triangulation was refined"});
    v(self.out, {"out", "The directory written"});
    core::describe_json_members(self.check, v);
  }
};

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
