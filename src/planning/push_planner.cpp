#include "proprio/planning/push_planner.hpp"
#include "proprio/geometry/depth_pixels.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <opencv2/imgproc.hpp>

#include "proprio/core/error.hpp"
#include "proprio/core/random.hpp"
#include "proprio/robot/inverse_kinematics.hpp"

namespace proprio::planning {

namespace {
constexpr double kTransitLift = 0.06;   // m: robot::PushMotionOptions::lift
constexpr int kCorridorLines = 5;       // lines across the swept corridor
constexpr double kEdgeWeight = 1.0;     // kEdge: cost per image side of distance to the edge
constexpr double kMetresToMm = 1000.0;  // hull computation in integer-free float mm
// Rate at which the chosen path's whole motion is checked, Hz: the simulated controller's,
// so that a joint jump (an IK branch change) on the way is caught as it would be there.
constexpr double kMotionCheckRate = 500.0;
// A path's lack of clearance (m) against its feature-density cost (features x m, 0.1-2 for most
// paths): a millimetre of it outweighs the density of a crowded path.
constexpr double kBlockedWeight = 1000.0;
// A push through a waypoint is taken only when it is clearer than the direct one by this much
// (as cost: 3 mm of clearance): it spends a push of the loop.
constexpr double kViaCost = 3.0;
// tall_start_clearance: added to the score of a push from farther behind, so that it ranks after
// every other path.
constexpr double kTallFarScore = 1e6;
// Waypoints: turned this far off the direct line either way, rad, and this far from p_c, m.
constexpr double kViaLeast = 20.0 * std::numbers::pi / 180.0;
constexpr double kViaMost = 100.0 * std::numbers::pi / 180.0;
constexpr double kViaNear = 0.04;
constexpr double kViaFar = 0.10;
// Shortened pushes (sweep_margin): the target is brought back toward the object in these steps, m.
constexpr double kShortStep = 0.005;
// hand_raise: the tip's height steps, m.
constexpr double kRaiseStep = 0.005;
// Depth pixels sampled every this many pixels in each direction for a blob's footprint.
constexpr int kDepthStep = 2;
// Depth pixels sampled for depth_tops: every one (its 4 mm cells all filled on a far top).
constexpr int kTopStep = 1;
// The top's height: this quantile of the object's depth points' heights (a few stray points at
// a silhouette's edge do not set it).
constexpr double kTopQuantile = 0.98;
// topple_offset's steps sideways, m.
constexpr double kToppleStep = 0.01;

double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}
}  // namespace

void PushPlanOptions::validate() const {
  core::check_field_bounds(*this, "push planning");
  blobs.validate();
  require(patch >= 2, "push planning: patch must be >= 2 px");
  require(min_approach <= max_approach, "push planning: min_approach must be <= max_approach");
  require(min_distance <= max_distance, "push planning: min_distance must be <= max_distance");
}

std::vector<cv::KeyPoint> textured_points(const cv::Mat& image, const PushPlanOptions& options,
                                          const cv::Mat& ignore) {
  require(!image.empty() && image.depth() == CV_8U, "textured points: need an 8-bit image");
  options.validate();
  cv::Mat grey;
  if (image.channels() == 3) {
    cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
  } else {
    grey = image;
  }
  cv::Mat sum;
  cv::Mat sqsum;
  cv::integral(grey, sum, sqsum, CV_64F, CV_64F);
  const int half = options.patch / 2;
  const double n = static_cast<double>(options.patch) * options.patch;
  const double min_var = options.min_contrast * options.min_contrast;
  cv::Mat1b skip;
  if (!ignore.empty()) {
    require(ignore.size() == image.size() && ignore.type() == CV_8U,
            "textured points: the ignore mask must be CV_8U of the image's size");
    cv::dilate(
        ignore, skip,
        cv::getStructuringElement(cv::MORPH_RECT, cv::Size(options.patch + 1, options.patch + 1)));
  }
  std::vector<cv::KeyPoint> out;
  // A point's patch spans [x - half, x - half + patch) (an odd patch has one more column to the
  // right), so the last point is the one whose patch still ends inside the image.
  for (int y = half; y - half + options.patch <= grey.rows; y += options.grid_step) {
    for (int x = half; x - half + options.patch <= grey.cols; x += options.grid_step) {
      const int x0 = x - half;
      const int y0 = y - half;
      const int x1 = x0 + options.patch;
      const int y1 = y0 + options.patch;
      const double s = sum.at<double>(y1, x1) - sum.at<double>(y0, x1) - sum.at<double>(y1, x0) +
                       sum.at<double>(y0, x0);
      const double q = sqsum.at<double>(y1, x1) - sqsum.at<double>(y0, x1) -
                       sqsum.at<double>(y1, x0) + sqsum.at<double>(y0, x0);
      const double var = q / n - (s / n) * (s / n);
      if (var >= min_var && (skip.empty() || skip(y, x) == 0)) {
        out.emplace_back(static_cast<float>(x), static_cast<float>(y),
                         static_cast<float>(options.patch));
      }
    }
  }
  return out;
}

namespace {

bool inside_region(const Eigen::Vector2d& p, const TableRegion& r, double margin) {
  return p.x() >= r.min.x() + margin && p.x() <= r.max.x() - margin &&
         p.y() >= r.min.y() + margin && p.y() <= r.max.y() - margin;
}

// The convex hull of points (any units), counter-clockwise in their own axes.
std::vector<Eigen::Vector2d> convex_hull(const std::vector<Eigen::Vector2d>& points, double scale) {
  std::vector<cv::Point2f> p;
  p.reserve(points.size());
  for (const auto& x : points) {
    p.emplace_back(static_cast<float>(x.x() * scale), static_cast<float>(x.y() * scale));
  }
  std::vector<cv::Point2f> h;
  cv::convexHull(p, h, /*clockwise=*/false);
  std::vector<Eigen::Vector2d> out;
  out.reserve(h.size());
  for (const auto& q : h) out.emplace_back(q.x / scale, q.y / scale);
  return out;
}

// The footprint of a blob seen from camera centre `eye` (world): its hull back-projected onto the
// table top, cut at the lateral width beyond the edge nearest the camera; its centre in `centre`.
std::vector<Eigen::Vector2d> footprint(const std::vector<Eigen::Vector2d>& table_hull,
                                       const Eigen::Vector2d& eye, Eigen::Vector2d& centre) {
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& p : table_hull) mean += p;
  mean /= static_cast<double>(table_hull.size());
  Eigen::Vector2d u = mean - eye;  // away from the camera, along the table
  if (u.norm() < 1e-9) u = Eigen::Vector2d::UnitY();
  u.normalize();
  const Eigen::Vector2d v(-u.y(), u.x());
  double near = std::numeric_limits<double>::infinity();
  double vmin = near;
  double vmax = -near;
  for (const auto& p : table_hull) {
    near = std::min(near, p.dot(u));
    vmin = std::min(vmin, p.dot(v));
    vmax = std::max(vmax, p.dot(v));
  }
  const double half = 0.5 * (vmax - vmin);
  const double far = near + 2 * half;
  centre = (near + half) * u + 0.5 * (vmin + vmax) * v;
  std::vector<Eigen::Vector2d> cut;
  for (const auto& p : table_hull) {
    const double s = std::min(p.dot(u), far);
    cut.push_back(s * u + p.dot(v) * v);
  }
  return cut;
}

// The footprint of a blob from its base contour (CentreMethod::kBase). Back-projected onto the
// table top, every point of a vertical edge lies on one ray from the camera's foot `eye` (the
// point under the camera), so the features' bearings around `eye` span the footprint's bearings
// whatever their height; the nearest feature of a bearing (the lowest in the image) is the
// object's foot there. The two outermost bearings' feet are the footprint's tangent points seen
// from `eye`; for a footprint symmetric about its centre (a box, a cylinder) p_c is their
// midpoint moved away from the eye by r^2 / D (a circle of radius r seen from distance D: the
// chord of its tangent points lies r^2 / D nearer). The footprint is the feet (one per bearing
// bin of `bin` rad, the angle of one feature-grid step) and their reflection through p_c.
// Throws Error above the horizon.
std::vector<Eigen::Vector2d> base_footprint(const std::vector<Eigen::Vector2d>& pixels,
                                            const geometry::Camera& camera,
                                            const Eigen::Vector2d& eye, double grid_step,
                                            Eigen::Vector2d& centre) {
  struct Foot {
    double bearing;
    double range;
    Eigen::Vector2d p;
  };
  std::vector<Foot> feet;
  feet.reserve(pixels.size());
  Eigen::Vector2d mean_pixel = Eigen::Vector2d::Zero();
  for (const auto& px : pixels) {
    const Eigen::Vector2d p = robot::pixel_to_table(camera, px, 0.0);
    const Eigen::Vector2d d = p - eye;
    feet.push_back({std::atan2(d.y(), d.x()), d.norm(), p});
    mean_pixel += px;
  }
  mean_pixel /= static_cast<double>(pixels.size());
  // A grid step's angle at the blob: the bins and the outermost bearings' tolerance.
  const Eigen::Vector2d a = robot::pixel_to_table(camera, mean_pixel, 0.0) - eye;
  const Eigen::Vector2d b =
      robot::pixel_to_table(camera, mean_pixel + Eigen::Vector2d(grid_step, 0.0), 0.0) - eye;
  const double bin = std::max(1e-4, std::abs(std::atan2(cross(a, b), a.dot(b))));
  std::sort(feet.begin(), feet.end(),
            [](const Foot& x, const Foot& y) { return x.bearing < y.bearing; });
  const auto nearest = [&](double from, double to) {
    const Foot* best = nullptr;
    for (const Foot& f : feet) {
      if (f.bearing >= from && f.bearing <= to && (best == nullptr || f.range < best->range)) {
        best = &f;
      }
    }
    return best;
  };
  const double lo = feet.front().bearing;
  const double hi = feet.back().bearing;
  const Eigen::Vector2d left = nearest(lo, lo + bin)->p;
  const Eigen::Vector2d right = nearest(hi - bin, hi)->p;
  const Eigen::Vector2d mid = 0.5 * (left + right);
  const double r = 0.5 * (right - left).norm();
  const double dist = (mid - eye).norm();
  // The r^2 / D term is wrong for a long object near the camera (its tangent points are its
  // ends) but right on average: without it the centres of tables 1-30 were 34.9 mm off, with it
  // 18.7 mm (median).
  centre = mid;
  if (dist > r) centre += (r * r / dist) * (mid - eye) / dist;
  std::vector<Eigen::Vector2d> out;
  for (double from = lo; from <= hi; from += bin) {
    if (const Foot* f = nearest(from, from + bin)) out.push_back(f->p);
  }
  out.push_back(left);
  out.push_back(right);
  const std::size_t n = out.size();
  for (std::size_t i = 0; i < n; ++i) out.push_back(2.0 * centre - out[i]);
  return out;
}

// The putative object of one blob, or none when it does not map onto the table.
std::optional<PutativeObject> putative_object(const features::Blob& blob,
                                              const std::vector<cv::KeyPoint>& features,
                                              const geometry::Camera& camera,
                                              const TableRegion& region,
                                              const PushPlanOptions& options,
                                              const cv::Mat& depth) {
  PutativeObject o;
  o.box = blob.box;
  o.mask = blob.mask;
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  for (const int i : blob.features) {
    const cv::Point2f& pt = features.at(static_cast<std::size_t>(i)).pt;
    o.pixels.emplace_back(pt.x, pt.y);
    sum += o.pixels.back();
  }
  if (o.pixels.size() < 3) return std::nullopt;
  o.centre_pixel = sum / static_cast<double>(o.pixels.size());
  o.hull_pixels = convex_hull(o.pixels, 1.0);
  std::vector<Eigen::Vector2d> table;
  try {
    std::vector<Eigen::Vector2d> extent;
    for (const auto& h : o.hull_pixels) {
      extent.push_back(robot::pixel_to_table(camera, h, options.centre_height));
    }
    o.extent = convex_hull(extent, kMetresToMm);
    if (options.centre == CentreMethod::kFeatures) {
      o.centre = robot::pixel_to_table(camera, o.centre_pixel, options.centre_height);
      table = extent;
    } else if (options.centre == CentreMethod::kBase) {
      table = base_footprint(o.pixels, camera, camera.center().head<2>(),
                             static_cast<double>(options.grid_step), o.centre);
    } else {
      for (const auto& h : o.hull_pixels) table.push_back(robot::pixel_to_table(camera, h, 0.0));
      table = footprint(table, camera.center().head<2>(), o.centre);
    }
  } catch (const Error&) {
    return std::nullopt;  // above the horizon: not on the table
  }
  if (!depth.empty()) {
    // An RGB-D look: the footprint and height measured from the depth points inside the
    // features' hull (every other pixel: 3-4 mm apart on the table, enough for a hull).
    if (auto m = measure_footprint(depth, camera, o.hull_pixels, o.mask, o.box, kDepthStep)) {
      o.centre = m->centre;
      table = std::move(m->hull);
      o.height = m->height;
    }
  }
  if (!inside_region(o.centre, region, 0.0) || o.centre.norm() < region.base_radius) {
    return std::nullopt;
  }
  o.hull = convex_hull(table, kMetresToMm);
  if (o.hull.size() < 3 || o.extent.size() < 3) return std::nullopt;
  return o;
}

}  // namespace

std::vector<Eigen::Vector3d> object_depth_points(const cv::Mat& depth,
                                                 const geometry::Camera& camera,
                                                 const std::vector<Eigen::Vector2d>& hull_pixels,
                                                 const cv::Mat& mask, cv::Rect box, int step) {
  require(depth.type() == CV_32FC1,
          "object_depth_points: the depth image must be CV_32FC1 (metres)");
  require(step >= 1, "object_depth_points: step must be at least 1");
  require(mask.empty() || (mask.type() == CV_8U && mask.size() == box.size()),
          "object_depth_points: the mask must be 8-bit of its box's size");
  std::vector<Eigen::Vector3d> out;
  if (hull_pixels.size() < 3) return out;
  std::vector<cv::Point2f> poly;
  poly.reserve(hull_pixels.size());
  for (const auto& h : hull_pixels) {
    poly.emplace_back(static_cast<float>(h.x()), static_cast<float>(h.y()));
  }
  const cv::Rect image(0, 0, depth.cols, depth.rows);
  const cv::Rect bounds = cv::boundingRect(poly) & image;
  const geometry::DepthPixels pixels(camera);
  for (int v = bounds.y; v < bounds.y + bounds.height; v += step) {
    const auto* row = depth.ptr<float>(v);
    for (int u = bounds.x; u < bounds.x + bounds.width; u += step) {
      const double d = row[u];
      if (!std::isfinite(d) || d <= 0) continue;
      if (!mask.empty()) {
        const cv::Point q(u - box.x, v - box.y);
        if (q.x < 0 || q.y < 0 || q.x >= mask.cols || q.y >= mask.rows ||
            mask.at<std::uint8_t>(q) == 0) {
          continue;
        }
      }
      if (cv::pointPolygonTest(poly, cv::Point2f(static_cast<float>(u), static_cast<float>(v)),
                               false) < 0) {
        continue;
      }
      const Eigen::Vector3d x = pixels.world(u, v, d);
      if (x.z() < kObjectLeastHeight) continue;
      out.push_back(x);
    }
  }
  return out;
}

std::optional<MeasuredFootprint> measure_footprint(const cv::Mat& depth,
                                                   const geometry::Camera& camera,
                                                   const std::vector<Eigen::Vector2d>& hull_pixels,
                                                   const cv::Mat& mask, cv::Rect box, int step) {
  const std::vector<Eigen::Vector3d> points =
      object_depth_points(depth, camera, hull_pixels, mask, box, step);
  std::vector<Eigen::Vector2d> xy;
  std::vector<double> z;
  xy.reserve(points.size());
  z.reserve(points.size());
  for (const auto& x : points) {
    xy.push_back(x.head<2>());
    z.push_back(x.z());
  }
  if (static_cast<int>(xy.size()) < kFootprintLeastPoints) return std::nullopt;
  MeasuredFootprint m;
  m.points = static_cast<int>(xy.size());
  const auto top = static_cast<std::ptrdiff_t>(kTopQuantile * static_cast<double>(z.size() - 1));
  std::nth_element(z.begin(), z.begin() + top, z.end());
  m.height = z[static_cast<std::size_t>(top)];
  m.hull = convex_hull(xy, kMetresToMm);
  // The hull's area centroid (the points' mean would lean toward the sides the camera sees).
  double area = 0;
  Eigen::Vector2d c = Eigen::Vector2d::Zero();
  for (std::size_t i = 0; i < m.hull.size(); ++i) {
    const Eigen::Vector2d& a = m.hull[i];
    const Eigen::Vector2d& b = m.hull[(i + 1) % m.hull.size()];
    const double w = cross(a, b);
    area += w;
    c += w * (a + b);
  }
  if (m.hull.size() < 3 || std::abs(area) < 1e-10) return std::nullopt;  // a line of points
  m.centre = c / (3.0 * area);
  return m;
}

PlanningView make_planning_view(const std::vector<cv::KeyPoint>& features,
                                const geometry::Camera& camera, const TableRegion& region,
                                const PushPlanOptions& options, const cv::Mat& depth) {
  options.validate();
  require(camera.width > 0 && camera.height > 0, "planning view: the camera has no image size");
  PlanningView view;
  view.camera = camera;
  view.image_size = cv::Size(camera.width, camera.height);
  if (!depth.empty()) {
    require(depth.type() == CV_32FC1 && depth.size() == view.image_size,
            "planning view: the depth image must be CV_32FC1 (metres) of the camera's image size "
            "(" +
                std::to_string(camera.width) + " x " + std::to_string(camera.height) + ")");
    view.depth = depth;
  }
  // The table point of each feature: the viewing ray X = C + s R^T K^-1 (u, v, 1) meets z = 0
  // (eqs 3.13-3.17 in closed form; back_project_to_plane's SVD per point would cost more than the
  // rest of the view).
  const Eigen::Matrix3d ray = camera.R.transpose() * camera.K.inverse();
  const Eigen::Vector3d eye = camera.center();
  for (const cv::KeyPoint& k : features) {
    const Eigen::Vector3d d = ray * Eigen::Vector3d(k.pt.x, k.pt.y, 1.0);
    if (d.z() >= -1e-12) continue;  // at or above the horizon: not on the table
    const double s = -eye.z() / d.z();
    if (s <= 0) continue;
    const Eigen::Vector2d t = (eye + s * d).head<2>();
    if (inside_region(t, region, region.edge_band)) view.features.push_back(k);
  }
  const std::vector<cv::KeyPoint>& kept = view.features;
  view.density = features::feature_density(kept, view.image_size, options.blobs);
  for (const features::Blob& b : features::find_blobs(kept, view.image_size, options.blobs)) {
    if (auto o = putative_object(b, kept, camera, region, options, view.depth)) {
      view.objects.push_back(std::move(*o));
    }
  }
  if (options.depth_split > 0) (void)split_by_depth(view, region, options);
  return view;
}

DepthTops depth_tops(const cv::Mat& depth, const geometry::Camera& camera, const cv::Mat& mask,
                     cv::Rect box, double jump, int step) {
  require(depth.type() == CV_32FC1, "depth_tops: the depth image must be CV_32FC1 (metres)");
  require(step >= 1, "depth_tops: step must be at least 1");
  require(std::isfinite(jump) && jump > 0, "depth_tops: jump must be positive");
  require(!mask.empty() && mask.type() == CV_8U && mask.size() == box.size(),
          "depth_tops: the mask must be 8-bit of its box's size");
  DepthTops out;
  out.labels = cv::Mat1i(box.size(), 0);
  // The depth points on objects: their pixel (in the box), table x y and height.
  struct Point {
    cv::Point q;
    Eigen::Vector2d xy;
    double z;
  };
  std::vector<Point> points;
  const cv::Rect image(0, 0, depth.cols, depth.rows);
  const geometry::DepthPixels pixels(camera);
  for (int y = 0; y < box.height; y += step) {
    for (int x = 0; x < box.width; x += step) {
      const cv::Point p(box.x + x, box.y + y);
      if (mask.at<std::uint8_t>(y, x) == 0 || !image.contains(p)) continue;
      const double d = depth.at<float>(p);
      if (!geometry::depth_measured(d)) continue;
      const Eigen::Vector3d w = pixels.world(p.x, p.y, d);
      if (w.z() < kObjectLeastHeight) continue;
      points.push_back({cv::Point(x, y), w.head<2>(), w.z()});
    }
  }
  if (static_cast<int>(points.size()) < kFootprintLeastPoints) return out;
  // The top-down map: the highest point per cell.
  Eigen::Vector2d lo = points.front().xy;
  Eigen::Vector2d hi = lo;
  for (const Point& p : points) {
    lo = lo.cwiseMin(p.xy);
    hi = hi.cwiseMax(p.xy);
  }
  const auto cell_of = [&](const Eigen::Vector2d& xy) {
    return cv::Point(static_cast<int>((xy.x() - lo.x()) / kTopCell),
                     static_cast<int>((xy.y() - lo.y()) / kTopCell));
  };
  const cv::Point far = cell_of(hi);
  cv::Mat1f top(far.y + 1, far.x + 1, -1.0F);
  for (const Point& p : points) {
    float& t = top(cell_of(p.xy));
    t = std::max(t, static_cast<float>(p.z));
  }
  // Tops: cells within two cells of each other (an empty cell between two sampled ones does not
  // part them) whose heights differ by less than the jump (a flood fill).
  cv::Mat1i part(top.size(), 0);
  int parts = 0;
  std::vector<cv::Point> stack;
  for (int y = 0; y < top.rows; ++y) {
    for (int x = 0; x < top.cols; ++x) {
      if (top(y, x) < 0 || part(y, x) != 0) continue;
      part(y, x) = ++parts;
      stack.assign(1, cv::Point(x, y));
      while (!stack.empty()) {
        const cv::Point c = stack.back();
        stack.pop_back();
        for (int dy = -2; dy <= 2; ++dy) {
          for (int dx = -2; dx <= 2; ++dx) {
            const cv::Point n(c.x + dx, c.y + dy);
            if (n.x < 0 || n.y < 0 || n.x >= top.cols || n.y >= top.rows) continue;
            if (top(n) < 0 || part(n) != 0 || std::abs(top(n) - top(c)) >= jump) continue;
            part(n) = parts;
            stack.push_back(n);
          }
        }
      }
    }
  }
  // Tops that keep kTopLeastArea once eroded by a cell.
  std::vector<int> top_of(static_cast<std::size_t>(parts) + 1, 0);
  const double least_cells = kTopLeastArea / (kTopCell * kTopCell);
  for (int k = 1; k <= parts; ++k) {
    const cv::Mat1b cells = part == k;
    if (cv::countNonZero(cells) < least_cells) continue;
    cv::Mat1b closed;
    cv::Mat1b inner;
    cv::morphologyEx(cells, closed, cv::MORPH_CLOSE, cv::Mat());
    cv::erode(closed, inner, cv::Mat(), cv::Point(-1, -1), 1, cv::BORDER_CONSTANT, 0);
    if (cv::countNonZero(inner) >= least_cells) top_of[static_cast<std::size_t>(k)] = ++out.count;
  }
  if (out.count == 0) return out;
  // Every mask pixel goes to the top of the nearest sampled point that lies on one.
  cv::Mat1b seeds(box.size(), 255);
  for (const Point& p : points) {
    if (top_of[static_cast<std::size_t>(part(cell_of(p.xy)))] > 0) seeds(p.q) = 0;
  }
  cv::Mat1f distance;
  cv::Mat1i nearest;
  cv::distanceTransform(seeds, distance, nearest, cv::DIST_L2, cv::DIST_MASK_5,
                        cv::DIST_LABEL_PIXEL);
  double most = 0;
  cv::minMaxLoc(nearest, nullptr, &most);
  std::vector<int> label_top(static_cast<std::size_t>(most) + 1, 0);
  for (const Point& p : points) {
    const int t = top_of[static_cast<std::size_t>(part(cell_of(p.xy)))];
    if (t > 0) label_top[static_cast<std::size_t>(nearest(p.q))] = t;
  }
  for (int y = 0; y < box.height; ++y) {
    for (int x = 0; x < box.width; ++x) {
      if (mask.at<std::uint8_t>(y, x) != 0) {
        out.labels(y, x) = label_top[static_cast<std::size_t>(nearest(y, x))];
      }
    }
  }
  return out;
}

int split_by_depth(PlanningView& view, const TableRegion& region, const PushPlanOptions& options) {
  if (options.depth_split <= 0 || view.depth.empty()) return 0;
  std::vector<cv::Mat> regions;
  for (const PutativeObject& o : view.objects) {
    const DepthTops t =
        depth_tops(view.depth, view.camera, o.mask, o.box, options.depth_split, kTopStep);
    if (t.count < 2) continue;
    for (int k = 1; k <= t.count; ++k) {
      cv::Mat r(view.image_size, CV_8U, cv::Scalar(0));
      r(o.box).setTo(255, t.labels == k);
      regions.push_back(r);
    }
  }
  if (regions.empty()) return 0;
  const std::size_t before = view.objects.size();
  (void)split_putative_objects(view, regions, options.blobs.min_features, region, options);
  return static_cast<int>(view.objects.size() - before);
}

std::vector<int> split_putative_objects(PlanningView& view, const std::vector<cv::Mat>& regions,
                                        int min_features, const TableRegion& region,
                                        const PushPlanOptions& options) {
  require(min_features >= 1, "split_putative_objects: min_features must be at least 1");
  for (const cv::Mat& r : regions) {
    require(r.empty() || (r.type() == CV_8U && r.size() == view.image_size),
            "split_putative_objects: a region must be an 8-bit mask of the view's image size");
  }
  const auto nr = static_cast<int>(regions.size());
  const auto in_region = [&](const cv::Point& q) {
    for (int r = 0; r < nr; ++r) {
      const cv::Mat& m = regions[static_cast<std::size_t>(r)];
      if (!m.empty() && m.at<uchar>(q) != 0) return r;
    }
    return -1;
  };
  const cv::Rect image(cv::Point(0, 0), view.image_size);
  const std::size_t n_objects = view.objects.size();
  for (std::size_t b = 0; b < n_objects; ++b) {
    const PutativeObject& o = view.objects[b];
    // The blob's features (indices into view.features) and the region each lies in.
    std::vector<int> members;
    std::vector<int> owner;
    for (std::size_t k = 0; k < view.features.size(); ++k) {
      const cv::Point q(static_cast<int>(std::lround(view.features[k].pt.x)),
                        static_cast<int>(std::lround(view.features[k].pt.y)));
      if (!o.box.contains(q) || !image.contains(q) || o.mask(q - o.box.tl()) == 0) continue;
      members.push_back(static_cast<int>(k));
      owner.push_back(in_region(q));
    }
    // The rest: the blob's mask outside every region, in connected parts.
    cv::Mat1b rest = o.mask.clone();
    for (const cv::Mat& m : regions) {
      if (!m.empty()) rest.setTo(0, m(o.box));
    }
    cv::Mat1i labels;
    const int n_parts = cv::connectedComponents(rest, labels, 8, CV_32S);
    // Parts: regions 0..nr-1, then rest components 1..n_parts-1 as nr + label - 1.
    const int total = nr + std::max(0, n_parts - 1);
    std::vector<int> part_of(members.size(), -1);
    std::vector<int> count(static_cast<std::size_t>(total), 0);
    for (std::size_t i = 0; i < members.size(); ++i) {
      int part = owner[i];
      if (part < 0) {
        const cv::KeyPoint& k = view.features[static_cast<std::size_t>(members[i])];
        const cv::Point q(static_cast<int>(std::lround(k.pt.x)) - o.box.x,
                          static_cast<int>(std::lround(k.pt.y)) - o.box.y);
        const int l = labels(q);
        if (l > 0) part = nr + l - 1;
      }
      part_of[i] = part;
      if (part >= 0) ++count[static_cast<std::size_t>(part)];
    }
    std::vector<int> big;
    for (int p = 0; p < total; ++p) {
      if (count[static_cast<std::size_t>(p)] >= min_features) big.push_back(p);
    }
    if (big.size() < 2) continue;
    std::sort(big.begin(), big.end(), [&](int x, int y) {
      return count[static_cast<std::size_t>(x)] > count[static_cast<std::size_t>(y)];
    });
    std::vector<PutativeObject> made;
    for (const int p : big) {
      features::Blob part;
      cv::Mat1b mask(o.box.size(), 0);
      if (p < nr) {
        o.mask.copyTo(mask, regions[static_cast<std::size_t>(p)](o.box));
      } else {
        mask.setTo(255, labels == (p - nr + 1));
      }
      for (std::size_t i = 0; i < members.size(); ++i) {
        // Points of the small parts go with the largest.
        const bool small =
            part_of[i] < 0 || std::find(big.begin(), big.end(), part_of[i]) == big.end();
        if (part_of[i] == p || (small && p == big.front())) part.features.push_back(members[i]);
      }
      const cv::Rect inner = cv::boundingRect(mask);
      if (inner.area() == 0) continue;
      part.box = inner + o.box.tl();
      part.mask = mask(inner).clone();
      if (auto po =
              putative_object(part, view.features, view.camera, region, options, view.depth)) {
        made.push_back(std::move(*po));
      }
    }
    if (made.size() < 2) continue;
    view.objects[b] = std::move(made.front());
    for (std::size_t i = 1; i < made.size(); ++i) view.objects.push_back(std::move(made[i]));
  }
  // Per region, the putative object holding most of its points.
  std::vector<int> found(regions.size(), -1);
  for (int r = 0; r < nr; ++r) {
    const cv::Mat& m = regions[static_cast<std::size_t>(r)];
    if (m.empty()) continue;
    int best = min_features - 1;
    for (std::size_t b = 0; b < view.objects.size(); ++b) {
      int n = 0;
      for (const auto& px : view.objects[b].pixels) {
        const cv::Point q(static_cast<int>(std::lround(px.x())),
                          static_cast<int>(std::lround(px.y())));
        if (image.contains(q) && m.at<uchar>(q) != 0) ++n;
      }
      if (n > best) {
        best = n;
        found[static_cast<std::size_t>(r)] = static_cast<int>(b);
      }
    }
  }
  return found;
}

PlanningView look_for_objects(const robot::Look& look, const TableRegion& region,
                              const PushPlanOptions& options) {
  cv::Mat depth = look.depth;
  if (!depth.empty() && !look.arm_mask.empty() && look.arm_mask.size() == depth.size()) {
    depth = depth.clone();
    depth.setTo(0, look.arm_mask);  // the arm's own body is no object's
  }
  return make_planning_view(textured_points(look.image, options, look.arm_mask), look.camera,
                            region, options, depth);
}

namespace {

// Mean absolute grey-level change over a 9 x 9 px window between two 8-bit looks.
cv::Mat1f motion_image(const cv::Mat& before, const cv::Mat& after) {
  require(!before.empty() && before.size() == after.size() && before.type() == after.type() &&
              before.depth() == CV_8U,
          "motion: the two looks must be 8-bit images of one size");
  cv::Mat gb;
  cv::Mat ga;
  if (before.channels() == 3) {
    cv::cvtColor(before, gb, cv::COLOR_BGR2GRAY);
    cv::cvtColor(after, ga, cv::COLOR_BGR2GRAY);
  } else {
    gb = before;
    ga = after;
  }
  cv::Mat diff;
  cv::absdiff(gb, ga, diff);
  cv::Mat1f mean;
  cv::boxFilter(diff, mean, CV_32F, cv::Size(9, 9));
  return mean;
}

bool moved_at(const cv::Mat1f& motion, float x, float y) {
  const int u = std::clamp(static_cast<int>(std::lround(x)), 0, motion.cols - 1);
  const int v = std::clamp(static_cast<int>(std::lround(y)), 0, motion.rows - 1);
  return motion(v, u) >= kMotionChange;
}

}  // namespace

double moved_share(const cv::Mat& before, const cv::Mat& after, const PutativeObject& object) {
  const cv::Mat1f motion = motion_image(before, after);
  if (object.pixels.empty()) return 0.0;
  std::size_t moved = 0;
  for (const auto& p : object.pixels) {
    moved += moved_at(motion, static_cast<float>(p.x()), static_cast<float>(p.y())) ? 1 : 0;
  }
  return static_cast<double>(moved) / static_cast<double>(object.pixels.size());
}

namespace {

// The largest distance from c to a vertex of `hull`: the radius of a circle about c holding it.
double hull_radius(const std::vector<Eigen::Vector2d>& hull, const Eigen::Vector2d& c) {
  double r = 0;
  for (const auto& h : hull) r = std::max(r, (h - c).norm());
  return r;
}

// Distance of p to the convex polygon `hull` (either orientation): 0 inside.
double distance_to_polygon(const std::vector<Eigen::Vector2d>& hull, const Eigen::Vector2d& p) {
  const std::size_t n = hull.size();
  int positive = 0;
  int negative = 0;
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d& a = hull[i];
    const Eigen::Vector2d e = hull[(i + 1) % n] - a;
    const double c = cross(e, p - a);
    positive += c > 0 ? 1 : 0;
    negative += c < 0 ? 1 : 0;
    const double t = std::clamp((p - a).dot(e) / std::max(e.squaredNorm(), 1e-18), 0.0, 1.0);
    best = std::min(best, (a + t * e - p).norm());
  }
  return positive > 0 && negative > 0 ? best : 0.0;
}

// Distance of p to the segment a-b.
double point_segment(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d e = b - a;
  const double t = std::clamp((p - a).dot(e) / std::max(e.squaredNorm(), 1e-18), 0.0, 1.0);
  return (a + t * e - p).norm();
}

// Distance between the segments a0-a1 and b0-b1: 0 when they cross.
double segment_distance(const Eigen::Vector2d& a0, const Eigen::Vector2d& a1,
                        const Eigen::Vector2d& b0, const Eigen::Vector2d& b1) {
  const double d1 = cross(a1 - a0, b0 - a0);
  const double d2 = cross(a1 - a0, b1 - a0);
  const double d3 = cross(b1 - b0, a0 - b0);
  const double d4 = cross(b1 - b0, a1 - b0);
  if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0))) {
    return 0.0;
  }
  return std::min({point_segment(a0, b0, b1), point_segment(a1, b0, b1), point_segment(b0, a0, a1),
                   point_segment(b1, a0, a1)});
}

}  // namespace

double polygon_distance(const std::vector<Eigen::Vector2d>& a,
                        const std::vector<Eigen::Vector2d>& b) {
  if (a.empty() || b.empty()) return std::numeric_limits<double>::infinity();
  if (a.size() >= 3) {
    for (const auto& p : b) {
      if (distance_to_polygon(a, p) == 0.0) return 0.0;
    }
  }
  if (b.size() >= 3) {
    for (const auto& p : a) {
      if (distance_to_polygon(b, p) == 0.0) return 0.0;
    }
  }
  // Edges (a point is a segment of no length; two points one segment).
  const auto edges = [](const std::vector<Eigen::Vector2d>& v) {
    return v.size() <= 2 ? std::size_t{1} : v.size();
  };
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < edges(a); ++i) {
    const Eigen::Vector2d& a0 = a[i];
    const Eigen::Vector2d& a1 = a[(i + 1) % a.size()];
    for (std::size_t j = 0; j < edges(b); ++j) {
      best = std::min(best, segment_distance(a0, a1, b[j], b[(j + 1) % b.size()]));
    }
  }
  return best;
}

bool descent_blocked(const Eigen::Vector2d& start, const std::vector<Eigen::Vector2d>& hull,
                     const std::vector<std::vector<Eigen::Vector2d>>& others, double clearance) {
  const double r = start.norm();
  const Eigen::Vector2d low = r > kForearmReach ? Eigen::Vector2d(start * (1.0 - kForearmReach / r))
                                                : Eigen::Vector2d(0, 0);
  const std::vector<Eigen::Vector2d> forearm{start, low};
  if (hull.size() >= 3 && polygon_distance(forearm, hull) == 0.0) return true;
  return std::any_of(others.begin(), others.end(), [&](const std::vector<Eigen::Vector2d>& o) {
    return !o.empty() && polygon_distance(forearm, o) < clearance;
  });
}

bool descent_blocked(const Eigen::Vector2d& start, const PutativeObject& pushed,
                     const std::vector<const PutativeObject*>& others, double clearance,
                     double tip_height) {
  const double finger = tip_height + kFingerDrop - kDescentHeightMargin;
  const double palm = tip_height + kPalmDrop - kDescentHeightMargin;
  const double r = start.norm();
  const Eigen::Vector2d low = r > kForearmReach ? Eigen::Vector2d(start * (1.0 - kForearmReach / r))
                                                : Eigen::Vector2d(0, 0);
  const std::vector<Eigen::Vector2d> forearm{start, low};
  const std::vector<Eigen::Vector2d> hand{start};
  if (pushed.hull.size() >= 3) {
    if (!pushed.height) {
      if (polygon_distance(forearm, pushed.hull) == 0.0) return true;
    } else if (*pushed.height >= finger) {
      const bool tall = *pushed.height >= palm;
      const double reach = (tall ? kPalmReach : kFingerReach) + kDescentReachMargin;
      if (polygon_distance(hand, pushed.hull) < reach) return true;
      if (tall && polygon_distance(forearm, pushed.hull) == 0.0) return true;
    }
  }
  return std::any_of(others.begin(), others.end(), [&](const PutativeObject* o) {
    if (o == nullptr || o->hull.empty()) return false;
    if (!o->height) return polygon_distance(forearm, o->hull) < clearance;
    if (*o->height >= palm) {
      return polygon_distance(forearm, o->hull) < clearance ||
             polygon_distance(hand, o->hull) <
                 std::max(clearance, kPalmReach + kDescentReachMargin);
    }
    if (*o->height >= finger) {
      return polygon_distance(hand, o->hull) <
             std::max(clearance, kFingerReach + kDescentReachMargin);
    }
    return false;
  });
}

std::vector<Eigen::Vector2d> hand_footprint(const Eigen::Vector2d& start,
                                            const Eigen::Vector2d& end, double along,
                                            double across) {
  require(start.allFinite() && end.allFinite() && (end - start).norm() > 0,
          "hand footprint: the push must have a finite, non-zero length");
  require(std::isfinite(along) && std::isfinite(across) && along >= 0 && across >= 0,
          "hand footprint: the half extents must be finite and >= 0");
  const Eigen::Vector2d n = (end - start).normalized();
  const Eigen::Vector2d m(-n.y(), n.x());
  const Eigen::Vector2d a = start - along * n;
  const Eigen::Vector2d b = end + along * n;
  return {a - across * m, b - across * m, b + across * m, a + across * m};
}

PushContact push_contact(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector2d& centre,
                         const Eigen::Vector2d& direction, double tip_height, robot::JawLine jaws,
                         bool roll_across, double offset) {
  require(direction.allFinite() && std::abs(direction.norm() - 1.0) < 1e-6,
          "push_contact: the direction must be a unit vector");
  require(std::isfinite(tip_height) && tip_height >= 0,
          "push_contact: the tip's height must be finite and non-negative");
  const Eigen::Vector2d side(-direction.y(), direction.x());
  const bool across =
      jaws == robot::JawLine::kAcross || (jaws == robot::JawLine::kRobot && roll_across);
  const bool along = jaws == robot::JawLine::kAlong;
  const double jaw_low = tip_height + kFingerDrop;
  const double jaw_high = jaw_low + kJawLength;
  // The rod reaches up to the palm; the palm itself is left out (push_contact).
  const double palm_low = tip_height + kPalmDrop;
  // The pusher's axis position (along the push, from the centre) at which a part first touches a
  // point at (s along, l across, z); +inf when no part passes it.
  const auto disc = [](double s, double l, double r) {
    return std::abs(l) <= r ? s - std::sqrt(r * r - l * l)
                            : std::numeric_limits<double>::infinity();
  };
  struct Hit {
    double at;
    double z;
    bool jaws;
  };
  std::vector<Hit> hits;
  PushContact c;
  double base = -std::numeric_limits<double>::infinity();
  double any_base = -std::numeric_limits<double>::infinity();
  for (const Eigen::Vector3d& p : points) {
    const Eigen::Vector2d d0 = p.head<2>() - centre;
    for (const Eigen::Vector2d& d : {d0, Eigen::Vector2d(-d0)}) {  // the unseen side: reflected
      const double s = d.dot(direction);
      const double l = d.dot(side) - offset;
      const double z = p.z();
      any_base = std::max(any_base, s);
      if (z <= kFootHeight) base = std::max(base, s);
      if (z < tip_height) continue;  // the tip passes over it
      double rod =
          z < palm_low ? disc(s, l, kPusherRadius) : std::numeric_limits<double>::infinity();
      double hand = std::numeric_limits<double>::infinity();
      if (z >= jaw_low && z <= jaw_high) {
        if (across) {
          if (std::abs(l) >= kFingerReach - 0.01 && std::abs(l) <= kFingerReach)
            hand = s - kJawHalf;
        } else if (along) {
          if (std::abs(l) <= kJawHalf) hand = s - kFingerReach;
        } else {
          hand = disc(s, l, kFingerReach);
        }
      }
      if (std::isfinite(rod) || std::isfinite(hand)) {
        hits.push_back({std::min(rod, hand), z, hand < rod});
      }
    }
  }
  if (!std::isfinite(base)) base = any_base;
  c.base = std::max(0.001, std::isfinite(base) ? base : 0.0);
  if (hits.empty()) return c;
  const double first = std::min_element(hits.begin(), hits.end(), [](const Hit& a, const Hit& b) {
                         return a.at < b.at;
                       })->at;
  c.met = true;
  c.height = std::numeric_limits<double>::infinity();
  for (const Hit& h : hits) {
    if (h.at > first + kContactBand) continue;
    if (h.z < c.height) {
      c.height = h.z;
      c.jaws = h.jaws;
    }
  }
  c.ratio = kToppleFriction * c.height / c.base;
  return c;
}

double hand_lack(const robot::TablePush& push, bool jaws_along,
                 const std::vector<const PutativeObject*>& others, double margin) {
  if (margin <= 0 || others.empty()) return 0.0;
  require(std::isfinite(push.height), "hand lack: the tip's height must be finite");
  const Eigen::Vector2d& s = push.start;
  const Eigen::Vector2d& e = push.end;
  const double finger = push.height + kFingerDrop - kDescentHeightMargin;
  const double palm = push.height + kPalmDrop - kDescentHeightMargin;
  const std::vector<Eigen::Vector2d> jaws = jaws_along
                                                ? hand_footprint(s, e, kFingerReach, kJawHalf)
                                                : hand_footprint(s, e, kJawHalf, kFingerReach);
  const std::vector<Eigen::Vector2d> palm_box = jaws_along
                                                    ? hand_footprint(s, e, kPalmReach, kPalmHalf)
                                                    : hand_footprint(s, e, kPalmHalf, kPalmReach);
  const auto low = [](const Eigen::Vector2d& p) -> Eigen::Vector2d {
    const double r = p.norm();
    return r > kForearmReach ? Eigen::Vector2d(p * (1.0 - kForearmReach / r))
                             : Eigen::Vector2d(0, 0);
  };
  const std::vector<Eigen::Vector2d> forearm = convex_hull({s, low(s), e, low(e)}, kMetresToMm);
  const std::vector<Eigen::Vector2d> line{s, e};
  double lack = 0;
  for (const PutativeObject* o : others) {
    if (o == nullptr || o->hull.empty()) continue;
    const double h = o->height ? *o->height : std::numeric_limits<double>::infinity();
    if (h < finger) continue;
    // A part nearer than the margin counts the shortfall; running into the object, the margin
    // plus how far the pusher's line lies inside the part's reach of it.
    const auto part = [&](const std::vector<Eigen::Vector2d>& poly, double reach) {
      const double d = polygon_distance(poly, o->hull);
      if (d >= margin) return 0.0;
      if (d > 0) return margin - d;
      return margin + std::max(0.0, reach - polygon_distance(line, o->hull));
    };
    double l = part(jaws, kFingerReach);
    if (h >= palm) l = std::max({l, part(palm_box, kPalmReach), part(forearm, 0.0)});
    lack += l;
  }
  return lack;
}

double path_clearance(const robot::TablePush& push, const std::vector<Eigen::Vector2d>& hull,
                      const Eigen::Vector2d& centre, const Eigen::Vector2d& target,
                      const std::vector<std::vector<Eigen::Vector2d>>& others, double clearance,
                      double hand_clearance) {
  if (others.empty() || (clearance <= 0 && hand_clearance <= 0)) return 0.0;
  // The corridor: the hull at the start and carried to the target, and all between (convex).
  std::vector<Eigen::Vector2d> both = hull;
  for (const auto& h : hull) both.push_back(h + (target - centre));
  const std::vector<Eigen::Vector2d> corridor = convex_hull(both, kMetresToMm);
  const std::vector<Eigen::Vector2d> hand{push.start, push.end};
  // Bounding circles first: most other objects are far from the path (the plan's time).
  const auto circle = [](const std::vector<Eigen::Vector2d>& v, Eigen::Vector2d& c) {
    c = Eigen::Vector2d::Zero();
    for (const auto& p : v) c += p;
    c /= static_cast<double>(v.size());
    double r = 0;
    for (const auto& p : v) r = std::max(r, (p - c).norm());
    return r;
  };
  Eigen::Vector2d cc;
  Eigen::Vector2d hc;
  const double cr = circle(corridor, cc);
  const double hr = circle(hand, hc);
  double lack = 0;
  for (const auto& o : others) {
    Eigen::Vector2d oc;
    const double orad = circle(o, oc);
    if (clearance > 0 && (oc - cc).norm() - orad - cr < clearance) {
      // A neighbour nearer than `clearance` before the push (tables are crowded) is not held
      // against every path: only coming nearer to it than it already is counts, and running
      // into it at least `clearance`.
      const double before = std::min(clearance, polygon_distance(hull, o));
      const double swept = polygon_distance(corridor, o);
      lack += std::max(0.0, before - swept);
      if (swept == 0.0 && before > 0.0) lack += clearance - before;
    }
    if (hand_clearance > 0 && (oc - hc).norm() - orad - hr < hand_clearance) {
      lack += std::max(0.0, hand_clearance - polygon_distance(hand, o));
    }
  }
  return lack;
}

double sweep_turn(const std::vector<Eigen::Vector2d>& hull) {
  if (hull.size() < 3) return kSweepTurn;
  std::vector<cv::Point2f> p;
  p.reserve(hull.size());
  for (const auto& h : hull) {
    p.emplace_back(static_cast<float>(h.x() * kMetresToMm),
                   static_cast<float>(h.y() * kMetresToMm));
  }
  const cv::RotatedRect rect = cv::minAreaRect(p);
  const double w = std::min(rect.size.width, rect.size.height);
  const double l = std::max(rect.size.width, rect.size.height);
  if (w <= 0) return kSweepTurn;
  const double fill = std::abs(cv::contourArea(p)) / (w * l);
  return fill >= kBoxFill && l <= kBoxAspect * w ? kBoxTurn : kSweepTurn;
}

std::vector<Eigen::Vector2d> sweep_region(const std::vector<Eigen::Vector2d>& hull,
                                          const Eigen::Vector2d& centre,
                                          const Eigen::Vector2d& target, double turn_most) {
  std::vector<Eigen::Vector2d> all = hull;
  for (const double turn : {0.0, turn_most, -turn_most}) {
    const Eigen::Rotation2Dd r(turn);
    for (const auto& h : hull) all.push_back(target + r * (h - centre));
  }
  return convex_hull(all, kMetresToMm);
}

double sweep_lack(const std::vector<Eigen::Vector2d>& hull, const Eigen::Vector2d& centre,
                  const Eigen::Vector2d& target,
                  const std::vector<std::vector<Eigen::Vector2d>>& others, double margin,
                  bool touching, double turn) {
  if (margin <= 0 || others.empty() || hull.size() < 3) return 0.0;
  const std::vector<Eigen::Vector2d> swept = sweep_region(hull, centre, target, turn);
  const double reach = hull_radius(hull, centre) + (target - centre).norm();
  double lack = 0;
  for (const auto& o : others) {
    if (o.size() < 3) continue;
    // Bounding circles first: most other objects are far from the path.
    Eigen::Vector2d oc = Eigen::Vector2d::Zero();
    for (const auto& p : o) oc += p;
    oc /= static_cast<double>(o.size());
    if ((oc - centre).norm() - hull_radius(o, oc) - reach > margin) continue;
    const double before = std::min(margin, polygon_distance(hull, o));
    if (before == 0.0) {
      // Touching already: nothing to keep clear of, unless the push goes toward it (drawn back
      // against the push, the object leaves it).
      const double length = (target - centre).norm();
      if (!touching || length < 1e-9) continue;
      const Eigen::Vector2d back = -kTouchBack / length * (target - centre);
      std::vector<Eigen::Vector2d> drawn;
      drawn.reserve(hull.size());
      for (const auto& h : hull) drawn.push_back(h + back);
      if (polygon_distance(drawn, o) > 0.0) lack += margin;
      continue;
    }
    const double gap = polygon_distance(swept, o);
    lack += std::max(0.0, before - gap);
    if (gap == 0.0) lack += margin - before;
  }
  return lack;
}

int find_pushed_object(const cv::Mat& before_image, const cv::Mat& after_image,
                       PlanningView& after_view, const PutativeObject& previous,
                       const Eigen::Vector2d& expected, double radius, const TableRegion& region,
                       const PushPlanOptions& options) {
  options.validate();
  const cv::Mat1f motion = motion_image(before_image, after_image);
  std::vector<Eigen::Vector2d> carried;
  // Its features' extent (back-projected at centre_height as the features below are), not its
  // footprint: a tall object's features lie beyond its footprint.
  for (const auto& h : previous.extent) carried.push_back(h + (expected - previous.centre));
  const double margin = 0.25 * radius;
  std::vector<cv::KeyPoint> moving;
  for (const cv::KeyPoint& k : after_view.features) {
    if (!moved_at(motion, k.pt.x, k.pt.y)) continue;
    if (carried.size() >= 3) {
      try {
        const Eigen::Vector2d t = robot::pixel_to_table(
            after_view.camera, Eigen::Vector2d(k.pt.x, k.pt.y), options.centre_height);
        if (distance_to_polygon(carried, t) > margin) continue;
      } catch (const Error&) {
        continue;
      }
    }
    moving.push_back(k);
  }
  std::optional<PutativeObject> best;
  double best_d = radius;
  for (const features::Blob& b :
       features::find_blobs(moving, after_view.image_size, options.blobs)) {
    if (auto o = putative_object(b, moving, after_view.camera, region, options, after_view.depth)) {
      const double d = (o->centre - expected).norm();
      if (d <= best_d) {
        best_d = d;
        best = std::move(o);
      }
    }
  }
  if (best) {
    // The whole blob holding the moving one, when it is the object alone (nearly all its features
    // inside the carried hull): its centre is not biased toward the parts that changed most.
    constexpr double kAlone = 0.85;
    constexpr double kAloneGrowth = 1.5;
    for (std::size_t k = 0; k < after_view.objects.size(); ++k) {
      const PutativeObject& o = after_view.objects[k];
      if (!o.box.contains(cv::Point(static_cast<int>(std::lround(best->centre_pixel.x())),
                                    static_cast<int>(std::lround(best->centre_pixel.y()))))) {
        continue;
      }
      std::size_t inside = 0;
      for (const auto& p : o.pixels) {
        try {
          const Eigen::Vector2d t =
              robot::pixel_to_table(after_view.camera, p, options.centre_height);
          inside += distance_to_polygon(carried, t) <= margin ? 1 : 0;
        } catch (const Error&) {
        }
      }
      // Or it moved nearly everywhere (no still neighbour in it; a turned object leaves its
      // carried hull) and is not much larger than the object was (no swept neighbour either).
      std::size_t moved = 0;
      for (const auto& p : o.pixels) {
        moved += moved_at(motion, static_cast<float>(p.x()), static_cast<float>(p.y())) ? 1 : 0;
      }
      const auto n = static_cast<double>(o.pixels.size());
      const bool alone = static_cast<double>(inside) >= kAlone * n ||
                         (static_cast<double>(moved) >= kAlone * n &&
                          n <= kAloneGrowth * static_cast<double>(previous.pixels.size()));
      if (alone && o.pixels.size() >= best->pixels.size()) {
        return static_cast<int>(k);
      }
    }
    after_view.objects.push_back(std::move(*best));
    return static_cast<int>(after_view.objects.size()) - 1;
  }
  int still = -1;
  double still_d = margin;
  for (std::size_t k = 0; k < after_view.objects.size(); ++k) {
    const double d = (after_view.objects[k].centre - previous.centre).norm();
    if (d <= still_d) {
      still_d = d;
      still = static_cast<int>(k);
    }
  }
  return still;
}

double distance_to_hull_edge(const std::vector<Eigen::Vector2d>& hull, const Eigen::Vector2d& p,
                             const Eigen::Vector2d& u) {
  const std::size_t n = hull.size();
  if (n < 3) return 0.0;
  // Inside: p on the same side of every edge (either orientation).
  int positive = 0;
  int negative = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double c = cross(hull[(i + 1) % n] - hull[i], p - hull[i]);
    positive += c > 0 ? 1 : 0;
    negative += c < 0 ? 1 : 0;
  }
  if (positive > 0 && negative > 0) return 0.0;
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d& a = hull[i];
    const Eigen::Vector2d e = hull[(i + 1) % n] - a;
    const double denom = cross(u, e);
    if (std::abs(denom) < 1e-15) continue;
    const double s = cross(a - p, e) / denom;
    const double t = cross(a - p, u) / denom;
    if (s >= 0 && t >= -1e-12 && t <= 1 + 1e-12) best = std::min(best, s);
  }
  return std::isfinite(best) ? best : 0.0;
}

double push_tip_height(const PutativeObject& object, const PushPlanOptions& options) {
  if (options.tip_fraction <= 0 || !object.height || *object.height > options.tip_raise_height) {
    return options.tip_height;
  }
  return std::clamp(options.tip_fraction * *object.height, options.tip_height,
                    std::max(options.tip_height, kMostTipHeight));
}

robot::JawLine push_jaws(const PutativeObject& object, double tip_height,
                         const PushPlanOptions& options) {
  if (options.jaws_along_height > 0 && object.height &&
      *object.height < tip_height + options.jaws_along_height) {
    return robot::JawLine::kAlong;
  }
  return robot::JawLine::kRobot;
}

double push_speed_for(const PutativeObject& object, const PushPlanOptions& options) {
  if (options.tall_push_speed > 0 && object.height && *object.height >= options.tall_height) {
    return options.tall_push_speed;
  }
  return options.push_speed;
}

robot::TablePush push_through_centre(const std::vector<Eigen::Vector2d>& hull,
                                     const Eigen::Vector2d& centre, const Eigen::Vector2d& target,
                                     double approach, double height, double speed,
                                     double pusher_radius) {
  const Eigen::Vector2d d = target - centre;
  require(d.allFinite() && d.norm() > 1e-9, "push: the target is the object's centre");
  const Eigen::Vector2d n = d / d.norm();  // SPEC §5: p_t - p_s, not the thesis's p_s - p_t
  const double back = distance_to_hull_edge(hull, centre, -n);
  robot::TablePush push;
  push.start = centre - (back + approach) * n;     // p_s, behind the object
  push.end = target - (back + pusher_radius) * n;  // the back edge where p_c is over p_t
  push.height = height;
  push.speed = speed;
  return push;
}

namespace {

// Density at table point xy (z = height) seen by the camera; 0 outside the image.
double density_at(const cv::Mat1f& density, const geometry::Matrix34d& P, const Eigen::Vector2d& xy,
                  double height) {
  const Eigen::Vector3d h = P * Eigen::Vector4d(xy.x(), xy.y(), height, 1.0);
  if (h.z() <= 0) return 0.0;
  const int u = static_cast<int>(std::lround(h.x() / h.z()));
  const int v = static_cast<int>(std::lround(h.y() / h.z()));
  if (u < 0 || v < 0 || u >= density.cols || v >= density.rows) return 0.0;
  return density(v, u);
}

// The integral of the density along the segment a -> b in steps of `step`.
double line_integral(const cv::Mat1f& density, const geometry::Matrix34d& P,
                     const Eigen::Vector2d& a, const Eigen::Vector2d& b, double height,
                     double step) {
  const double len = (b - a).norm();
  const int n = std::max(1, static_cast<int>(std::ceil(len / step)));
  double sum = 0;
  for (int i = 0; i <= n; ++i) {
    sum += density_at(density, P, a + (b - a) * (static_cast<double>(i) / n), height);
  }
  return sum * len / (n + 1);
}

}  // namespace

double path_cost(const cv::Mat1f& density, const geometry::Camera& camera,
                 const robot::TablePush& push, const std::vector<Eigen::Vector2d>& hull,
                 const Eigen::Vector2d& centre, const Eigen::Vector2d& target, double height,
                 double step) {
  const geometry::Matrix34d P = camera.P();
  const Eigen::Vector2d n = (target - centre).normalized();
  const Eigen::Vector2d side(-n.y(), n.x());
  const double back = distance_to_hull_edge(hull, centre, -n);
  const double front = distance_to_hull_edge(hull, centre, n);
  double half_width = 0;
  for (const auto& h : hull) half_width = std::max(half_width, std::abs((h - centre).dot(side)));
  // The pusher alone, from p_s to the object's back edge (eq 7.5 along f(t)).
  double cost = line_integral(density, P, push.start, centre - back * n, height, step);
  // The corridor the object sweeps.
  for (int k = 0; k < kCorridorLines; ++k) {
    const double o = half_width * (2.0 * k / (kCorridorLines - 1) - 1.0);
    cost += line_integral(density, P, centre - back * n + o * side, target + front * n + o * side,
                          height, step) /
            kCorridorLines;
  }
  return cost;
}

namespace {

cv::Mat1f others_density(const PlanningView& view, const PutativeObject& object) {
  cv::Mat1f d = view.density.clone();
  d(object.box).setTo(0.0F, object.mask);
  std::vector<cv::Point> poly;
  for (const auto& h : object.hull_pixels) {
    poly.emplace_back(static_cast<int>(std::lround(h.x())), static_cast<int>(std::lround(h.y())));
  }
  if (poly.size() >= 3) cv::fillConvexPoly(d, poly, cv::Scalar(0.0));
  return d;
}

// Distance of the target's pixel to the nearest image border, as a fraction of the larger side.
double border_fraction(const geometry::Camera& cam, const Eigen::Vector2d& t, double height) {
  const Eigen::Vector3d X(t.x(), t.y(), height);
  if (cam.depth(X) <= 0) return 1.0;
  const Eigen::Vector2d px = cam.project(X);
  const double d = std::min({px.x(), px.y(), cam.width - 1 - px.x(), cam.height - 1 - px.y()});
  return std::max(0.0, d) / std::max(cam.width, cam.height);
}

bool in_view(const geometry::Camera& cam, const Eigen::Vector2d& t, double height) {
  const Eigen::Vector3d X(t.x(), t.y(), height);
  if (cam.depth(X) <= 0) return false;
  const Eigen::Vector2d px = cam.project(X);
  return px.x() >= 0 && px.y() >= 0 && px.x() <= cam.width - 1 && px.y() <= cam.height - 1;
}

std::string metres(const Eigen::Vector2d& p) {
  char b[64];
  std::snprintf(b, sizeof b, "(%.3f, %.3f) m", p.x(), p.y());
  return b;
}

}  // namespace

namespace {

// Spacing of the balls a capsule or cylinder is sampled as, and of a box's surface points, m.
constexpr double kPartSample = 0.005;

// A ball of the arm's surface: centre (world m) and radius (m).
struct Ball {
  Eigen::Vector3d centre;
  double radius;
};

// The colliding geoms of the arm's moving parts: in the subtree of its base body, not the base
// nor the first link's body (the robot's contact check leaves those out too).
std::vector<int> moving_arm_geoms(const robot::Arm& a) {
  const mjModel& m = a.model();
  const int base = a.base_body();
  const int first = m.jnt_bodyid[a.joint_id(0)];
  std::vector<int> out;
  for (int g = 0; g < m.ngeom; ++g) {
    const int b = m.geom_bodyid[g];
    if (b == base || b == first) continue;
    if (m.geom_contype[g] == 0 && m.geom_conaffinity[g] == 0) continue;
    bool in_arm = false;
    for (int k = b; k > 0; k = m.body_parentid[k]) {
      if (k == base) {
        in_arm = true;
        break;
      }
    }
    if (in_arm) out.push_back(g);
  }
  return out;
}

// Geom g (where `d`'s kinematics put it) as balls.
void geom_balls(const mjModel& m, const mjData& d, int g, std::vector<Ball>& out) {
  const Eigen::Vector3d pos(d.geom_xpos[3 * g], d.geom_xpos[3 * g + 1], d.geom_xpos[3 * g + 2]);
  Eigen::Matrix3d rot;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) rot(r, c) = d.geom_xmat[9 * g + 3 * r + c];
  }
  const mjtNum* size = m.geom_size + 3 * g;
  switch (m.geom_type[g]) {
    case mjGEOM_SPHERE:
      out.push_back({pos, size[0]});
      return;
    case mjGEOM_CAPSULE:
    case mjGEOM_CYLINDER: {
      const Eigen::Vector3d axis = rot.col(2);
      const int n = 1 + static_cast<int>(std::ceil(2.0 * size[1] / kPartSample));
      for (int i = 0; i <= n; ++i) {
        const double t = -size[1] + 2.0 * size[1] * static_cast<double>(i) / n;
        out.push_back({pos + t * axis, size[0]});
      }
      return;
    }
    case mjGEOM_BOX: {
      std::array<int, 3> n{};
      for (int k = 0; k < 3; ++k) {
        n[static_cast<std::size_t>(k)] =
            1 + static_cast<int>(std::ceil(2.0 * size[k] / kPartSample));
      }
      for (int i = 0; i <= n[0]; ++i) {
        for (int j = 0; j <= n[1]; ++j) {
          for (int k = 0; k <= n[2]; ++k) {
            const bool surface = i == 0 || j == 0 || k == 0 || i == n[0] || j == n[1] || k == n[2];
            if (!surface) continue;
            const Eigen::Vector3d local(size[0] * (2.0 * i / n[0] - 1.0),
                                        size[1] * (2.0 * j / n[1] - 1.0),
                                        size[2] * (2.0 * k / n[2] - 1.0));
            out.push_back({pos + rot * local, 0.0});
          }
        }
      }
      return;
    }
    default:
      out.push_back({pos, m.geom_rbound[g]});
      return;
  }
}

}  // namespace

DescentMap descent_map(const PlanningView& view, const TableRegion& region) {
  DescentMap map;
  map.origin = region.min;
  const int cols =
      std::max(1, static_cast<int>(std::ceil((region.max.x() - region.min.x()) / kDescentCell)));
  const int rows =
      std::max(1, static_cast<int>(std::ceil((region.max.y() - region.min.y()) / kDescentCell)));
  map.top = cv::Mat1f::zeros(rows, cols);
  const auto cell_of = [&](const Eigen::Vector2d& p, int& cx, int& cy) {
    cx = static_cast<int>(std::floor((p.x() - map.origin.x()) / kDescentCell));
    cy = static_cast<int>(std::floor((p.y() - map.origin.y()) / kDescentCell));
    return cx >= 0 && cy >= 0 && cx < cols && cy < rows;
  };
  if (!view.depth.empty()) {
    require(view.depth.type() == CV_32FC1, "descent map: the depth image must be CV_32FC1");
    const geometry::DepthPixels pixels(view.camera);
    for (int v = 0; v < view.depth.rows; v += 2) {
      const float* row = view.depth.ptr<float>(v);
      for (int u = 0; u < view.depth.cols; u += 2) {
        if (!geometry::depth_measured(row[u])) continue;
        const Eigen::Vector3d X = pixels.world(u, v, row[u]);
        if (X.z() < kObjectLeastHeight) continue;
        int cx = 0;
        int cy = 0;
        if (!cell_of(X.head<2>(), cx, cy)) continue;
        float& t = map.top(cy, cx);
        t = std::max(t, static_cast<float>(X.z()));
      }
    }
    return map;
  }
  for (const PutativeObject& o : view.objects) {
    if (o.hull.size() < 3) continue;
    const auto h = static_cast<float>(o.height.value_or(kUnknownHeight));
    Eigen::Vector2d lo = o.hull.front();
    Eigen::Vector2d hi = o.hull.front();
    for (const auto& p : o.hull) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    int x0 = 0;
    int y0 = 0;
    int x1 = 0;
    int y1 = 0;
    (void)cell_of(lo, x0, y0);
    (void)cell_of(hi, x1, y1);
    for (int cy = std::max(0, y0); cy <= std::min(rows - 1, y1); ++cy) {
      for (int cx = std::max(0, x0); cx <= std::min(cols - 1, x1); ++cx) {
        const Eigen::Vector2d c = map.origin + kDescentCell * Eigen::Vector2d(cx + 0.5, cy + 0.5);
        if (distance_to_polygon(o.hull, c) > 0.5 * kDescentCell) continue;
        map.top(cy, cx) = std::max(map.top(cy, cx), h);
      }
    }
  }
  return map;
}

namespace {

// The first part of the arm, posed at `q`, whose balls (geom_balls of `geoms`) come within
// `margin` of a column of `map` (descent_meets_object's test), named with its height and the
// cell's top; nullopt when none does. `highest`: the map's highest top.
std::optional<std::string> pose_meets(robot::ArmState& arm, const robot::JointVector& q,
                                      const std::vector<int>& geoms, const DescentMap& map,
                                      double margin, double highest) {
  const mjModel& m = arm.arm().model();
  const double half_diagonal = 0.5 * std::numbers::sqrt2 * kDescentCell;
  arm.set_joints(q);
  std::vector<Ball> balls;
  for (const int g : geoms) {
    balls.clear();
    geom_balls(m, arm.data(), g, balls);
    for (const Ball& b : balls) {
      const double low = b.centre.z() - b.radius - margin;
      if (low >= highest) continue;
      const double reach = b.radius + margin + half_diagonal;
      const int x0 =
          static_cast<int>(std::floor((b.centre.x() - reach - map.origin.x()) / kDescentCell));
      const int x1 =
          static_cast<int>(std::floor((b.centre.x() + reach - map.origin.x()) / kDescentCell));
      const int y0 =
          static_cast<int>(std::floor((b.centre.y() - reach - map.origin.y()) / kDescentCell));
      const int y1 =
          static_cast<int>(std::floor((b.centre.y() + reach - map.origin.y()) / kDescentCell));
      for (int cy = std::max(0, y0); cy <= std::min(map.top.rows - 1, y1); ++cy) {
        for (int cx = std::max(0, x0); cx <= std::min(map.top.cols - 1, x1); ++cx) {
          const double t = map.top(cy, cx);
          // An empty cell is the table the pusher comes down to, not an object (a margin above
          // the pusher's lowest point would otherwise meet every one).
          if (t <= 0 || t <= low) continue;
          const Eigen::Vector2d c = map.origin + kDescentCell * Eigen::Vector2d(cx + 0.5, cy + 0.5);
          if ((c - b.centre.head<2>()).norm() > reach) continue;
          const char* name = mj_id2name(&m, mjOBJ_GEOM, g);
          return std::string(name != nullptr ? name : "the arm") + " at " +
                 std::to_string(static_cast<int>(std::lround(b.centre.z() * 1000))) +
                 " mm on something " + std::to_string(static_cast<int>(std::lround(t * 1000))) +
                 " mm tall at " + metres(c);
        }
      }
    }
  }
  return std::nullopt;
}

// The roll j5 plan_push_motion gives `push` from `q_rest` (across the push when `roll_across` or
// push.jaws say so, along it for kAlong): q_rest with that roll.
robot::JointVector push_roll(robot::ArmState& arm, const robot::TablePush& push,
                             const robot::JointVector& q_rest, bool roll_across,
                             const robot::IkOptions& ik) {
  robot::JointVector q_from = q_rest;
  const bool across =
      push.jaws == robot::JawLine::kAcross || (push.jaws == robot::JawLine::kRobot && roll_across);
  if (across || push.jaws == robot::JawLine::kAlong) {
    const Eigen::Vector3d mid(0.5 * (push.start.x() + push.end.x()),
                              0.5 * (push.start.y() + push.end.y()), push.height);
    const robot::JointVector q_mid = robot::solve_ik(arm, mid, q_rest, ik).q;
    q_from[4] = across ? robot::fingers_across_roll(arm, q_mid, push.end - push.start)
                       : robot::fingers_along_roll(arm, q_mid, push.end - push.start);
  }
  return q_from;
}

}  // namespace

namespace {

// descent_meets_object with the parts `geoms` only.
std::optional<std::string> descent_meets(robot::ArmState& arm, const robot::TablePush& push,
                                         const robot::JointVector& q_rest, const DescentMap& map,
                                         double margin, bool roll_across,
                                         const std::vector<int>& geoms) {
  require(std::isfinite(margin) && margin >= 0, "descent poses: the margin must be >= 0");
  push.validate();
  if (map.top.empty()) return std::nullopt;
  double highest = 0;
  cv::minMaxLoc(map.top, nullptr, &highest);
  if (highest <= 0) return std::nullopt;
  const Eigen::Vector3d start(push.start.x(), push.start.y(), push.height);
  const robot::PushMotionOptions motion;
  // The roll as plan_push_motion sets it.
  const robot::JointVector q_from = push_roll(arm, push, q_rest, roll_across, motion.ik);
  const robot::JointVector q_above =
      robot::solve_ik(arm, start + Eigen::Vector3d(0, 0, motion.lift), q_from, motion.ik).q;
  // The top of the way down: the first of kDescentTops reached (seeded by the pose above the
  // start, as the robot's transit is).
  robot::JointVector q = q_above;
  double top = 0;
  for (const double h : kDescentTops) {
    try {
      q = robot::solve_ik(arm, Eigen::Vector3d(start.x(), start.y(), h), q_above, motion.ik).q;
      top = h;
      break;
    } catch (const Error&) {
      if (h == kDescentTops.back()) throw;
    }
  }
  const int steps = std::max(1, static_cast<int>(std::ceil((top - push.height) / kDescentStep)));
  for (int i = 0; i <= steps; ++i) {
    const double z = top + (push.height - top) * static_cast<double>(i) / steps;
    if (i > 0) q = robot::solve_ik(arm, Eigen::Vector3d(start.x(), start.y(), z), q, motion.ik).q;
    if (std::optional<std::string> met = pose_meets(arm, q, geoms, map, margin, highest)) {
      return met;
    }
  }
  return std::nullopt;
}

// The arm's moving parts above the jaws: the palm and the links (not the pusher, not a finger).
std::vector<int> parts_above_jaws(const robot::Arm& a) {
  const mjModel& m = a.model();
  std::vector<int> out;
  for (const int g : moving_arm_geoms(a)) {
    const char* name = mj_id2name(&m, mjOBJ_GEOM, g);
    const std::string s = name != nullptr ? name : "";
    if (s == "arm_pusher" || s.find("finger") != std::string::npos) continue;
    out.push_back(g);
  }
  return out;
}

}  // namespace

std::optional<std::string> descent_meets_object(robot::ArmState& arm, const robot::TablePush& push,
                                                const robot::JointVector& q_rest,
                                                const DescentMap& map, double margin,
                                                bool roll_across) {
  return descent_meets(arm, push, q_rest, map, margin, roll_across, moving_arm_geoms(arm.arm()));
}

std::optional<std::string> tall_push_meets(robot::ArmState& arm, const robot::TablePush& push,
                                           const robot::JointVector& q_rest, const DescentMap& map,
                                           double margin, bool roll_across, double contact) {
  require(std::isfinite(margin) && margin >= 0, "tall push: the margin must be >= 0");
  require(std::isfinite(contact) && contact >= 0, "tall push: the contact distance must be >= 0");
  const std::vector<int> geoms = parts_above_jaws(arm.arm());
  if (std::optional<std::string> met =
          descent_meets(arm, push, q_rest, map, margin, roll_across, geoms)) {
    return met;
  }
  if (map.top.empty()) return std::nullopt;
  double highest = 0;
  cv::minMaxLoc(map.top, nullptr, &highest);
  if (highest <= 0) return std::nullopt;
  // The hand kTallLead before the pusher meets the object.
  const robot::PushMotionOptions motion;
  const robot::JointVector q_from = push_roll(arm, push, q_rest, roll_across, motion.ik);
  const Eigen::Vector2d n = (push.end - push.start).normalized();
  const Eigen::Vector2d p = push.start + std::clamp(contact - kTallLead, 0.0, push.length()) * n;
  const robot::JointVector q =
      robot::solve_ik(arm, Eigen::Vector3d(p.x(), p.y(), push.height), q_from, motion.ik).q;
  if (std::optional<std::string> met = pose_meets(arm, q, geoms, map, 0.0, highest)) {
    return *met + " before the pusher meets the object";
  }
  return std::nullopt;
}

bool tall_start(const PutativeObject& object, double tip_height, const PushPlanOptions& options) {
  return options.tall_start_clearance > 0 && object.height &&
         *object.height >= tip_height + kPalmDrop - kDescentHeightMargin;
}

cv::Mat1f density_of_others(const PlanningView& view, int object) {
  ensure(object >= 0 && object < static_cast<int>(view.objects.size()),
         "density of others: no putative object " + std::to_string(object));
  return others_density(view, view.objects[static_cast<std::size_t>(object)]);
}

PushPlan plan_push(const PlanningView& view, int object, PushGoal goal,
                   const Eigen::Vector2d& target, const TableRegion& region, robot::ArmState& arm,
                   const robot::JointVector& q_rest, const PushPlanOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  options.validate();
  if (goal == PushGoal::kTarget) require(target.allFinite(), "push: the target must be finite");
  PushPlan plan;
  plan.object = object;
  auto finish = [&](PlanOutcome outcome, std::string message) {
    plan.outcome = outcome;
    plan.message = std::move(message);
    plan.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return plan;
  };
  if (view.objects.empty()) return finish(PlanOutcome::kNoObjects, "no putative object in view");
  if (object < 0 || object >= static_cast<int>(view.objects.size())) {
    return finish(PlanOutcome::kUnknownObject,
                  "object " + std::to_string(object) + " is not in view (" +
                      std::to_string(view.objects.size()) + " putative objects)");
  }
  const PutativeObject& o = view.objects[static_cast<std::size_t>(object)];
  plan.centre = o.centre;
  const double radius = hull_radius(o.hull, o.centre);
  if (goal == PushGoal::kTarget) {
    plan.target = target;
    if (!inside_region(target, region, options.table_margin + radius)) {
      return finish(PlanOutcome::kTargetOffTable,
                    "target " + metres(target) + " is off the table (the object, " +
                        std::to_string(static_cast<int>(std::lround(radius * 1000))) +
                        " mm across its centre, would not fit)");
    }
    if ((target - o.centre).norm() < options.least_push) {
      return finish(PlanOutcome::kAtTarget, "the object is already at the target");
    }
  }
  const cv::Mat1f others = others_density(view, o);
  // The other objects' hulls the path keeps clear of; a blob holding p_c (the pushed object
  // merged with a neighbour, or found again as a part of one) cannot be kept clear of.
  std::vector<std::vector<Eigen::Vector2d>> obstacles;
  std::vector<const PutativeObject*> obstacle_objects;
  for (std::size_t k = 0; k < view.objects.size(); ++k) {
    const PutativeObject& other = view.objects[k];
    if (static_cast<int>(k) == object || other.hull.size() < 3) continue;
    if (distance_to_polygon(other.hull, o.centre) == 0.0) continue;
    obstacles.push_back(other.hull);
    obstacle_objects.push_back(&other);
  }
  // The object's hull carried from its centre to p.
  const auto hull_at = [&o](const Eigen::Vector2d& p) {
    std::vector<Eigen::Vector2d> h = o.hull;
    for (auto& x : h) x += p - o.centre;
    return h;
  };
  // free_target_margin: a target the object cannot lie at without meeting another object is
  // moved to the nearest point a straight push reaches clear.
  Eigen::Vector2d goal_target = target;
  if (goal == PushGoal::kTarget && options.free_target_margin > 0 && !obstacles.empty()) {
    const double m = options.free_target_margin;
    const std::vector<Eigen::Vector2d> at = hull_at(target);
    const bool against = std::any_of(obstacles.begin(), obstacles.end(), [&](const auto& other) {
      return polygon_distance(at, other) < m;
    });
    const auto clear = [&](const Eigen::Vector2d& p) {
      return inside_region(p, region, options.table_margin + radius) &&
             sweep_lack(o.hull, o.centre, p, obstacles, m, false, 0.0) <= 0;
    };
    bool found = false;
    for (int ring = 1; against && !found && ring * kFreeTargetStep <= kFreeTargetMost + 1e-9;
         ++ring) {
      const double r = ring * kFreeTargetStep;
      double nearest = std::numeric_limits<double>::infinity();
      for (int k = 0; k < kFreeTargetAngles; ++k) {
        const double a = 2.0 * std::numbers::pi * k / kFreeTargetAngles;
        const Eigen::Vector2d p = target + r * Eigen::Vector2d(std::cos(a), std::sin(a));
        if (const double d = (p - o.centre).norm(); d < nearest && clear(p)) {
          nearest = d;
          goal_target = p;
          found = true;
        }
      }
    }
    plan.target_moved = (goal_target - target).norm();
    plan.target = goal_target;
    if (found && (goal_target - o.centre).norm() < options.least_push) {
      return finish(PlanOutcome::kAtTarget,
                    "the object is already at the nearest free point to the target " +
                        metres(target) + ", " +
                        std::to_string(static_cast<int>(std::lround(plan.target_moved * 1000))) +
                        " mm from it (it lies against another object)");
    }
  }
  // Heights known (a depth look): the descent check goes by each object's height.
  const bool heights = o.height.has_value() ||
                       std::any_of(obstacle_objects.begin(), obstacle_objects.end(),
                                   [](const PutativeObject* x) { return x->height.has_value(); });
  // The tip's height and the speed for this object (its measured height, when depth gave one).
  const double tip = push_tip_height(o, options);
  const double speed = push_speed_for(o, options);
  const robot::JawLine jaws = push_jaws(o, tip, options);
  // tall_start_clearance: a tall object's start far enough behind it for the arm's way down.
  const bool tall = tall_start(o, tip, options);
  // The turn the swept region allows for (sweep_margin).
  const double turn = options.sweep_turn_by_shape ? sweep_turn(o.hull) : kSweepTurn;
  core::Rng rng(options.seed);
  const robot::IkOptions ik;
  struct Candidate {
    double score;  // kBlockedWeight * blocked + cost (+ kViaCost)
    double cost;
    double blocked;
    bool via;
    Eigen::Vector2d target;
    double approach;
    robot::TablePush push;
    double shortened = 0;
    double hand = 0;    // hand_lack's part of blocked
    double topple = 0;  // push_contact's ratio (topple_ratio)
    double offset = 0;  // topple_offset: the line shifted sideways, m
    bool far = false;   // tall_start_clearance: a longer approach, tried after the others
  };
  std::vector<Candidate> feasible;
  // topple_ratio: the pushed object's depth points, to judge where each push meets it.
  const std::vector<Eigen::Vector3d> topple_points =
      options.topple_ratio > 0 && !view.depth.empty()
          ? object_depth_points(view.depth, view.camera, o.hull_pixels, o.mask, o.box, kDepthStep)
          : std::vector<Eigen::Vector3d>{};
  // hand_margin: the hand's shortfall of a push, which is set to the jaws' line (hand_jaws) and
  // the tip's height (hand_raise) that block it least. 0 when hand_margin is 0.
  const bool low_object = o.height && *o.height < tip + kFingerDrop - kDescentHeightMargin;
  const double raise_top =
      options.hand_raise > 0 && o.height && *o.height <= options.tip_raise_height
          ? std::min({kMostTipHeight, kRaiseFraction * *o.height, tip + options.hand_raise})
          : tip;
  const auto hand_fit = [&](robot::TablePush& push) {
    if (options.hand_margin <= 0) return 0.0;
    const auto lack = [&](const robot::TablePush& p) {
      return hand_lack(p, p.jaws == robot::JawLine::kAlong, obstacle_objects, options.hand_margin);
    };
    double best_lack = lack(push);
    if (best_lack > 0 && options.hand_jaws && low_object && push.jaws != robot::JawLine::kAlong) {
      robot::TablePush along = push;
      along.jaws = robot::JawLine::kAlong;
      if (const double l = lack(along); l < best_lack) {
        best_lack = l;
        push = along;
      }
    }
    for (double z = tip + kRaiseStep; best_lack > 0 && z <= raise_top + 1e-9; z += kRaiseStep) {
      robot::TablePush raised = push;
      raised.height = z;
      if (const double l = lack(raised); l < best_lack) {
        best_lack = l;
        push = raised;
      }
    }
    return best_lack;
  };
  // A single push of the object's centre to t: checked (region, descent, reach) and scored.
  const auto leg = [&](const Eigen::Vector2d& t, double approach) -> std::optional<Candidate> {
    robot::TablePush push =
        push_through_centre(o.hull, o.centre, t, approach, tip, speed, options.pusher_radius);
    push.jaws = jaws;
    if (!inside_region(push.start, region, options.table_margin) ||
        !inside_region(t, region, options.table_margin + radius) ||
        (goal == PushGoal::kEdge && !in_view(view.camera, t, 0.0)) || push.length() < 0.005) {
      ++plan.rejected_region;
      return std::nullopt;
    }
    double hand = hand_fit(push);
    double topple = 0;
    double offset = 0;
    if (static_cast<int>(topple_points.size()) >= kFootprintLeastPoints) {
      const Eigen::Vector2d n = (t - o.centre).normalized();
      const auto ratio = [&](robot::JawLine j, double e) {
        return push_contact(topple_points, o.centre, n, push.height, j, options.roll_across, e)
            .ratio;
      };
      topple = ratio(push.jaws, 0.0);
      if (topple > options.topple_ratio && options.topple_offset > 0) {
        // The jaws across, then the line shifted to meet a low part (1 cm steps, either way).
        const robot::JawLine across = robot::JawLine::kAcross;
        if (const double r = ratio(across, 0.0); r <= options.topple_ratio) {
          topple = r;
          push.jaws = across;
        }
        for (double e = kToppleStep;
             topple > options.topple_ratio && e <= options.topple_offset + 1e-9; e += kToppleStep) {
          for (const double side : {e, -e}) {
            const double r = ratio(across, side);
            if (r > options.topple_ratio) continue;
            const Eigen::Vector2d shift = side * Eigen::Vector2d(-n.y(), n.x());
            robot::TablePush shifted =
                push_through_centre(o.hull, o.centre + shift, t + shift, approach, push.height,
                                    push.speed, options.pusher_radius);
            shifted.jaws = across;
            if (!inside_region(shifted.start, region, options.table_margin)) continue;
            push = shifted;
            topple = r;
            offset = side;
            break;
          }
        }
      }
      if (topple > options.topple_ratio) {
        ++plan.rejected_topple;
        return std::nullopt;
      }
      if (push.jaws != jaws && options.hand_margin > 0) {
        hand = hand_lack(push, false, obstacle_objects, options.hand_margin);
      }
    }
    if (options.descent_clearance > 0 &&
        (heights ? descent_blocked(push.start, o, obstacle_objects, options.descent_clearance,
                                   push.height)
                 : descent_blocked(push.start, o.hull, obstacles, options.descent_clearance))) {
      ++plan.rejected_reach;
      return std::nullopt;
    }
    if (!robot::reachable(arm, push.start, push.height, q_rest, ik) ||
        !robot::reachable(arm, push.start, push.height + kTransitLift, q_rest, ik) ||
        !robot::reachable(arm, push.end, push.height, q_rest, ik)) {
      ++plan.rejected_reach;
      return std::nullopt;
    }
    double cost = path_cost(others, view.camera, push, o.hull, o.centre, t, options.centre_height,
                            options.path_step);
    if (goal == PushGoal::kEdge) cost += kEdgeWeight * border_fraction(view.camera, t, 0.0);
    const double blocked = path_clearance(push, o.hull, o.centre, t, obstacles, options.clearance,
                                          options.hand_clearance) +
                           sweep_lack(o.hull, o.centre, t, obstacles, options.sweep_margin,
                                      options.sweep_touching, turn) +
                           hand;
    return Candidate{kBlockedWeight * blocked + cost,
                     cost,
                     blocked,
                     false,
                     t,
                     approach,
                     push,
                     0.0,
                     hand,
                     topple,
                     offset};
  };
  // A waypoint path: the second leg, from the waypoint t on to the target, as the next plan would
  // make it, its cost and shortfalls added to the first leg's c. false when it cannot be made.
  const auto second_leg = [&](Candidate& c, const Eigen::Vector2d& t) {
    const std::vector<Eigen::Vector2d> moved = hull_at(t);
    if ((goal_target - t).norm() < options.least_push) return false;
    robot::TablePush next = push_through_centre(moved, t, goal_target, options.min_approach, tip,
                                                speed, options.pusher_radius);
    next.jaws = jaws;
    if (!inside_region(next.start, region, options.table_margin) ||
        !robot::reachable(arm, next.start, next.height, q_rest, ik) ||
        !robot::reachable(arm, next.end, next.height, q_rest, ik)) {
      ++plan.rejected_reach;
      return false;
    }
    c.cost += path_cost(others, view.camera, next, moved, t, goal_target, options.centre_height,
                        options.path_step);
    c.blocked +=
        path_clearance(next, moved, t, goal_target, obstacles, options.clearance,
                       options.hand_clearance) +
        sweep_lack(moved, t, goal_target, obstacles, options.sweep_margin, options.sweep_touching,
                   turn) +
        hand_lack(next, next.jaws == robot::JawLine::kAlong, obstacle_objects, options.hand_margin);
    c.via = true;
    c.score = kBlockedWeight * c.blocked + c.cost + kViaCost;
    return true;
  };
  const int via_points = goal == PushGoal::kTarget ? options.via_points : 0;
  const Eigen::Vector2d line = (goal_target - o.centre).normalized();
  for (int i = 0; i < options.candidates + via_points; ++i) {
    ++plan.sampled;
    const bool via = i >= options.candidates;
    Eigen::Vector2d t = goal_target;
    if (via) {
      // A waypoint beside the line: turned 20-100 degrees off it either way, 4-10 cm away.
      const double a = (rng.uniform() < 0.5 ? -1.0 : 1.0) * rng.uniform(kViaLeast, kViaMost);
      const double r = rng.uniform(kViaNear, kViaFar);
      t = o.centre + r * (Eigen::Rotation2Dd(a) * line);
    } else if (goal == PushGoal::kTarget) {
      if (i > 0 && options.target_spread > 0) {
        const double r = options.target_spread * std::sqrt(rng.uniform());
        const double a = rng.uniform(-std::numbers::pi, std::numbers::pi);
        t += r * Eigen::Vector2d(std::cos(a), std::sin(a));
      }
    } else {
      const double a = rng.uniform(-std::numbers::pi, std::numbers::pi);
      const double r = rng.uniform(options.min_distance, options.max_distance);
      t = o.centre + r * Eigen::Vector2d(std::cos(a), std::sin(a));
    }
    const double approach = rng.uniform(options.min_approach, options.max_approach);
    if ((t - o.centre).norm() < options.least_push) {
      ++plan.rejected_region;
      continue;
    }
    std::optional<Candidate> c = leg(t, approach);
    if (!c) continue;
    if (via && !second_leg(*c, t)) continue;
    if (!via && goal == PushGoal::kTarget && c->blocked > 0 &&
        ((options.sweep_margin > 0 &&
          sweep_lack(o.hull, o.centre, t, obstacles, options.sweep_margin, options.sweep_touching,
                     turn) > 0) ||
         c->hand > 0)) {
      // Shortened: the object stopped on the same line where its swept region (and, with
      // hand_margin, the hand) is first clear.
      const double full = (t - o.centre).norm();
      const Eigen::Vector2d n = (t - o.centre) / full;
      const auto shorten = [&](double d) {
        if (std::optional<Candidate> s = leg(o.centre + d * n, approach)) {
          s->shortened = full - d;
          s->score += kShortCost * (full - d);
          feasible.push_back(*s);
        }
      };
      // hand_keep_short: the first point clear of the sweep, kept when none is clear of both.
      std::optional<double> sweep_clear;
      bool found = false;
      for (double d = full - kShortStep; d >= options.least_push; d -= kShortStep) {
        const Eigen::Vector2d ts = o.centre + d * n;
        if (sweep_lack(o.hull, o.centre, ts, obstacles, options.sweep_margin,
                       options.sweep_touching) > 0)
          continue;
        if (!sweep_clear) sweep_clear = d;
        if (options.hand_margin > 0) {
          robot::TablePush p = push_through_centre(o.hull, o.centre, ts, approach, tip, speed,
                                                   options.pusher_radius);
          p.jaws = jaws;
          if (p.length() >= 0.005 && hand_fit(p) > 0) continue;
        }
        shorten(d);
        found = true;
        break;
      }
      if (!found && sweep_clear && options.hand_keep_short && options.sweep_margin > 0 &&
          sweep_lack(o.hull, o.centre, t, obstacles, options.sweep_margin, options.sweep_touching,
                     turn) > 0) {
        shorten(*sweep_clear);
      }
    }
    feasible.push_back(*c);
    // tall_start_clearance: the same push from farther behind, ranked after every other path
    // (taken only when those bring the arm onto the tall object).
    if (tall && !via) {
      const double longer = approach + std::max(0.0, kTallMostApproach - options.max_approach);
      if (std::optional<Candidate> f = leg(t, longer)) {
        f->far = true;
        f->score += kTallFarScore;
        feasible.push_back(*f);
      }
    }
  }
  // via_blocked: no direct push reaches the target clear, so waypoints in a fixed fan round the
  // line, each scored with both legs.
  const bool direct_clear = std::any_of(feasible.begin(), feasible.end(), [](const Candidate& c) {
    return !c.via && !c.far && c.blocked <= 0 && c.shortened <= 0;
  });
  if (goal == PushGoal::kTarget && options.via_blocked > 0 && !direct_clear) {
    const int half = (options.via_blocked + 1) / 2;
    const double approach = 0.5 * (options.min_approach + options.max_approach);
    for (int i = 0; i < options.via_blocked; ++i) {
      ++plan.sampled;
      const int m = i / 2;
      const double f = half > 1 ? static_cast<double>(m) / (half - 1) : 0.5;
      const double a = (i % 2 == 0 ? 1.0 : -1.0) * (kViaLeast + f * (kViaMost - kViaLeast));
      const double r = kViaNear + (kViaFar - kViaNear) * 0.5 * (m % 3);
      // Even pairs round the object's centre (a way round from the start); odd pairs beside the
      // target (its second leg comes in from another side).
      const Eigen::Vector2d t =
          (m % 2 == 0) ? Eigen::Vector2d(o.centre + r * (Eigen::Rotation2Dd(a) * line))
                       : Eigen::Vector2d(goal_target - r * (Eigen::Rotation2Dd(a) * line));
      std::optional<Candidate> c = leg(t, approach);
      if (!c || !second_leg(*c, t)) continue;
      feasible.push_back(*c);
    }
  }
  std::stable_sort(feasible.begin(), feasible.end(),
                   [](const Candidate& a, const Candidate& b) { return a.score < b.score; });
  double best = std::numeric_limits<double>::infinity();
  robot::PushMotionOptions motion;
  motion.rate_hz = kMotionCheckRate;
  // descent_pose_margin: what the arm may meet, the pushed object too.
  const DescentMap solid =
      options.descent_pose_margin > 0 || tall ? descent_map(view, region) : DescentMap{};
  std::string first_tall;
  std::string first_met;
  // descent_pose_fallback: the best path whose descent alone met something.
  const Candidate* met = nullptr;
  const auto take = [&](const Candidate& c) {
    best = c.cost;
    plan.target = c.target;
    plan.push = c.push;
    plan.approach = c.approach;
    plan.cost = c.cost;
    plan.blocked = c.blocked;
    plan.hand_blocked = c.hand;
    plan.via = c.via;
    plan.shortened = c.shortened;
    plan.topple = c.topple;
    plan.offset = c.offset;
    plan.direction = (c.target - o.centre).normalized();
    plan.edge_distance = distance_to_hull_edge(o.hull, o.centre, -plan.direction);
  };
  for (const Candidate& c : feasible) {
    try {
      (void)robot::plan_push_motion(arm, c.push, q_rest, motion);
    } catch (const Error&) {
      ++plan.rejected_reach;
      continue;
    }
    if (tall) {
      // The tall object's own check: no fallback (a hand that comes down on it, or leans into it
      // before the pusher meets it, knocks it over).
      try {
        if (std::optional<std::string> part = tall_push_meets(
                arm, c.push, q_rest, solid, options.tall_start_clearance, options.roll_across,
                std::max(0.0, c.approach - options.pusher_radius))) {
          if (plan.rejected_tall == 0) first_tall = *part;
          ++plan.rejected_tall;
          continue;
        }
      } catch (const Error&) {
        ++plan.rejected_reach;
        continue;
      }
    }
    if (options.descent_pose_margin > 0) {
      try {
        if (std::optional<std::string> part = descent_meets_object(
                arm, c.push, q_rest, solid, options.descent_pose_margin, options.roll_across)) {
          if (plan.rejected_descent == 0) {
            first_met = *part;
            met = &c;
          }
          ++plan.rejected_descent;
          continue;
        }
      } catch (const Error&) {
        ++plan.rejected_reach;
        continue;
      }
    }
    take(c);
    break;
  }
  if (!std::isfinite(best) && met != nullptr && options.descent_pose_fallback) {
    take(*met);
    plan.descent_met = true;
  }
  if (!std::isfinite(best)) {
    return finish(
        PlanOutcome::kUnreachable,
        "no path: of " + std::to_string(plan.sampled) + " sampled, " +
            std::to_string(plan.rejected_region) + " left the table or view and " +
            std::to_string(plan.rejected_reach) + " were out of the arm's reach" +
            (plan.rejected_topple > 0
                 ? " and " + std::to_string(plan.rejected_topple) + " would tip the object over"
                 : std::string()) +
            (plan.rejected_descent > 0
                 ? " and " + std::to_string(plan.rejected_descent) +
                       " would meet an object on the arm's way down (the first: " + first_met + ")"
                 : std::string()) +
            (plan.rejected_tall > 0
                 ? " and " + std::to_string(plan.rejected_tall) +
                       " would bring the arm down too near something by the tall object (the "
                       "first: " +
                       first_tall + ")"
                 : std::string()));
  }
  std::string said = "push object " + std::to_string(object) + " from " + metres(plan.push.start) +
                     " to " + metres(plan.push.end) + ", its centre to " + metres(plan.target);
  if (plan.via) said += " (a waypoint round a blocked line)";
  if (plan.offset != 0) {
    said += " (its line " + std::to_string(static_cast<int>(std::lround(plan.offset * 1000))) +
            " mm to the left of the centre: through the centre it would tip over)";
  }
  if (plan.target_moved > 0) {
    said += " (the target " + metres(target) +
            " lies against another object: the nearest free point, " +
            std::to_string(static_cast<int>(std::lround(plan.target_moved * 1000))) +
            " mm from it)";
  }
  if (plan.descent_met) said += " (every path's way down meets an object: " + first_met + ")";
  if (plan.push.jaws != jaws && plan.push.jaws == robot::JawLine::kAlong) {
    said += " (the jaws along the push: the hand clears)";
  }
  if (plan.push.jaws != jaws && plan.push.jaws == robot::JawLine::kAcross) {
    said += " (the jaws across the push: with them as they were it would tip over)";
  }
  if (plan.push.height > tip + 1e-9) {
    said += " (the tip raised to " +
            std::to_string(static_cast<int>(std::lround(plan.push.height * 1000))) +
            " mm: the hand clears)";
  }
  if (plan.shortened > 0) {
    said += " (" + std::to_string(static_cast<int>(std::lround(plan.shortened * 1000))) +
            " mm short: the way on meets another object)";
  }
  return finish(PlanOutcome::kPlanned, said);
}

PushPlanOptions after_refusal(const PushPlanOptions& options) {
  options.validate();
  PushPlanOptions o = options;
  if (o.refusal_pose_margin <= 0) return o;
  o.descent_pose_margin = std::max(o.descent_pose_margin, o.refusal_pose_margin);
  o.descent_pose_fallback = true;
  return o;
}

PushPlan plan_push_hand_clear(const PlanningView& view, int object, PushGoal goal,
                              const Eigen::Vector2d& target, const TableRegion& region,
                              robot::ArmState& arm, const robot::JointVector& q_rest,
                              const PushPlanOptions& options, double margin, int via) {
  require(std::isfinite(margin) && margin >= 0 && margin <= 0.05,
          "plan_push_hand_clear: margin must be in [0, 0.05] m");
  require(via >= 0, "plan_push_hand_clear: via must be >= 0");
  if (margin <= 0) return plan_push(view, object, goal, target, region, arm, q_rest, options);
  PushPlanOptions clear = options;
  clear.hand_margin = std::max(clear.hand_margin, margin);
  clear.hand_jaws = true;
  clear.via_blocked = std::max(clear.via_blocked, via);
  PushPlan tried = plan_push(view, object, goal, target, region, arm, q_rest, clear);
  if (tried.outcome == PlanOutcome::kPlanned && tried.blocked <= 0 && tried.shortened <= 0) {
    tried.hand_cleared = true;
    return tried;
  }
  PushPlan plan = plan_push(view, object, goal, target, region, arm, q_rest, options);
  // How far the try fell short: its blocking, and its shortening (clear only shortened).
  plan.hand_fallback =
      tried.outcome == PlanOutcome::kPlanned ? tried.blocked + tried.shortened : -1.0;
  plan.seconds += tried.seconds;
  return plan;
}

}  // namespace proprio::planning
