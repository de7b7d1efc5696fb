#include "proprio/geometry/point_files.hpp"

#include <algorithm>

#include "proprio/core/csv.hpp"
#include "proprio/core/error.hpp"
#include "proprio/core/files.hpp"

namespace proprio::geometry {
namespace {

core::CsvTable read_exact(const std::filesystem::path& path, std::vector<std::string> columns) {
  core::CsvReadOptions o;
  o.exact_columns = std::move(columns);
  const std::string text = core::read_file(path);
  // Every line proprio and spreadsheets write ends in a newline: a last line without one is
  // most likely a file cut short, maybe in the middle of a number ("12.5" read as "12").
  if (!text.empty() && text.back() != '\n') {
    const long lines = 1 + static_cast<long>(std::count(text.begin(), text.end(), '\n'));
    throw Error::at_line(path, lines,
                         "the last line does not end in a newline: the file looks "
                         "cut short (a number may be cut in the middle)");
  }
  return core::parse_csv(text, path, o);
}

}  // namespace

Correspondences read_correspondences_csv(const std::filesystem::path& path) {
  const core::CsvTable t = read_exact(path, {"X", "Y", "Z", "u", "v"});
  Correspondences c;
  c.source = path;
  c.lines = t.lines;
  for (size_t i = 0; i < t.rows.size(); ++i) {
    c.world.emplace_back(t.at(i, 0), t.at(i, 1), t.at(i, 2));
    c.pixels.emplace_back(t.at(i, 3), t.at(i, 4));
  }
  return c;
}

PixelPairs read_pixel_pairs_csv(const std::filesystem::path& path) {
  const core::CsvTable t = read_exact(path, {"u1", "v1", "u2", "v2"});
  PixelPairs p;
  p.source = path;
  p.lines = t.lines;
  for (size_t i = 0; i < t.rows.size(); ++i) {
    p.x1.emplace_back(t.at(i, 0), t.at(i, 1));
    p.x2.emplace_back(t.at(i, 2), t.at(i, 3));
  }
  return p;
}

PixelList read_pixels_csv(const std::filesystem::path& path) {
  const core::CsvTable t = read_exact(path, {"u", "v"});
  PixelList p;
  p.source = path;
  p.lines = t.lines;
  for (size_t i = 0; i < t.rows.size(); ++i) p.pixels.emplace_back(t.at(i, 0), t.at(i, 1));
  return p;
}

void write_points_csv(const std::filesystem::path& path,
                      const std::vector<Eigen::Vector3d>& points) {
  std::vector<std::vector<std::optional<double>>> rows;
  rows.reserve(points.size());
  for (const auto& X : points) rows.push_back({X.x(), X.y(), X.z()});
  core::write_file_atomic(path, core::format_csv({"X", "Y", "Z"}, rows));
}

void write_stereo_corners_csv(const std::filesystem::path& path,
                              const std::vector<StereoCorner>& corners) {
  std::vector<std::vector<std::optional<double>>> rows;
  rows.reserve(corners.size());
  for (const auto& c : corners) {
    rows.push_back({c.pair, c.corner, c.left_px.x(), c.left_px.y(), c.right_px.x(), c.right_px.y(),
                    c.X.x(), c.X.y(), c.X.z()});
  }
  core::write_file_atomic(
      path, core::format_csv({"pair", "corner", "u1", "v1", "u2", "v2", "X", "Y", "Z"}, rows));
}

}  // namespace proprio::geometry
