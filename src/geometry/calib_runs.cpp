#include "proprio/geometry/calib_runs.hpp"

#include <algorithm>
#include <cstdio>
#include <opencv2/imgcodecs.hpp>

#include "proprio/core/error.hpp"
#include "proprio/core/files.hpp"
#include "proprio/core/text.hpp"
#include "proprio/geometry/point_files.hpp"
#include "proprio/geometry/triangulation.hpp"

namespace proprio::geometry {
namespace {
namespace fs = std::filesystem;

// Runs f; an Error from the library gets the name of the file it came from.
template <typename F>
auto naming(const fs::path& file, F&& f) {
  try {
    return f();
  } catch (const Error& e) {
    throw Error::in_file(file, e.what());
  }
}

void require_paths(std::initializer_list<const fs::path*> paths, const char* what) {
  for (const fs::path* p : paths) {
    if (p->empty()) throw Error(std::string(what) + " are required");
  }
}

void write_png(const fs::path& path, const cv::Mat& image) {
  std::vector<uchar> png;
  if (!cv::imencode(".png", image, png)) throw Error::in_file(path, "cannot encode the image");
  core::write_file_atomic(path,
                          std::string_view(reinterpret_cast<const char*>(png.data()), png.size()));
}

}  // namespace

std::string describe_camera(const std::string& name, const Camera& c) {
  const Eigen::Vector3d C = c.center();
  // + 0.0 prints -0 as 0.
  return core::printf_string(
      "%s: fx %.2f fy %.2f cx %.2f cy %.2f skew %.3g; centre (%.5g, %.5g, %.5g)\n", name.c_str(),
      c.K(0, 0), c.K(1, 1), c.K(0, 2), c.K(1, 2), c.K(0, 1), C.x() + 0.0, C.y() + 0.0, C.z() + 0.0);
}

void CalibDltOptions::validate() const {
  require_paths({&points, &out}, "dlt: the point file and the output calib.yml");
  core::require_output_not_input(out, {points}, "--out");
  if ((width > 0) != (height > 0)) throw Error("dlt: give both --width and --height, or neither");
  if (width < 0 || height < 0) throw Error("dlt: the image size must be positive");
}

CalibRun run_calib_dlt(const CalibDltOptions& o, const core::Provenance& provenance) {
  o.validate();
  const auto pts = read_correspondences_csv(o.points);
  const auto r = naming(o.points, [&] { return calibrate_dlt(pts.world, pts.pixels); });
  Camera cam = r.camera;
  cam.width = o.width;
  cam.height = o.height;
  write_calib(o.out, cam, provenance);
  CalibRun run;
  run.report = core::printf_string("DLT on %d points: reprojection RMS %.4f px, max %.4f px\n",
                                   r.summary.num_points, r.rms_px, r.summary.max_residual_px) +
               describe_camera("camera", cam) + core::printf_string("wrote %s\n", o.out.c_str());
  if (r.summary.points_behind > 0) {
    run.warnings.push_back(core::printf_string("%s: %d points lie behind the estimated camera",
                                               o.points.c_str(), r.summary.points_behind));
  }
  run.document = core::result_document("proprio.calib.dlt", 1, provenance);
  core::fields_into_json(CalibDltRecord{o.points, o.out, r, cam}, run.document);
  run.message = core::first_line(run.brief());
  return run;
}

void CalibTriangulateOptions::validate() const {
  require_paths({&calib1, &calib2, &points, &out},
                "triangulate: both calibrations, the point file and the output");
  core::require_output_not_input(out, {calib1, calib2, points}, "--out");
}

CalibRun run_calib_triangulate(const CalibTriangulateOptions& o,
                               const core::Provenance& provenance) {
  o.validate();
  const Camera c1 = read_calib(o.calib1);
  const Camera c2 = read_calib(o.calib2);
  auto px = read_pixel_pairs_csv(o.points);
  if (o.distorted) {
    px.x1 = undistort_pixels(c1, px.x1);
    px.x2 = undistort_pixels(c2, px.x2);
  }
  TriangulationOptions to;
  to.refine = o.refine;
  const Matrix34d P1 = c1.P(), P2 = c2.P();
  try {
    require_distinct_centres(P1, P2);
  } catch (const Error& e) {
    // A fault of the two calibrations, not of a line of the point file.
    throw Error::in_file(o.calib2, std::string(e.what()) + " (calib1: " + o.calib1.string() + ")");
  }
  BatchTriangulation all;
  try {
    all = triangulate(P1, P2, px.x1, px.x2, to);
  } catch (const Error&) {
    // Find the row again so that the message names its line.
    for (size_t i = 0; i < px.x1.size(); ++i) {
      try {
        triangulate(P1, P2, px.x1[i], px.x2[i], to);
      } catch (const Error& e) {
        throw Error::at_line(o.points, px.lines[i], e.what());
      }
    }
    throw;
  }
  write_points_csv(o.out, all.points);
  CalibRun run;
  run.report = core::printf_string("%s\nwrote %s\n", all.summary.brief().c_str(), o.out.c_str());
  run.document = core::result_document("proprio.calib.triangulate", 1, provenance);
  core::fields_into_json(CalibTriangulateRecord{o.points, o.out, o.distorted, all.summary},
                         run.document);
  run.message = core::first_line(run.brief());
  return run;
}

void CalibBackprojectOptions::validate() const {
  require_paths({&calib, &points, &out},
                "backproject: the calibration, the point file and the output");
  core::require_output_not_input(out, {calib, points}, "--out");
  naming("--plane", [&] {
    plane.validate();
    return 0;
  });
}

CalibRun run_calib_backproject(const CalibBackprojectOptions& o,
                               const core::Provenance& provenance) {
  o.validate();
  const Camera cam = read_calib(o.calib);
  auto px = read_pixels_csv(o.points);
  if (o.distorted) px.pixels = undistort_pixels(cam, px.pixels);
  const Matrix34d P = cam.P();
  std::vector<Eigen::Vector3d> points;
  double min_cos = 1.0;
  for (size_t i = 0; i < px.pixels.size(); ++i) {
    try {
      const auto b = back_project_to_plane(P, px.pixels[i], o.plane);
      points.push_back(b.X);
      min_cos = std::min(min_cos, b.incidence_cos);
    } catch (const Error& e) {
      throw Error::at_line(o.points, px.lines[i], e.what());
    }
  }
  write_points_csv(o.out, points);
  const Eigen::Vector3d& n = o.plane.n;
  CalibRun run;
  run.report = core::printf_string(
      "back-projected %zu pixels onto %g x + %g y + %g z = %g (most grazing ray: cos %.3f)\n"
      "wrote %s\n",
      points.size(), n.x(), n.y(), n.z(), o.plane.kappa, min_cos, o.out.c_str());
  run.document = core::result_document("proprio.calib.backproject", 1, provenance);
  core::fields_into_json(CalibBackprojectRecord{o.points,
                                                o.out,
                                                {{n.x(), n.y(), n.z()}, o.plane.kappa},
                                                points.size(),
                                                o.distorted,
                                                min_cos},
                         run.document);
  run.message = core::first_line(run.brief());
  return run;
}

void CalibUncertaintyOptions::validate() const {
  require_paths({&calib1, &calib2, &out}, "uncertainty: both calibrations and the output");
  if (out.extension() != ".png") throw Error("uncertainty: --out must name a .png file");
  core::require_output_not_input(out, {calib1, calib2}, "--out");
  map.validate();
  render.validate();
}

CalibRun run_calib_uncertainty(const CalibUncertaintyOptions& o,
                               const core::Provenance& provenance) {
  o.validate();
  const Camera c1 = read_calib(o.calib1);
  const Camera c2 = read_calib(o.calib2);
  const auto map = compute_uncertainty_map(c1, c2, o.map);
  write_png(o.out, render_uncertainty_map(map, o.render));
  const auto& s = map.summary;
  const double f = o.render.unit_scale;
  const char* unit = o.render.unit.c_str();
  CalibRun run;
  run.report = core::printf_string(
      "visual uncertainty (sigma %.3g px): %d of %d cells seen by both cameras\n"
      "max std of the triangulated point: min %.4g %s at (%.4g, %.4g, %.4g), median %.4g %s, "
      "max %.4g %s\nwrote %s\n",
      o.map.sigma_px, s.valid_cells, s.cells, s.min_sigma * f, unit, s.best_point.x(),
      s.best_point.y(), s.best_point.z(), s.median_sigma * f, unit, s.max_sigma * f, unit,
      o.out.c_str());
  run.document = core::result_document("proprio.calib.uncertainty", 1, provenance);
  core::fields_into_json(
      CalibUncertaintyRecord{o.calib1, o.calib2, o.out, {&map, f, o.render.unit}}, run.document);
  run.message = core::first_line(run.brief());
  return run;
}

void CalibStereoOptions::validate() const {
  require_paths({&out}, "stereo: the output folder");
  if (fs::exists(out) && !fs::is_directory(out)) {
    throw Error::in_file(out, "exists and is not a directory");
  }
}

CalibRun run_calib_stereo(const CalibStereoOptions& o, const core::Provenance& provenance) {
  o.validate();
  StereoCheckOptions check = o.check;
  if (check.images_dir.empty()) check.images_dir = default_stereo_images_dir();
  core::require_output_not_input(o.out, {check.images_dir}, "--out");
  const auto r = run_stereo_check(check);
  write_calib(o.out / "left.yml", r.left, provenance);
  write_calib(o.out / "right.yml", r.right, provenance);
  write_stereo_corners_csv(o.out / "corners.csv", r.corners);
  CalibRun run;
  std::string& text = run.report;
  text = core::printf_string("stereo check on %s (board %dx%d, square %g)\n%s\n",
                             check.images_dir.c_str(), check.board.width, check.board.height,
                             check.square_size, r.summary.brief().c_str());
  text += describe_camera("left camera", r.left);
  text += describe_camera("right camera", r.right);
  for (const auto& p : r.pairs) {
    text += core::printf_string(
        "  pair %s: board %s/%s, %d corners, planarity %.4f, neighbours %.5f squares\n",
        p.id.c_str(), p.found_left ? "found" : "missed", p.found_right ? "found" : "missed",
        p.corners, p.planarity_rms, p.neighbour_mean);
  }
  text += core::printf_string("wrote %s/{left.yml,right.yml,corners.csv}\n", o.out.c_str());
  run.document = core::result_document("proprio.calib.stereo", 1, provenance);
  core::fields_into_json(CalibStereoRecord{check.images_dir,
                                           {check.board.width, check.board.height},
                                           check.square_size,
                                           check.refine_triangulation,
                                           o.out,
                                           r},
                         run.document);
  run.message = core::first_line(run.brief());
  return run;
}

}  // namespace proprio::geometry
