// proprio calib ...: camera geometry (thesis 3.2-3.4; docs/formats/calib.md).
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <opencv2/imgcodecs.hpp>

#include "cli.hpp"
#include "proprio/core/error.hpp"
#include "proprio/core/files.hpp"
#include "proprio/geometry/backprojection.hpp"
#include "proprio/geometry/dlt.hpp"
#include "proprio/geometry/json.hpp"
#include "proprio/geometry/point_files.hpp"
#include "proprio/geometry/stereo_check.hpp"
#include "proprio/geometry/triangulation.hpp"
#include "proprio/geometry/uncertainty_map.hpp"

namespace proprio::app {
namespace {
namespace fs = std::filesystem;
using geometry::Camera;

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

// Runs f; an Error from the library gets the name of the file it came from.
template <typename F>
auto naming(const fs::path& file, F&& f) {
  try {
    return f();
  } catch (const Error& e) {
    throw Error::in_file(file, e.what());
  }
}

void print_camera(const char* name, const Camera& c) {
  const Eigen::Vector3d C = c.center();
  std::printf("%s: fx %.2f fy %.2f cx %.2f cy %.2f skew %.3g; centre (%.5g, %.5g, %.5g)\n", name,
              c.K(0, 0), c.K(1, 1), c.K(0, 2), c.K(1, 2), c.K(0, 1), C.x() + 0.0, C.y() + 0.0,
              C.z() + 0.0);  // + 0.0 prints -0 as 0
}

// ---- dlt ---------------------------------------------------------------------------------------

struct DltArgs {
  std::string points, out, json;
  int width = 0, height = 0;
};

void run_dlt(const DltArgs& a, const Invocation& inv) {
  if ((a.width > 0) != (a.height > 0))
    throw Error("dlt: give both --width and --height, or neither");
  const auto pts = geometry::read_correspondences_csv(a.points);
  const auto r = naming(a.points, [&] { return geometry::calibrate_dlt(pts.world, pts.pixels); });
  Camera cam = r.camera;
  cam.width = a.width;
  cam.height = a.height;
  geometry::write_calib(a.out, cam, inv.provenance());
  std::printf("DLT on %d points: reprojection RMS %.4f px, max %.4f px\n", r.summary.num_points,
              r.rms_px, r.summary.max_residual_px);
  print_camera("camera", cam);
  std::printf("wrote %s\n", a.out.c_str());
  if (r.summary.points_behind > 0) {
    std::fprintf(stderr, "proprio: warning: %s: %d points lie behind the estimated camera\n",
                 a.points.c_str(), r.summary.points_behind);
  }
  core::Json doc = core::result_document("proprio.calib.dlt", 1, inv.provenance());
  doc["points_file"] = a.points;
  doc["calib"] = a.out;
  doc.update(geometry::to_json(r));
  doc["camera"] = geometry::to_json(cam);
  write_json_result(a.json, doc);
}

// ---- triangulate -------------------------------------------------------------------------------

struct TriangulateArgs {
  std::string calib1, calib2, points, out, json;
  bool refine = false, distorted = false;
};

void run_triangulate(const TriangulateArgs& a, const Invocation& inv) {
  const Camera c1 = geometry::read_calib(a.calib1);
  const Camera c2 = geometry::read_calib(a.calib2);
  auto px = geometry::read_pixel_pairs_csv(a.points);
  if (a.distorted) {
    px.x1 = geometry::undistort_pixels(c1, px.x1);
    px.x2 = geometry::undistort_pixels(c2, px.x2);
  }
  geometry::TriangulationOptions o;
  o.refine = a.refine;
  const geometry::Matrix34d P1 = c1.P(), P2 = c2.P();
  geometry::BatchTriangulation all;
  try {
    all = geometry::triangulate(P1, P2, px.x1, px.x2, o);
  } catch (const Error&) {
    // Find the row again so that the message names its line.
    for (size_t i = 0; i < px.x1.size(); ++i) {
      try {
        geometry::triangulate(P1, P2, px.x1[i], px.x2[i], o);
      } catch (const Error& e) {
        throw Error::at_line(a.points, px.lines[i], e.what());
      }
    }
    throw;
  }
  geometry::write_points_csv(a.out, all.points);
  std::printf("%s\nwrote %s\n", all.summary.brief().c_str(), a.out.c_str());
  core::Json doc = core::result_document("proprio.calib.triangulate", 1, inv.provenance());
  doc["points_file"] = a.points;
  doc["out"] = a.out;
  doc["distorted_input"] = a.distorted;
  doc.update(geometry::to_json(all.summary));
  write_json_result(a.json, doc);
}

// ---- backproject -------------------------------------------------------------------------------

struct BackprojectArgs {
  std::string calib, points, plane, out, json;
  bool distorted = false;
};

void run_backproject(const BackprojectArgs& a, const Invocation& inv) {
  const auto v = parse_numbers(a.plane, 4, "--plane", "nx,ny,nz,kappa");
  geometry::Plane plane{{v[0], v[1], v[2]}, v[3]};
  naming("--plane", [&] {
    plane.validate();
    return 0;
  });
  const Camera cam = geometry::read_calib(a.calib);
  auto px = geometry::read_pixels_csv(a.points);
  if (a.distorted) px.pixels = geometry::undistort_pixels(cam, px.pixels);
  const geometry::Matrix34d P = cam.P();
  std::vector<Eigen::Vector3d> points;
  double min_cos = 1.0;
  for (size_t i = 0; i < px.pixels.size(); ++i) {
    try {
      const auto b = geometry::back_project_to_plane(P, px.pixels[i], plane);
      points.push_back(b.X);
      min_cos = std::min(min_cos, b.incidence_cos);
    } catch (const Error& e) {
      throw Error::at_line(a.points, px.lines[i], e.what());
    }
  }
  geometry::write_points_csv(a.out, points);
  std::printf(
      "back-projected %zu pixels onto %g x + %g y + %g z = %g (most grazing ray: cos %.3f)\n"
      "wrote %s\n",
      points.size(), v[0], v[1], v[2], v[3], min_cos, a.out.c_str());
  core::Json doc = core::result_document("proprio.calib.backproject", 1, inv.provenance());
  doc["points_file"] = a.points;
  doc["out"] = a.out;
  doc["plane"] = {{"n", {v[0], v[1], v[2]}}, {"kappa", v[3]}};
  doc["points"] = points.size();
  doc["distorted_input"] = a.distorted;
  doc["min_incidence_cos"] = min_cos;
  write_json_result(a.json, doc);
}

// ---- uncertainty -------------------------------------------------------------------------------

struct UncertaintyArgs {
  std::string calib1, calib2, out, json;
  std::optional<double> x, y, z;
  std::string x_range, y_range, z_range;
  double sigma_px = 1.0;
  int cells = 200;
  geometry::UncertaintyRenderOptions render;
};

void run_uncertainty(const UncertaintyArgs& a, const Invocation& inv) {
  if (fs::path(a.out).extension() != ".png")
    throw Error("uncertainty: --out must name a .png file");
  const int slices = (a.x ? 1 : 0) + (a.y ? 1 : 0) + (a.z ? 1 : 0);
  if (slices > 1) throw Error("uncertainty: give one of --x, --y, --z (the slice)");
  geometry::UncertaintyMapOptions o;
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
  o.sigma_px = a.sigma_px;
  o.cells_a = o.cells_b = a.cells;
  const Camera c1 = geometry::read_calib(a.calib1);
  const Camera c2 = geometry::read_calib(a.calib2);
  const auto map = geometry::compute_uncertainty_map(c1, c2, o);
  const cv::Mat image = geometry::render_uncertainty_map(map, a.render);
  std::vector<uchar> png;
  cv::imencode(".png", image, png);
  core::write_file_atomic(a.out,
                          std::string_view(reinterpret_cast<const char*>(png.data()), png.size()));
  const auto& s = map.summary;
  const double f = a.render.unit_scale;
  std::printf(
      "visual uncertainty (sigma %.3g px): %d of %d cells seen by both cameras\n"
      "max std of the triangulated point: min %.4g %s at (%.4g, %.4g, %.4g), median %.4g %s, "
      "max %.4g %s\nwrote %s\n",
      o.sigma_px, s.valid_cells, s.cells, s.min_sigma * f, a.render.unit.c_str(), s.best_point.x(),
      s.best_point.y(), s.best_point.z(), s.median_sigma * f, a.render.unit.c_str(),
      s.max_sigma * f, a.render.unit.c_str(), a.out.c_str());
  core::Json doc = core::result_document("proprio.calib.uncertainty", 1, inv.provenance());
  doc["calib1"] = a.calib1;
  doc["calib2"] = a.calib2;
  doc["out"] = a.out;
  doc.update(geometry::to_json(map, f, a.render.unit));
  write_json_result(a.json, doc);
}

// ---- stereo ------------------------------------------------------------------------------------

struct StereoArgs {
  std::string images, board = "9x6", out, json;
  double square = 1.0;
  bool refine = false;
};

void run_stereo(const StereoArgs& a, const Invocation& inv) {
  geometry::StereoCheckOptions o;
  o.images_dir = a.images.empty() ? geometry::default_stereo_images_dir() : fs::path(a.images);
  o.board = parse_board(a.board);
  o.square_size = a.square;
  o.refine_triangulation = a.refine;
  if (fs::exists(a.out) && !fs::is_directory(a.out)) {
    throw Error::in_file(a.out, "exists and is not a directory");
  }
  const auto r = geometry::run_stereo_check(o);
  geometry::write_calib(fs::path(a.out) / "left.yml", r.left, inv.provenance());
  geometry::write_calib(fs::path(a.out) / "right.yml", r.right, inv.provenance());
  geometry::write_stereo_corners_csv(fs::path(a.out) / "corners.csv", r.corners);
  std::printf("stereo check on %s (board %dx%d, square %g)\n%s\n", o.images_dir.c_str(),
              o.board.width, o.board.height, o.square_size, r.summary.brief().c_str());
  print_camera("left camera", r.left);
  print_camera("right camera", r.right);
  for (const auto& p : r.pairs) {
    std::printf("  pair %s: board %s/%s, %d corners, planarity %.4f, neighbours %.5f squares\n",
                p.id.c_str(), p.found_left ? "found" : "missed", p.found_right ? "found" : "missed",
                p.corners, p.planarity_rms, p.neighbour_mean);
  }
  std::printf("wrote %s/{left.yml,right.yml,corners.csv}\n", a.out.c_str());
  core::Json doc = core::result_document("proprio.calib.stereo", 1, inv.provenance());
  doc["images"] = o.images_dir.string();
  doc["board"] = {o.board.width, o.board.height};
  doc["square_size"] = o.square_size;
  doc["refined"] = o.refine_triangulation;
  doc["out"] = a.out;
  doc.update(geometry::to_json(r));
  write_json_result(a.json, doc);
}

}  // namespace

void register_calib_commands(CLI::App& root, const Invocation& inv) {
  auto* calib = root.add_subcommand("calib", "Camera calibration and geometry (thesis 3.2-3.4)");
  calib->require_subcommand(1);
  constexpr const char* kJson = "Also write the figures as JSON to this file";

  auto dlt_args = std::make_shared<DltArgs>();
  auto* dlt = calib->add_subcommand(
      "dlt", "Estimate a camera's P from >= 6 non-coplanar 3D-2D pairs (DLT, eqs 3.7-3.11)");
  dlt->add_option("--points", dlt_args->points, "CSV with header X,Y,Z,u,v (world units, pixels)")
      ->required();
  dlt->add_option("--out", dlt_args->out, "calib.yml to write")->required();
  dlt->add_option("--width", dlt_args->width, "Image width to record in calib.yml, pixels")
      ->check(CLI::PositiveNumber);
  dlt->add_option("--height", dlt_args->height, "Image height to record in calib.yml, pixels")
      ->check(CLI::PositiveNumber);
  dlt->add_option("--json", dlt_args->json, kJson);
  dlt->callback([dlt_args, &inv] { run_dlt(*dlt_args, inv); });

  auto tri_args = std::make_shared<TriangulateArgs>();
  auto* tri = calib->add_subcommand(
      "triangulate", "Triangulate pixel pairs seen by two calibrated cameras (3.4.1)");
  tri->add_option("--calib1", tri_args->calib1, "calib.yml of camera 1")->required();
  tri->add_option("--calib2", tri_args->calib2, "calib.yml of camera 2")->required();
  tri->add_option("--points", tri_args->points,
                  "CSV with header u1,v1,u2,v2 (undistorted pixels unless --distorted)")
      ->required();
  tri->add_option("--out", tri_args->out, "CSV to write, header X,Y,Z (one row per input row)")
      ->required();
  tri->add_flag("--refine", tri_args->refine,
                "Refine each point by Levenberg-Marquardt on the reprojection errors");
  tri->add_flag("--distorted", tri_args->distorted,
                "The pixels are as measured: remove the lens distortion of the calibrations first");
  tri->add_option("--json", tri_args->json, kJson);
  tri->callback([tri_args, &inv] { run_triangulate(*tri_args, inv); });

  auto bp_args = std::make_shared<BackprojectArgs>();
  auto* bp = calib->add_subcommand(
      "backproject", "Back-project pixels of one camera onto a known plane (eqs 3.13-3.17)");
  bp->add_option("--calib", bp_args->calib, "calib.yml of the camera")->required();
  bp->add_option("--points", bp_args->points,
                 "CSV with header u,v (undistorted pixels unless --distorted)")
      ->required();
  bp->add_option("--plane", bp_args->plane,
                 "The plane n.X = kappa as nx,ny,nz,kappa (world frame; e.g. 0,0,1,0 the table)")
      ->required();
  bp->add_option("--out", bp_args->out, "CSV to write, header X,Y,Z")->required();
  bp->add_flag("--distorted", bp_args->distorted,
               "The pixels are as measured: remove the lens distortion first");
  bp->add_option("--json", bp_args->json, kJson);
  bp->callback([bp_args, &inv] { run_backproject(*bp_args, inv); });

  auto un_args = std::make_shared<UncertaintyArgs>();
  auto* un = calib->add_subcommand(
      "uncertainty",
      "Map how pixel noise spreads into triangulated points over a workspace slice (3.4.2)");
  un->add_option("--calib1", un_args->calib1, "calib.yml of camera 1")->required();
  un->add_option("--calib2", un_args->calib2, "calib.yml of camera 2")->required();
  un->add_option("--out", un_args->out, "Heat-map PNG to write")->required();
  un->add_option("--x", un_args->x, "Slice at this x (world units)");
  un->add_option("--y", un_args->y, "Slice at this y (world units)");
  un->add_option("--z", un_args->z, "Slice at this z (world units; the default slice is z = 0)");
  un->add_option("--x-range", un_args->x_range, "MIN,MAX of x over the slice (default -1,1)");
  un->add_option("--y-range", un_args->y_range, "MIN,MAX of y over the slice (default -1,1)");
  un->add_option("--z-range", un_args->z_range, "MIN,MAX of z over the slice (default -1,1)");
  un->add_option("--sigma-px", un_args->sigma_px, "Pixel noise std per axis, both cameras")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  un->add_option("--cells", un_args->cells, "Grid cells per axis")
      ->check(CLI::Range(2, 4096))
      ->capture_default_str();
  un->add_option("--unit", un_args->render.unit, "Unit of the uncertainty in the legend")
      ->capture_default_str();
  un->add_option("--unit-scale", un_args->render.unit_scale,
                 "Legend units per world unit (1000: metres to mm)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  un->add_option("--world-unit", un_args->render.world_unit, "Unit of the axes")
      ->capture_default_str();
  un->add_option("--json", un_args->json, kJson);
  un->callback([un_args, &inv] { run_uncertainty(*un_args, inv); });

  auto st_args = std::make_shared<StereoArgs>();
  auto* st = calib->add_subcommand(
      "stereo",
      "Calibrate a stereo pair from chessboard images and check our triangulation against it");
  st->add_option("--images", st_args->images,
                 "Folder with leftNN / rightNN images (default: opencv-doc's samples, " +
                     geometry::default_stereo_images_dir().string() + ")");
  st->add_option("--board", st_args->board, "Inner corners COLSxROWS")->capture_default_str();
  st->add_option("--square", st_args->square, "Side of a square, world units")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  st->add_flag("--refine", st_args->refine,
               "Refine the triangulated corners (Levenberg-Marquardt)");
  st->add_option("--out", st_args->out, "Folder to write left.yml, right.yml, corners.csv into")
      ->required();
  st->add_option("--json", st_args->json, kJson);
  st->callback([st_args, &inv] { run_stereo(*st_args, inv); });
}

}  // namespace proprio::app
