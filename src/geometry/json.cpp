#include "proprio/geometry/json.hpp"

namespace proprio::geometry {

core::Json matrix_to_json(const Eigen::MatrixXd& m) {
  core::Json rows = core::Json::array();
  for (Eigen::Index r = 0; r < m.rows(); ++r) {
    core::Json row = core::Json::array();
    for (Eigen::Index c = 0; c < m.cols(); ++c) row.push_back(m(r, c));
    rows.push_back(row);
  }
  return rows;
}

namespace {

core::Json vector_to_json(const Eigen::VectorXd& v) {
  return core::Json(std::vector<double>(v.data(), v.data() + v.size()));
}

}  // namespace

core::Json to_json(const Camera& camera) {
  return {{"K", matrix_to_json(camera.K)},   {"dist", camera.dist},
          {"R", matrix_to_json(camera.R)},   {"t", vector_to_json(camera.t)},
          {"P", matrix_to_json(camera.P())}, {"centre", vector_to_json(camera.center())},
          {"image_width", camera.width},     {"image_height", camera.height}};
}

core::Json to_json(const DltResult& r) {
  const auto& s = r.summary;
  return {{"rms_px", r.rms_px},
          {"points", s.num_points},
          {"max_residual_px", s.max_residual_px},
          {"residuals_px", r.residuals_px},
          {"P", matrix_to_json(r.P)},
          {"camera", to_json(r.camera)},
          {"summary",
           {{"normalized", s.normalized},
            {"sigma11_ratio", s.sigma11_ratio},
            {"sigma12_ratio", s.sigma12_ratio},
            {"points_behind", s.points_behind}}}};
}

core::Json to_json(const BatchTriangulationSummary& s) {
  return {{"points", s.num_points},           {"refined", s.refined},
          {"iterations", s.total_iterations}, {"not_converged", s.not_converged},
          {"linear_rms_px", s.linear_rms_px}, {"rms_px", s.final_rms_px},
          {"max_rms_px", s.max_rms_px}};
}

core::Json to_json(const UncertaintyMap& map, double unit_scale, const std::string& unit) {
  const auto& o = map.options;
  const auto& s = map.summary;
  static const char* const kAxes[3] = {"x", "y", "z"};
  return {{"slice", {{"axis", kAxes[o.slice_axis]}, {"at", o.slice_at}}},
          {"range_a", {o.range_a(0), o.range_a(1)}},
          {"range_b", {o.range_b(0), o.range_b(1)}},
          {"cells", {o.cells_a, o.cells_b}},
          {"sigma_px", o.sigma_px},
          {"unit", unit},
          {"unit_scale", unit_scale},
          {"summary",
           {{"cells", s.cells},
            {"valid_cells", s.valid_cells},
            {"behind_camera", s.behind_camera},
            {"outside_image", s.outside_image},
            {"unobservable", s.unobservable},
            {"min_sigma", s.min_sigma * unit_scale},
            {"median_sigma", s.median_sigma * unit_scale},
            {"max_sigma", s.max_sigma * unit_scale},
            {"best_point", vector_to_json(s.best_point)}}}};
}

core::Json to_json(const StereoCheckResult& r) {
  const auto& s = r.summary;
  core::Json pairs = core::Json::array();
  for (const auto& p : r.pairs) {
    pairs.push_back({{"id", p.id},
                     {"left", p.left.string()},
                     {"right", p.right.string()},
                     {"found_left", p.found_left},
                     {"found_right", p.found_right},
                     {"corners", p.corners},
                     {"planarity_rms", p.planarity_rms},
                     {"neighbour_mean", p.neighbour_mean}});
  }
  return {{"pairs_found", s.pairs_found},
          {"pairs_used", s.pairs_used},
          {"corners", s.corners},
          {"image_size", {s.image_size.width, s.image_size.height}},
          {"rms_left_px", s.rms_left_px},
          {"rms_right_px", s.rms_right_px},
          {"stereo_rms_px", s.stereo_rms_px},
          {"baseline", s.baseline},
          {"triangulation_rms_px", s.triangulation_rms_px},
          {"max_diff_opencv", s.max_diff_opencv},
          {"mean_diff_opencv", s.mean_diff_opencv},
          {"planarity_rms", s.planarity_rms},
          {"planarity_worst", s.planarity_worst},
          {"neighbour_mean", s.neighbour_mean},
          {"neighbour_error", s.neighbour_error},
          {"left", to_json(r.left)},
          {"right", to_json(r.right)},
          {"per_pair", pairs}};
}

}  // namespace proprio::geometry
