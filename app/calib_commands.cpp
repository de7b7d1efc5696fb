// proprio calib ...: camera geometry (thesis 3.2-3.4; docs/formats/calib.md).
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>

#include "cli.hpp"
#include "proprio/core/error.hpp"
#include "proprio/core/files.hpp"
#include "proprio/geometry/calib_runs.hpp"

namespace proprio::app {
namespace {
namespace fs = std::filesystem;

// "a,b,..." -> exactly n finite numbers; `what` names the option in the error.
std::vector<double> parse_numbers(const std::string& text, size_t n, const std::string& what,
                                  const std::string& form) {
  std::vector<double> out;
  bool ok = true;
  size_t start = 0;
  while (ok) {
    const size_t comma = std::min(text.find(',', start), text.size());
    double v = 0.0;
    const auto [ptr, ec] = std::from_chars(text.data() + start, text.data() + comma, v);
    ok = ec == std::errc() && ptr == text.data() + comma && std::isfinite(v);
    out.push_back(v);
    if (comma == text.size()) break;
    start = comma + 1;
  }
  if (!ok || out.size() != n) {
    std::string m = what;
    m += ": expected ";
    m += form;
    m += " (finite numbers), got '";
    m += text;
    m += "'";
    throw Error(m);
  }
  return out;
}

// "9x6" -> (9, 6).
cv::Size parse_board(const std::string& text) {
  int w = 0, h = 0;
  const char* end = text.data() + text.size();
  const auto r1 = std::from_chars(text.data(), end, w);
  const bool ok = r1.ec == std::errc() && r1.ptr != end && *r1.ptr == 'x' &&
                  std::from_chars(r1.ptr + 1, end, h).ptr == end && w > 0 && h > 0;
  if (!ok) {
    std::string m = "--board: expected COLSxROWS such as 9x6, got '";
    m += text;
    m += "'";
    throw Error(m);
  }
  return {w, h};
}

Eigen::Vector2d parse_range(const std::string& text, const std::string& what) {
  const auto v = parse_numbers(text, 2, what, "MIN,MAX");
  if (!(v[0] < v[1])) throw Error(what + ": MIN must be below MAX");
  return {v[0], v[1]};
}

void print(const geometry::CalibRun& r, const JsonFlag& json) {
  std::fputs(r.brief().c_str(), stdout);
  for (const auto& w : r.warnings) std::fprintf(stderr, "proprio: warning: %s\n", w.c_str());
  json.write(r.document);
}

struct DltArgs {
  geometry::CalibDltOptions options;
  JsonFlag json;
};

struct TriangulateArgs {
  geometry::CalibTriangulateOptions options;
  JsonFlag json;
};

struct BackprojectArgs {
  geometry::CalibBackprojectOptions options;
  std::string plane;
  JsonFlag json;
};

struct UncertaintyArgs {
  geometry::CalibUncertaintyOptions options;
  std::optional<double> x, y, z;
  std::string x_range, y_range, z_range;
  JsonFlag json;
};

// The slice and its ranges from --x/--y/--z and --x-range/--y-range/--z-range.
void set_slice(UncertaintyArgs& a) {
  const int slices = (a.x ? 1 : 0) + (a.y ? 1 : 0) + (a.z ? 1 : 0);
  if (slices > 1) throw Error("uncertainty: give one of --x, --y, --z (the slice)");
  geometry::UncertaintyMapOptions& o = a.options.map;
  o.slice_axis = a.x ? 0 : a.y ? 1 : 2;
  o.slice_at = a.x ? *a.x : a.y ? *a.y : a.z.value_or(0.0);
  const std::string* ranges[3] = {&a.x_range, &a.y_range, &a.z_range};
  const char* names[3] = {"--x-range", "--y-range", "--z-range"};
  if (!ranges[o.slice_axis]->empty()) {
    throw Error(std::string("uncertainty: ") + names[o.slice_axis] +
                " runs across the slice; give the ranges of the other two axes");
  }
  int k = 0;
  for (int axis = 0; axis < 3; ++axis) {
    if (axis == o.slice_axis) continue;
    Eigen::Vector2d& r = k++ == 0 ? o.range_a : o.range_b;
    if (!ranges[axis]->empty()) r = parse_range(*ranges[axis], names[axis]);
  }
}

struct StereoArgs {
  geometry::CalibStereoOptions options;
  std::string images, board = "9x6";
  JsonFlag json;
};

}  // namespace

void register_calib_commands(CLI::App& root, const Invocation& inv) {
  auto* calib = root.add_subcommand("calib", "Camera calibration and geometry (thesis 3.2-3.4)");
  calib->require_subcommand(1);

  auto dlt_args = std::make_shared<DltArgs>();
  auto* dlt = calib->add_subcommand(
      "dlt", "Estimate a camera's P from >= 6 non-coplanar 3D-2D pairs (DLT, eqs 3.7-3.11)");
  dlt->add_option("--points", dlt_args->options.points,
                  "CSV with header X,Y,Z,u,v (world units, pixels)")
      ->required();
  dlt->add_option("--out", dlt_args->options.out, "calib.yml to write")->required();
  dlt->add_option("--width", dlt_args->options.width, "Image width to record in calib.yml, pixels")
      ->check(CLI::PositiveNumber);
  dlt->add_option("--height", dlt_args->options.height,
                  "Image height to record in calib.yml, pixels")
      ->check(CLI::PositiveNumber);
  dlt_args->json.add_to(dlt, "the figures");
  dlt->callback([dlt_args, &inv] {
    const auto& o = dlt_args->options;
    dlt_args->json.refuse({o.out, o.points});
    print(geometry::run_calib_dlt(dlt_args->options, inv.provenance()), dlt_args->json);
  });

  auto tri_args = std::make_shared<TriangulateArgs>();
  auto* tri = calib->add_subcommand(
      "triangulate", "Triangulate pixel pairs seen by two calibrated cameras (3.4.1)");
  tri->add_option("--calib1", tri_args->options.calib1, "calib.yml of camera 1")->required();
  tri->add_option("--calib2", tri_args->options.calib2, "calib.yml of camera 2")->required();
  tri->add_option("--points", tri_args->options.points,
                  "CSV with header u1,v1,u2,v2 (undistorted pixels unless --distorted)")
      ->required();
  tri->add_option("--out", tri_args->options.out,
                  "CSV to write, header X,Y,Z (one row per input row)")
      ->required();
  tri->add_flag("--refine", tri_args->options.refine,
                "Refine each point by Levenberg-Marquardt on the reprojection errors");
  tri->add_flag("--distorted", tri_args->options.distorted,
                "The pixels are as measured: remove the lens distortion of the calibrations first");
  tri_args->json.add_to(tri, "the figures");
  tri->callback([tri_args, &inv] {
    const auto& o = tri_args->options;
    tri_args->json.refuse({o.out, o.calib1, o.calib2, o.points});
    print(geometry::run_calib_triangulate(tri_args->options, inv.provenance()), tri_args->json);
  });

  auto bp_args = std::make_shared<BackprojectArgs>();
  auto* bp = calib->add_subcommand(
      "backproject", "Back-project pixels of one camera onto a known plane (eqs 3.13-3.17)");
  bp->add_option("--calib", bp_args->options.calib, "calib.yml of the camera")->required();
  bp->add_option("--points", bp_args->options.points,
                 "CSV with header u,v (undistorted pixels unless --distorted)")
      ->required();
  bp->add_option("--plane", bp_args->plane,
                 "The plane n.X = kappa as nx,ny,nz,kappa (world frame; e.g. 0,0,1,0 the table)")
      ->required();
  bp->add_option("--out", bp_args->options.out, "CSV to write, header X,Y,Z")->required();
  bp->add_flag("--distorted", bp_args->options.distorted,
               "The pixels are as measured: remove the lens distortion first");
  bp_args->json.add_to(bp, "the figures");
  bp->callback([bp_args, &inv] {
    const auto& o = bp_args->options;
    bp_args->json.refuse({o.out, o.calib, o.points});
    const auto v = parse_numbers(bp_args->plane, 4, "--plane", "nx,ny,nz,kappa");
    bp_args->options.plane = geometry::Plane{{v[0], v[1], v[2]}, v[3]};
    print(geometry::run_calib_backproject(bp_args->options, inv.provenance()), bp_args->json);
  });

  auto un_args = std::make_shared<UncertaintyArgs>();
  auto* un = calib->add_subcommand(
      "uncertainty",
      "Map how pixel noise spreads into triangulated points over a workspace slice (3.4.2)");
  un->add_option("--calib1", un_args->options.calib1, "calib.yml of camera 1")->required();
  un->add_option("--calib2", un_args->options.calib2, "calib.yml of camera 2")->required();
  un->add_option("--out", un_args->options.out, "Heat-map PNG to write")->required();
  un->add_option("--x", un_args->x, "Slice at this x (world units)");
  un->add_option("--y", un_args->y, "Slice at this y (world units)");
  un->add_option("--z", un_args->z, "Slice at this z (world units; the default slice is z = 0)");
  un->add_option("--x-range", un_args->x_range, "MIN,MAX of x over the slice (default -1,1)");
  un->add_option("--y-range", un_args->y_range, "MIN,MAX of y over the slice (default -1,1)");
  un->add_option("--z-range", un_args->z_range, "MIN,MAX of z over the slice (default -1,1)");
  un->add_option("--sigma-px", un_args->options.map.sigma_px,
                 "Pixel noise std per axis, both cameras")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  un->add_option("--cells", un_args->options.map.cells_a, "Grid cells per axis")
      ->check(CLI::Range(2, 4096))
      ->capture_default_str();
  un->add_option("--unit", un_args->options.render.unit, "Unit of the uncertainty in the legend")
      ->capture_default_str();
  un->add_option("--unit-scale", un_args->options.render.unit_scale,
                 "Legend units per world unit (1000: metres to mm)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  un->add_option("--world-unit", un_args->options.render.world_unit, "Unit of the axes")
      ->capture_default_str();
  un_args->json.add_to(un, "the figures");
  un->callback([un_args, &inv] {
    const auto& o = un_args->options;
    un_args->json.refuse({o.out, o.calib1, o.calib2});
    set_slice(*un_args);
    un_args->options.map.cells_b = un_args->options.map.cells_a;
    print(geometry::run_calib_uncertainty(un_args->options, inv.provenance()), un_args->json);
  });

  auto st_args = std::make_shared<StereoArgs>();
  auto* st = calib->add_subcommand(
      "stereo",
      "Calibrate a stereo pair from chessboard images and check our triangulation against it");
  st->add_option("--images", st_args->images,
                 "Folder with leftNN / rightNN images (default: opencv-doc's samples, " +
                     geometry::default_stereo_images_dir().string() + ")");
  st->add_option("--board", st_args->board, "Inner corners COLSxROWS")->capture_default_str();
  st->add_option("--square", st_args->options.check.square_size, "Side of a square, world units")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  st->add_flag("--refine", st_args->options.check.refine_triangulation,
               "Refine the triangulated corners (Levenberg-Marquardt)");
  st->add_option("--out", st_args->options.out,
                 "Folder to write left.yml, right.yml, corners.csv into")
      ->required();
  st_args->json.add_to(st, "the figures");
  st->callback([st_args, &inv] {
    geometry::CalibStereoOptions& o = st_args->options;
    o.check.images_dir = st_args->images;
    o.check.board = parse_board(st_args->board);
    st_args->json.refuse({o.out, o.check.images_dir});
    print(geometry::run_calib_stereo(o, inv.provenance()), st_args->json);
  });
}

}  // namespace proprio::app
