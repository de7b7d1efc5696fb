#pragma once
// The library calls behind `proprio calib ...` (thesis 3.2-3.4; docs/formats/calib.md): each
// reads its files, does the one job, writes its outputs and returns what it did, the text the CLI
// prints and the record it writes for --json (docs/formats/schemas/calib_*.schema.json). Errors
// name the file, and the line of a point file, they came from.

#include <filesystem>
#include <string>
#include <vector>

#include "proprio/core/fields.hpp"
#include "proprio/core/json_io.hpp"
#include "proprio/core/provenance.hpp"
#include "proprio/geometry/backprojection.hpp"
#include "proprio/geometry/camera.hpp"
#include "proprio/geometry/dlt.hpp"
#include "proprio/geometry/stereo_check.hpp"
#include "proprio/geometry/triangulation.hpp"
#include "proprio/geometry/uncertainty_map.hpp"

namespace proprio::geometry {

/// "NAME: fx .. fy .. cx .. cy .. skew ..; centre (x, y, z)" and a newline.
std::string describe_camera(const std::string& name, const Camera& camera);

/// The records of the calib commands (their `document`, after the provenance). A record that
/// carries a library type (a DLT fit, a triangulation summary, an uncertainty map, a stereo
/// check) lists that type's described fields flat among its own.
struct CalibDltRecord {
  std::filesystem::path points_file;
  std::filesystem::path calib;  ///< the calibration written
  DltResult fit;
  Camera camera;  ///< as written (with the image size given)
  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.points_file, {"points_file", "The correspondences"});
    v(self.calib, {"calib", "The calibration written"});
    DltResult::describe(self.fit, v);
    v(self.camera, {"camera", "The camera"});
  }
};

struct CalibTriangulateRecord {
  std::filesystem::path points_file;
  std::filesystem::path out;
  bool distorted_input = false;
  BatchTriangulationSummary summary;
  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.points_file, {"points_file", "The pixel pairs"});
    v(self.out, {"out", "The points written"});
    v(self.distorted_input, {"distorted_input", "Whether the pixels were undistorted first"});
    BatchTriangulationSummary::describe(self.summary, v);
  }
};

/// An uncertainty map as `calib uncertainty` records it: the slice, ranges, grid and noise, and
/// the summary with its sigmas in the legend's unit (multiplied by `unit_scale`).
struct UncertaintyMapRecord {
  const UncertaintyMap* map = nullptr;
  double unit_scale = 1.0;
  std::string unit;

  struct Slice {
    std::string axis;
    double at = 0;
    template <class Self, class Visitor>
    static void describe(Self& self, Visitor& v) {
      v(self.axis, {"axis", "x, y or z: the axis normal to the slice"});
      v(self.at, {"at", "Its value there"});
    }
  };
  struct Summary {
    const UncertaintyMapSummary* s;
    double f;
    template <class Self, class Visitor>
    static void describe(Self& self, Visitor& v) {
      const UncertaintyMapSummary& s = *self.s;
      v(s.cells, {"cells", "Grid cells"});
      v(s.valid_cells, {"valid_cells", "Cells seen by both cameras"});
      v(s.behind_camera, {"behind_camera", "Cells behind either camera"});
      v(s.outside_image, {"outside_image", "Cells outside an image"});
      v(s.unobservable, {"unobservable", "Cells on the baseline"});
      v(s.min_sigma * self.f, {"min_sigma", "Least sigma, legend unit"});
      v(s.median_sigma * self.f, {"median_sigma", "Median sigma, legend unit"});
      v(s.max_sigma * self.f, {"max_sigma", "Largest sigma, legend unit"});
      v(core::vector_values(s.best_point), {"best_point", "The cell centre with min_sigma"});
    }
  };

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    static const char* const kAxes[3] = {"x", "y", "z"};
    const UncertaintyMapOptions& o = self.map->options;
    v(Slice{kAxes[o.slice_axis], o.slice_at}, {"slice", "The slice"});
    v(std::vector<double>{o.range_a(0), o.range_a(1)}, {"range_a", "First in-slice axis"});
    v(std::vector<double>{o.range_b(0), o.range_b(1)}, {"range_b", "Second in-slice axis"});
    v(std::vector<int>{o.cells_a, o.cells_b}, {"cells", "Grid cells per axis"});
    v(o.sigma_px, {"sigma_px", "Pixel noise std, px"});
    v(self.unit, {"unit", "The legend's unit"});
    v(self.unit_scale, {"unit_scale", "Legend units per world unit"});
    v(Summary{&self.map->summary, self.unit_scale}, {"summary", "The map's summary"});
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

struct CalibUncertaintyRecord {
  std::filesystem::path calib1;
  std::filesystem::path calib2;
  std::filesystem::path out;
  UncertaintyMapRecord map;
  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.calib1, {"calib1", "The first camera"});
    v(self.calib2, {"calib2", "The second camera"});
    v(self.out, {"out", "The image written"});
    UncertaintyMapRecord::describe(self.map, v);
  }
};

struct CalibStereoRecord {
  std::filesystem::path images;
  std::vector<int> board;  ///< inner corners: width, height
  double square_size = 1.0;
  bool refined = false;
  std::filesystem::path out;
  StereoCheckResult check;
  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.images, {"images", "The stereo sequence"});
    v(self.board, {"board", "Inner corners per row and per column"});
    v(self.square_size, {"square_size", "Side of a square"});
    v(self.refined, {"refined", "Whether triangulation was refined"});
    v(self.out, {"out", "The directory written"});
    StereoCheckResult::describe(self.check, v);
  }
};

/// What a calib command did, under the Summary convention (core::Summary): brief() is what the
/// CLI prints on stdout, `message` its first line.
// NOLINTNEXTLINE(bugprone-exception-escape)
struct CalibRun {
  std::string report;                 ///< brief()'s text: lines, each ending in '\n'
  std::vector<std::string> warnings;  ///< what it prints on stderr (the run still succeeded)
  core::Json document;                ///< the --json record
  std::string message;                ///< one line: brief()'s first
  [[nodiscard]] std::string brief() const { return report; }
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
