#include "proprio/geometry/uncertainty_map.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "proprio/core/error.hpp"
#include "proprio/geometry/visual_uncertainty.hpp"

namespace proprio::geometry {
namespace {

// The two in-slice axes, in increasing order.
std::array<int, 2> in_slice_axes(int slice_axis) {
  if (slice_axis == 0) return {1, 2};
  if (slice_axis == 1) return {0, 2};
  return {0, 1};
}

bool sees(const Camera& c, const Eigen::Vector2d& x) {
  return x.x() >= -0.5 && x.y() >= -0.5 && x.x() < c.width - 0.5 && x.y() < c.height - 0.5;
}

std::string fmt(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

constexpr char kAxisNames[3] = {'x', 'y', 'z'};

}  // namespace

void UncertaintyMapOptions::validate() const {
  require(slice_axis >= 0 && slice_axis <= 2, "uncertainty map: slice axis must be 0, 1 or 2");
  require(std::isfinite(slice_at), "uncertainty map: slice position must be finite");
  require(range_a.allFinite() && range_b.allFinite() && range_a(0) < range_a(1) &&
              range_b(0) < range_b(1),
          "uncertainty map: each range must be finite with min < max");
  require(cells_a >= 2 && cells_b >= 2 && cells_a <= 4096 && cells_b <= 4096,
          "uncertainty map: cells per axis must lie in [2, 4096]");
  require(std::isfinite(sigma_px) && sigma_px > 0.0,
          "uncertainty map: pixel noise sigma must be positive");
}

void UncertaintyRenderOptions::validate() const {
  require(std::isfinite(unit_scale) && unit_scale > 0.0,
          "uncertainty map: unit scale must be positive");
  require(map_width_px >= 100 && map_width_px <= 4000,
          "uncertainty map: map width must lie in [100, 4000] pixels");
  require(clip_percentile > 0.0 && clip_percentile <= 100.0,
          "uncertainty map: clip percentile must lie in (0, 100]");
}

Eigen::Vector3d UncertaintyMap::cell_centre(int row, int col) const {
  const auto axes = in_slice_axes(options.slice_axis);
  Eigen::Vector3d X;
  X(options.slice_axis) = options.slice_at;
  const auto& ra = options.range_a;
  const auto& rb = options.range_b;
  X(axes[0]) = ra(0) + (ra(1) - ra(0)) * (col + 0.5) / options.cells_a;
  X(axes[1]) = rb(0) + (rb(1) - rb(0)) * (row + 0.5) / options.cells_b;
  return X;
}

UncertaintyMap compute_uncertainty_map(const Camera& camera1, const Camera& camera2,
                                       const UncertaintyMapOptions& options) {
  options.validate();
  UncertaintyMap map;
  map.options = options;
  map.sigma = Eigen::ArrayXXd::Zero(options.cells_b, options.cells_a);
  map.valid.setConstant(options.cells_b, options.cells_a, false);
  map.camera_centres = {camera1.center(), camera2.center()};
  const Matrix34d P1 = camera1.P();
  const Matrix34d P2 = camera2.P();
  const Eigen::Matrix2d Sigma = options.sigma_px * options.sigma_px * Eigen::Matrix2d::Identity();
  const bool check_image = options.visible_only && camera1.width > 0 && camera1.height > 0 &&
                           camera2.width > 0 && camera2.height > 0;
  auto& s = map.summary;
  s.cells = options.cells_a * options.cells_b;
  std::vector<double> values;
  values.reserve(static_cast<size_t>(s.cells));
  for (int r = 0; r < options.cells_b; ++r) {
    for (int c = 0; c < options.cells_a; ++c) {
      const Eigen::Vector3d X = map.cell_centre(r, c);
      if (camera1.depth(X) <= 0.0 || camera2.depth(X) <= 0.0) {
        ++s.behind_camera;
        continue;
      }
      if (check_image &&
          (!sees(camera1, camera1.project(X)) || !sees(camera2, camera2.project(X)))) {
        ++s.outside_image;
        continue;
      }
      Eigen::Matrix3d cov;
      try {
        cov = triangulation_covariance(P1, P2, X, Sigma);
      } catch (const Error&) {
        ++s.unobservable;
        continue;
      }
      const double worst =
          Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(cov, Eigen::EigenvaluesOnly)
              .eigenvalues()(2);
      const double sigma = std::sqrt(std::max(worst, 0.0));
      map.sigma(r, c) = sigma;
      map.valid(r, c) = true;
      values.push_back(sigma);
      if (s.valid_cells == 0 || sigma < s.min_sigma) {
        s.min_sigma = sigma;
        s.best_point = X;
      }
      s.max_sigma = std::max(s.max_sigma, sigma);
      ++s.valid_cells;
    }
  }
  if (s.valid_cells == 0) {
    throw Error("uncertainty map: no cell of the slice is seen by both cameras (" +
                std::to_string(s.behind_camera) + " behind a camera, " +
                std::to_string(s.outside_image) + " outside an image)");
  }
  std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
  s.median_sigma = values[values.size() / 2];
  return map;
}

cv::Mat render_uncertainty_map(const UncertaintyMap& map, const UncertaintyRenderOptions& options) {
  options.validate();
  const auto& o = map.options;
  const auto axes = in_slice_axes(o.slice_axis);
  const int W = options.map_width_px;
  const double aspect = (o.range_b(1) - o.range_b(0)) / (o.range_a(1) - o.range_a(0));
  const int H = std::clamp(static_cast<int>(std::lround(W * aspect)), 120, 4 * W);
  constexpr int kLeft = 80, kRight = 130, kTop = 50, kBottom = 60;
  cv::Mat canvas(kTop + H + kBottom, kLeft + W + kRight, CV_8UC3, cv::Scalar(255, 255, 255));

  // Logarithmic colour scale from the smallest value to the clip percentile.
  std::vector<double> values;
  for (int r = 0; r < map.sigma.rows(); ++r) {
    for (int c = 0; c < map.sigma.cols(); ++c) {
      if (map.valid(r, c)) values.push_back(map.sigma(r, c));
    }
  }
  assert(!values.empty());
  std::sort(values.begin(), values.end());
  const double lo = std::log10(values.front());
  const size_t clip_index = std::min(
      values.size() - 1,
      static_cast<size_t>(std::floor(options.clip_percentile / 100.0 * (values.size() - 1))));
  double hi = std::log10(values[clip_index]);
  if (hi - lo < 1e-6) hi = lo + 1.0;
  const bool clipped = values.back() > values[clip_index];
  auto level = [&](double v) {
    return static_cast<uchar>(std::clamp((std::log10(v) - lo) / (hi - lo), 0.0, 1.0) * 255.0);
  };

  cv::Mat levels(H, W, CV_8U);
  cv::Mat invalid(H, W, CV_8U, cv::Scalar(0));
  for (int py = 0; py < H; ++py) {
    const int row = o.cells_b - 1 - std::min(o.cells_b - 1, py * o.cells_b / H);  // b points up
    for (int px = 0; px < W; ++px) {
      const int col = std::min(o.cells_a - 1, px * o.cells_a / W);
      if (map.valid(row, col)) {
        levels.at<uchar>(py, px) = level(map.sigma(row, col));
      } else {
        levels.at<uchar>(py, px) = 0;
        invalid.at<uchar>(py, px) = 255;
      }
    }
  }
  cv::Mat coloured;
  cv::applyColorMap(levels, coloured, cv::COLORMAP_TURBO);
  coloured.setTo(cv::Scalar(70, 70, 70), invalid);
  coloured.copyTo(canvas(cv::Rect(kLeft, kTop, W, H)));
  cv::rectangle(canvas, cv::Rect(kLeft - 1, kTop - 1, W + 2, H + 2), cv::Scalar(0, 0, 0));

  const int font = cv::FONT_HERSHEY_SIMPLEX;
  const cv::Scalar black(0, 0, 0);
  auto text = [&](const std::string& s, cv::Point at, double scale = 0.45) {
    cv::putText(canvas, s, at, font, scale, black, 1, cv::LINE_AA);
  };
  auto text_width = [&](const std::string& s, double scale = 0.45) {
    int baseline = 0;
    return cv::getTextSize(s, font, scale, 1, &baseline).width;
  };

  // Axes: ticks at both ends and the middle.
  for (int i = 0; i <= 2; ++i) {
    const double f = i / 2.0;
    const std::string la = fmt("%.3g", o.range_a(0) + f * (o.range_a(1) - o.range_a(0)));
    const int x = kLeft + static_cast<int>(f * (W - 1));
    cv::line(canvas, {x, kTop + H}, {x, kTop + H + 5}, black);
    text(la, {x - text_width(la) / 2, kTop + H + 20});
    const std::string lb = fmt("%.3g", o.range_b(0) + f * (o.range_b(1) - o.range_b(0)));
    const int y = kTop + H - 1 - static_cast<int>(f * (H - 1));
    cv::line(canvas, {kLeft - 5, y}, {kLeft, y}, black);
    text(lb, {kLeft - 8 - text_width(lb), y + 5});
  }
  std::string name_a(1, kAxisNames[axes[0]]);
  name_a += " [";
  name_a += options.world_unit;
  name_a += "]";
  std::string name_b(1, kAxisNames[axes[1]]);
  name_b += " [";
  name_b += options.world_unit;
  name_b += "]";
  text(name_a, {kLeft + W / 2 - text_width(name_a) / 2, kTop + H + 42});
  text(name_b, {8, kTop - 8});  // above the vertical axis, clear of its tick labels

  // Camera centres inside the slice's ranges.
  for (int k = 0; k < 2; ++k) {
    const Eigen::Vector3d& C = map.camera_centres[static_cast<size_t>(k)];
    const double fa = (C(axes[0]) - o.range_a(0)) / (o.range_a(1) - o.range_a(0));
    const double fb = (C(axes[1]) - o.range_b(0)) / (o.range_b(1) - o.range_b(0));
    if (fa < 0 || fa > 1 || fb < 0 || fb > 1) continue;
    const cv::Point p(kLeft + static_cast<int>(fa * (W - 1)),
                      kTop + H - 1 - static_cast<int>(fb * (H - 1)));
    cv::circle(canvas, p, 6, cv::Scalar(255, 255, 255), cv::FILLED, cv::LINE_AA);
    cv::circle(canvas, p, 6, black, 1, cv::LINE_AA);
    std::string label = "C";
    label += std::to_string(k + 1);
    cv::putText(canvas, label, p + cv::Point(8, -8), font, 0.5, cv::Scalar(255, 255, 255), 2,
                cv::LINE_AA);
    cv::putText(canvas, label, p + cv::Point(8, -8), font, 0.5, black, 1, cv::LINE_AA);
  }

  // Colour bar with five labelled ticks.
  const int bar_x = kLeft + W + 20;
  cv::Mat bar_levels(H, 1, CV_8U);
  for (int y = 0; y < H; ++y) {
    bar_levels.at<uchar>(y, 0) = static_cast<uchar>(255.0 * (H - 1 - y) / (H - 1));
  }
  cv::Mat bar;
  cv::applyColorMap(bar_levels, bar, cv::COLORMAP_TURBO);
  cv::resize(bar, bar, {18, H}, 0, 0, cv::INTER_NEAREST);
  bar.copyTo(canvas(cv::Rect(bar_x, kTop, 18, H)));
  cv::rectangle(canvas, cv::Rect(bar_x - 1, kTop - 1, 20, H + 2), black);
  for (int i = 0; i <= 4; ++i) {
    const double f = i / 4.0;
    const double v = std::pow(10.0, lo + f * (hi - lo)) * options.unit_scale;
    std::string label = fmt("%.3g", v);
    if (i == 4 && clipped) label.insert(0, ">=");
    const int y = kTop + H - 1 - static_cast<int>(f * (H - 1));
    cv::line(canvas, {bar_x + 18, y}, {bar_x + 23, y}, black);
    text(label, {bar_x + 26, y + 5});
  }
  std::string unit = "[";
  unit += options.unit;
  unit += "]";
  text(unit, {bar_x - 4, kTop - 10});

  // Title.
  std::string title = "max std of triangulated point, sigma = ";
  title += fmt("%.3g", o.sigma_px);
  title += " px, ";
  title += kAxisNames[o.slice_axis];
  title += " = ";
  title += fmt("%.3g", o.slice_at);
  text(title, {kLeft, 28}, 0.5);
  return canvas;
}

}  // namespace proprio::geometry
