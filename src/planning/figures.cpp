#include "proprio/planning/figures.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>
#include <string>

#include "proprio/core/error.hpp"
#include "text.hpp"

namespace proprio::planning {

namespace {

const cv::Scalar kBlack(0, 0, 0), kGrey(150, 150, 150), kLight(215, 215, 215),
    kWhite(255, 255, 255), kBlue(200, 110, 20), kRed(40, 40, 210), kGreen(40, 150, 40),
    kDarkGreen(20, 90, 20);
constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;

std::string fmt(double v, int decimals) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

void text(cv::Mat& img, const std::string& s, cv::Point at, double scale = 0.45,
          const cv::Scalar& colour = kBlack, int thickness = 1) {
  cv::putText(img, s, at, kFont, scale, colour, thickness, cv::LINE_AA);
}

// A "nice" tick step for a range (1, 2 or 5 times a power of ten).
double tick_step(double range, int target = 6) {
  const double raw = range / target;
  const double p = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0, 10.0}) {
    if (m * p >= raw) return m * p;
  }
  return 10 * p;
}

int decimals_for(double step) {
  return std::max(0, -static_cast<int>(std::floor(std::log10(step) + 1e-9)));
}

// A plot area mapping data coordinates to pixels, y up.
struct Axes {
  cv::Rect area;
  double x0 = 0, x1 = 1, y0 = 0, y1 = 1;
  [[nodiscard]] cv::Point px(double x, double y) const {
    return {
        area.x + static_cast<int>(std::lround((x - x0) / (x1 - x0) * area.width)),
        area.y + area.height - static_cast<int>(std::lround((y - y0) / (y1 - y0) * area.height))};
  }
  [[nodiscard]] double scale() const { return area.width / (x1 - x0); }  // px per unit x
};

void draw_axes(cv::Mat& img, const Axes& a, const std::string& xlabel, const std::string& ylabel,
               const std::string& title) {
  cv::rectangle(img, a.area, kBlack, 1);
  const double sx = tick_step(a.x1 - a.x0), sy = tick_step(a.y1 - a.y0);
  for (double x = std::ceil(a.x0 / sx) * sx; x <= a.x1 + 1e-9; x += sx) {
    const cv::Point p = a.px(x, a.y0);
    cv::line(img, p, p + cv::Point(0, 5), kBlack);
    cv::line(img, {p.x, a.area.y}, {p.x, a.area.y + a.area.height}, kLight);
    text(img, fmt(std::abs(x) < 1e-12 ? 0 : x, decimals_for(sx)), p + cv::Point(-14, 20), 0.4);
  }
  for (double y = std::ceil(a.y0 / sy) * sy; y <= a.y1 + 1e-9; y += sy) {
    const cv::Point p = a.px(a.x0, y);
    cv::line(img, p, p - cv::Point(5, 0), kBlack);
    cv::line(img, {a.area.x, p.y}, {a.area.x + a.area.width, p.y}, kLight);
    text(img, fmt(std::abs(y) < 1e-12 ? 0 : y, decimals_for(sy)), p + cv::Point(-48, 5), 0.4);
  }
  cv::rectangle(img, a.area, kBlack, 1);
  text(img, xlabel, {a.area.x + a.area.width / 2 - 40, a.area.y + a.area.height + 40}, 0.45);
  text(img, ylabel, {a.area.x - 60, a.area.y - 10}, 0.45);
  text(img, title, {a.area.x, a.area.y - 30}, 0.55, kBlack, 1);
}

void cross(cv::Mat& img, cv::Point p, int r, const cv::Scalar& c, int thickness = 2) {
  cv::line(img, p + cv::Point(-r, -r), p + cv::Point(r, r), c, thickness, cv::LINE_AA);
  cv::line(img, p + cv::Point(-r, r), p + cv::Point(r, -r), c, thickness, cv::LINE_AA);
}

void legend(cv::Mat& img, cv::Point at,
            const std::vector<std::pair<std::string, cv::Scalar>>& items) {
  for (std::size_t i = 0; i < items.size(); ++i) {
    const cv::Point p = at + cv::Point(0, static_cast<int>(i) * 18);
    cv::rectangle(img, p + cv::Point(0, -9), p + cv::Point(12, 1), items[i].second, cv::FILLED);
    text(img, items[i].first, p + cv::Point(18, 0), 0.42);
  }
}

cv::Vec3b colour_of(double v, double lo, double hi) {
  static cv::Mat lut;
  if (lut.empty()) {
    cv::Mat ramp(1, 256, CV_8UC1);
    for (int i = 0; i < 256; ++i) ramp.at<uchar>(0, i) = static_cast<uchar>(i);
    cv::applyColorMap(ramp, lut, cv::COLORMAP_VIRIDIS);
  }
  const double u = hi > lo ? std::clamp((v - lo) / (hi - lo), 0.0, 1.0) : 0.5;
  return lut.at<cv::Vec3b>(0, static_cast<int>(std::lround(u * 255)));
}

// Data bounds of a set of points, padded and made square in data units.
void fit(Axes& a, const std::vector<Eigen::Vector2d>& pts, double pad) {
  double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
  for (const auto& p : pts) {
    x0 = std::min(x0, p.x());
    x1 = std::max(x1, p.x());
    y0 = std::min(y0, p.y());
    y1 = std::max(y1, p.y());
  }
  x0 -= pad, x1 += pad, y0 -= pad, y1 += pad;
  // Equal scale on both axes.
  const double sx = (x1 - x0) / a.area.width, sy = (y1 - y0) / a.area.height;
  const double s = std::max(sx, sy);
  const double cx = 0.5 * (x0 + x1), cy = 0.5 * (y0 + y1);
  a.x0 = cx - 0.5 * s * a.area.width;
  a.x1 = cx + 0.5 * s * a.area.width;
  a.y0 = cy - 0.5 * s * a.area.height;
  a.y1 = cy + 0.5 * s * a.area.height;
}

}  // namespace

TargetMotion figure_target(const GridSpec& grid, double t_plan) {
  TargetMotion m;
  m.velocity = {-0.1, 0, 0};
  m.start = grid.start + Eigen::Vector3d(0.10, 0.12, 0) - m.velocity * (t_plan + grid.duration);
  return m;
}

cv::Mat draw_energy_grid(const GridCosts& costs) {
  const GridSpec& g = costs.options.grid;
  double lo = 1e300, hi = -1e300;
  for (const GridPoint& p : costs.points) {
    if (!p.valid) continue;
    lo = std::min(lo, p.energy);
    hi = std::max(hi, p.energy);
  }
  require(hi >= lo, "energy plot: no valid trajectory in the grid");
  const int cols = std::min(3, g.gamma.count);
  const int rows = (g.gamma.count + cols - 1) / cols;
  const int pw = 300, ph = 260, left = 80, top = 80, gap_x = 90, gap_y = 100;
  cv::Mat img(top + rows * (ph + gap_y) + 20, left + cols * (pw + gap_x) + 120, CV_8UC3, kWhite);
  text(img, "Fig 3-8: energy of each trajectory, sum over joints of integral |tau_k| dt (N m s)",
       {20, 30}, 0.6);
  for (int k = 0; k < g.gamma.count; ++k) {
    Axes a;
    a.area = {left + (k % cols) * (pw + gap_x), top + 30 + (k / cols) * (ph + gap_y), pw, ph};
    const double dt = g.theta.count > 1 ? (g.theta.max - g.theta.min) / (g.theta.count - 1) : 1;
    const double dl =
        g.length.count > 1 ? (g.length.max - g.length.min) / (g.length.count - 1) : 0.01;
    a.x0 = g.theta.min - dt / 2;
    a.x1 = g.theta.max + dt / 2;
    a.y0 = g.length.min - dl / 2;
    a.y1 = g.length.max + dl / 2;
    for (int it = 0; it < g.theta.count; ++it) {
      for (int il = 0; il < g.length.count; ++il) {
        const GridPoint& p = costs.points[static_cast<std::size_t>(g.index(it, il, k))];
        const double th = g.theta.value(it), l = g.length.value(il);
        const cv::Point c0 = a.px(th - dt / 2, l + dl / 2), c1 = a.px(th + dt / 2, l - dl / 2);
        const cv::Vec3b c = p.valid ? colour_of(p.energy, lo, hi) : cv::Vec3b(60, 60, 60);
        cv::rectangle(img, cv::Rect(c0, c1), cv::Scalar(c[0], c[1], c[2]), cv::FILLED);
      }
    }
    draw_axes(img, a, "theta (rad)", "l (m)", "gamma = " + fmt(g.gamma.value(k), 2));
  }
  // Colour bar.
  const cv::Rect bar(img.cols - 90, top + 30, 22, rows * (ph + gap_y) - gap_y);
  for (int y = 0; y < bar.height; ++y) {
    const cv::Vec3b c = colour_of(hi - (hi - lo) * y / std::max(1, bar.height - 1), lo, hi);
    cv::line(img, {bar.x, bar.y + y}, {bar.x + bar.width, bar.y + y}, cv::Scalar(c[0], c[1], c[2]));
  }
  cv::rectangle(img, bar, kBlack);
  text(img, fmt(hi, 2), {bar.x - 4, bar.y - 8}, 0.42);
  text(img, fmt(lo, 2), {bar.x - 4, bar.y + bar.height + 18}, 0.42);
  text(img, "N m s", {bar.x - 6, bar.y + bar.height + 36}, 0.42);
  return img;
}

cv::Mat draw_interception(const TrialResult& trial, const GridSpec& grid) {
  const TrialRecord& rec = trial.record;
  ensure(!rec.measurements.empty() && !rec.executed.empty(),
         "interception plot: the trial was not recorded");
  cv::Mat img(760, 1000, CV_8UC3, kWhite);
  Axes a;
  a.area = {90, 90, 640, 600};
  std::vector<Eigen::Vector2d> pts;
  const double t_end = trial.executed ? trial.t_intercept : trial.t_plan + grid.duration;
  pts.push_back(trial.target.position(0).head<2>());
  pts.push_back(trial.target.position(t_end).head<2>());
  for (int i = 0; i < grid.size(); ++i) pts.push_back(grid.end_point(grid.params(i)).head<2>());
  pts.push_back(grid.start.head<2>());
  fit(a, pts, 0.05);
  // Data go on a copy whose plot area alone is kept, so that nothing spills over the labels.
  cv::Mat canvas = img.clone();
  std::swap(canvas, img);
  // The reachable half-disc: the grid's end points.
  for (int i = 0; i < grid.size(); ++i) {
    cv::circle(img, a.px(grid.end_point(grid.params(i)).x(), grid.end_point(grid.params(i)).y()), 3,
               kLight, cv::FILLED);
  }
  // True path.
  const Eigen::Vector3d s0 = trial.target.position(0), s1 = trial.target.position(t_end);
  cv::line(img, a.px(s0.x(), s0.y()), a.px(s1.x(), s1.y()), kGrey, 2, cv::LINE_AA);
  for (const auto& m : rec.measurements) {
    if (m.t > t_end + 1e-9) continue;
    cv::circle(img, a.px(m.position.x(), m.position.y()), 2, kBlue, cv::FILLED, cv::LINE_AA);
  }
  // The first plan's prediction, every other frame, circles of radius = predicted std.
  for (std::size_t i = 0; i < rec.forecast.size(); i += 2) {
    const TargetEstimate& e = rec.forecast[i];
    const double sigma = std::sqrt(e.position_cov().topLeftCorner<2, 2>().trace() / 2);
    const int r = std::max(2, static_cast<int>(std::lround(sigma * a.scale())));
    cv::circle(img, a.px(e.mean.x(), e.mean.y()), r, kRed, 1, cv::LINE_AA);
  }
  for (std::size_t i = 1; i < rec.commanded.size(); ++i) {
    cv::line(img, a.px(rec.commanded[i - 1].x(), rec.commanded[i - 1].y()),
             a.px(rec.commanded[i].x(), rec.commanded[i].y()), kGreen, 2, cv::LINE_AA);
  }
  for (const auto& p : rec.executed) cv::circle(img, a.px(p.x(), p.y()), 2, kDarkGreen, cv::FILLED);
  const cv::Point start = a.px(grid.start.x(), grid.start.y());
  cv::rectangle(img, start - cv::Point(5, 5), start + cv::Point(5, 5), kBlack, cv::FILLED);
  if (trial.executed) {
    cross(img, a.px(trial.target_at.x(), trial.target_at.y()), 7, kBlue);
    cross(img, a.px(trial.ee_at.x(), trial.ee_at.y()), 5, kDarkGreen);
  }
  std::swap(canvas, img);
  canvas(a.area).copyTo(img(a.area));
  draw_axes(img, a, "x (m)", "y (m)",
            "Fig 3-10: interception seen from above (world frame, robot base at the origin)");
  std::string sub = "noise " + fmt(trial.sigma_px, 2) + " px; ";
  sub += trial.executed ? "miss " + fmt(trial.miss * 1e3, 2) + " mm, predicted std " +
                              fmt(trial.first_predicted_sigma * 1e3, 2) + " mm, meets it " +
                              fmt(trial.t_intercept - trial.t_plan, 2) + " s after the plan"
                        : "not executed: " + trial.why_not.substr(0, 60);
  text(img, sub, {a.area.x, a.area.y - 10}, 0.42);
  legend(img, {a.area.x + a.area.width + 15, a.area.y + 20},
         {{"reachable end points", kLight},
          {"target's true path", kGrey},
          {"measurements", kBlue},
          {"prediction, radius = std", kRed},
          {"arm's commanded path", kGreen},
          {"end-effector (sim)", kDarkGreen},
          {"start p0", kBlack}});
  return img;
}

cv::Mat draw_noise_choices(const TargetMotion& target, double t_plan, const GridSpec& grid,
                           const std::vector<NoiseChoice>& choices) {
  ensure(!choices.empty(), "noise plot: no choices to draw");
  cv::Mat img(700, 1400, CV_8UC3, kWhite);
  auto colour = [](PriorMode m) {
    return m == PriorMode::kBoth ? kBlue : m == PriorMode::kEnergy ? kBlack : kRed;
  };
  double noise_max = 0, t_max = 0, t_min = grid.duration;
  for (const auto& c : choices) {
    noise_max = std::max(noise_max, c.noise_cm);
    if (c.draws == 0) continue;
    t_max = std::max(t_max, c.mean_time + c.std_time);
    t_min = std::min(t_min, c.mean_time - c.std_time);
  }
  // Left: top view.
  Axes a;
  a.area = {90, 110, 560, 500};
  std::vector<Eigen::Vector2d> pts;
  const double t_end = t_plan + grid.duration + std::max(t_max, 0.5) + 0.3;
  pts.reserve(static_cast<std::size_t>(grid.size()) + 1);
  for (int i = 0; i < grid.size(); ++i) pts.push_back(grid.end_point(grid.params(i)).head<2>());
  pts.push_back(grid.start.head<2>());
  fit(a, pts, 0.12);
  cv::Mat canvas = img.clone();
  std::swap(canvas, img);
  for (int i = 0; i < grid.size(); ++i) {
    const Eigen::Vector3d p = grid.end_point(grid.params(i));
    cv::circle(img, a.px(p.x(), p.y()), 3, kLight, cv::FILLED);
  }
  const Eigen::Vector3d s0 = target.position(t_plan), s1 = target.position(t_end);
  cv::arrowedLine(img, a.px(s0.x(), s0.y()), a.px(s1.x(), s1.y()), kGrey, 2, cv::LINE_AA, 0, 0.03);
  const cv::Point start = a.px(grid.start.x(), grid.start.y());
  cv::rectangle(img, start - cv::Point(5, 5), start + cv::Point(5, 5), kBlack, cv::FILLED);
  for (const auto& c : choices) {
    if (c.draws == 0) continue;
    const Eigen::Vector3d p = target.position(t_plan + c.mean_time);
    const int r = 3 + static_cast<int>(std::lround(6 * c.noise_cm / std::max(noise_max, 1e-9)));
    const int off = c.mode == PriorMode::kBoth ? 0 : c.mode == PriorMode::kEnergy ? 1 : 2;
    cv::circle(img, a.px(p.x(), p.y()) + cv::Point(0, 4 * off - 4), r, colour(c.mode), 2,
               cv::LINE_AA);
  }
  std::swap(canvas, img);
  canvas(a.area).copyTo(img(a.area));
  draw_axes(img, a, "x (m)", "y (m)",
            "where the planner meets the target (marker grows with noise)");
  // Right: interception time against noise.
  Axes b;
  b.area = {800, 110, 520, 500};
  b.x0 = -0.1 * std::max(noise_max, 0.1);
  b.x1 = std::max(noise_max, 0.1) * 1.1;
  b.y0 = t_min - 0.05;
  b.y1 = std::max(t_max, grid.duration + 0.2) + 0.1;
  for (PriorMode m : {PriorMode::kBoth, PriorMode::kEnergy, PriorMode::kPrecision}) {
    cv::Point prev(-1, -1);
    for (const auto& c : choices) {
      if (c.mode != m || c.draws == 0) continue;
      const cv::Point p = b.px(c.noise_cm, c.mean_time);
      cv::line(img, b.px(c.noise_cm, c.mean_time - c.std_time),
               b.px(c.noise_cm, c.mean_time + c.std_time), colour(m), 1);
      cv::circle(img, p, 4, colour(m), cv::FILLED, cv::LINE_AA);
      if (prev.x >= 0) cv::line(img, prev, p, colour(m), 2, cv::LINE_AA);
      prev = p;
    }
  }
  draw_axes(img, b, "measurement noise (cm, per axis)", "interception - plan (s)",
            "interception time against noise");
  text(img, "Fig 3-11: the interception point chosen as the noise grows, per prior", {20, 35},
       0.65);
  legend(img, {b.area.x + b.area.width - 160, b.area.y + 20},
         {{"energy and precision", kBlue}, {"energy only", kBlack}, {"precision only", kRed}});
  return img;
}

}  // namespace proprio::planning
