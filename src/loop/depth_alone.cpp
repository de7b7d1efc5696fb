// The robot's singulation check from depth footprints (include/proprio/loop/depth_alone.hpp).
#include "proprio/loop/depth_alone.hpp"
#include "proprio/geometry/depth_pixels.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <opencv2/imgproc.hpp>

#include "proprio/core/error.hpp"
#include "proprio/core/text.hpp"
#include "proprio/loop/self_supervision.hpp"

namespace proprio::loop {

namespace {

// Union-find over pixel indices.
int find_root(std::vector<int>& parent, int i) {
  while (parent[static_cast<std::size_t>(i)] != i) {
    const int p = parent[static_cast<std::size_t>(i)];
    parent[static_cast<std::size_t>(i)] = parent[static_cast<std::size_t>(p)];
    i = p;
  }
  return i;
}

void join_sets(std::vector<int>& parent, int a, int b) {
  a = find_root(parent, a);
  b = find_root(parent, b);
  if (a != b) parent[static_cast<std::size_t>(std::max(a, b))] = std::min(a, b);
}

std::vector<Eigen::Vector2d> hull_of(const std::vector<Eigen::Vector2d>& xy) {
  std::vector<cv::Point2f> pts;
  pts.reserve(xy.size());
  for (const auto& p : xy) pts.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()));
  std::vector<cv::Point2f> h;
  if (pts.size() >= 3) cv::convexHull(pts, h, false);  // counter-clockwise (y up)
  std::vector<Eigen::Vector2d> out;
  out.reserve(h.size());
  for (const auto& p : h) out.emplace_back(p.x, p.y);
  if (out.size() < 3) return xy;  // a line or a point: its points
  return out;
}

}  // namespace

void DepthAloneOptions::validate() const {
  require(std::isfinite(part_gap) && part_gap >= 0 && part_gap <= 0.1,
          "depth_alone: part_gap must be in [0, 0.1] m");
}

void DepthFootprintOptions::validate() const {
  require(std::isfinite(least_height) && least_height >= 0 && least_height <= 0.1,
          "depth footprints: least_height must be in [0, 0.1] m");
  require(std::isfinite(join) && join > 0 && join <= 0.2,
          "depth footprints: join must be in (0, 0.2] m");
  require(least_pixels >= 1 && least_pixels <= 100000,
          "depth footprints: least_pixels must be in [1, 100000]");
}

DepthFootprints depth_footprints(const cv::Mat& depth, const geometry::Camera& camera,
                                 const planning::TableRegion& region,
                                 const DepthFootprintOptions& options) {
  options.validate();
  DepthFootprints out;
  if (depth.empty()) return out;
  require(depth.type() == CV_32FC1, "depth footprints: the depth image must be CV_32FC1 (metres)");
  require(camera.width == 0 || (depth.cols == camera.width && depth.rows == camera.height),
          "depth footprints: the depth image must be of the camera's image size");
  const int w = depth.cols;
  const int h = depth.rows;
  const geometry::DepthPixels pixels(camera);
  std::vector<Eigen::Vector3d> x(static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
  std::vector<char> on(x.size(), 0);
  const Eigen::Vector2d lo = region.min + Eigen::Vector2d::Constant(region.edge_band);
  const Eigen::Vector2d hi = region.max - Eigen::Vector2d::Constant(region.edge_band);
  for (int v = 0; v < h; ++v) {
    const auto* row = depth.ptr<float>(v);
    for (int u = 0; u < w; ++u) {
      const double d = row[u];
      if (!geometry::depth_measured(d)) continue;
      const Eigen::Vector3d p = pixels.world(u, v, d);
      if (p.z() < options.least_height) continue;
      if (p.x() < lo.x() || p.y() < lo.y() || p.x() > hi.x() || p.y() > hi.y()) continue;
      if (p.head<2>().norm() < region.base_radius) continue;
      const auto i =
          static_cast<std::size_t>(v) * static_cast<std::size_t>(w) + static_cast<std::size_t>(u);
      x[i] = p;
      on[i] = 1;
    }
  }
  std::vector<int> parent(x.size());
  std::iota(parent.begin(), parent.end(), 0);
  const double join2 = options.join * options.join;
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      const int i = v * w + u;
      if (on[static_cast<std::size_t>(i)] == 0) continue;
      const auto link = [&](int j) {
        if (on[static_cast<std::size_t>(j)] != 0 &&
            (x[static_cast<std::size_t>(i)] - x[static_cast<std::size_t>(j)]).squaredNorm() <=
                join2) {
          join_sets(parent, i, j);
        }
      };
      if (u + 1 < w) link(i + 1);
      if (v + 1 < h) link(i + w);
    }
  }
  std::vector<int> count(x.size(), 0);
  for (int i = 0; i < w * h; ++i) {
    if (on[static_cast<std::size_t>(i)] != 0)
      ++count[static_cast<std::size_t>(find_root(parent, i))];
  }
  out.labels = cv::Mat1i(h, w, -1);
  std::vector<int> index(x.size(), -1);
  std::vector<std::vector<Eigen::Vector2d>> xy;
  for (int i = 0; i < w * h; ++i) {
    if (on[static_cast<std::size_t>(i)] == 0) continue;
    const int r = find_root(parent, i);
    if (count[static_cast<std::size_t>(r)] < options.least_pixels) continue;
    int& k = index[static_cast<std::size_t>(r)];
    if (k < 0) {
      k = static_cast<int>(out.parts.size());
      out.parts.emplace_back();
      xy.emplace_back();
    }
    auto& part = out.parts[static_cast<std::size_t>(k)];
    const Eigen::Vector3d& p = x[static_cast<std::size_t>(i)];
    xy[static_cast<std::size_t>(k)].push_back(p.head<2>());
    part.centre += p.head<2>();
    part.height = std::max(part.height, p.z());
    ++part.pixels;
    out.labels(i / w, i % w) = k;
  }
  for (std::size_t k = 0; k < out.parts.size(); ++k) {
    out.parts[k].centre /= static_cast<double>(out.parts[k].pixels);
    out.parts[k].hull = hull_of(xy[k]);
  }
  return out;
}

DepthAlone depth_alone(const DepthFootprints& fp, const planning::PlanningView& view, int chosen,
                       double clearance, const DepthAloneOptions& options) {
  options.validate();
  require(chosen >= 0 && chosen < static_cast<int>(view.objects.size()),
          "depth_alone: the chosen blob is not one of the view's");
  require(std::isfinite(clearance) && clearance > 0, "depth_alone: clearance must be positive");
  DepthAlone out;
  out.blob_gaps.assign(view.objects.size(), std::nullopt);
  if (fp.parts.empty()) {
    out.why = "no depth footprint in view";
    return out;
  }
  require(fp.labels.cols == view.image_size.width && fp.labels.rows == view.image_size.height,
          "depth_alone: the footprints' labels must be of the view's image size");
  // The footprints each blob's features lie on, counted.
  const auto votes = [&](const planning::PutativeObject& o) {
    std::vector<int> n(fp.parts.size(), 0);
    for (const auto& p : o.pixels) {
      const int u = static_cast<int>(std::lround(p.x()));
      const int v = static_cast<int>(std::lround(p.y()));
      if (u < 0 || v < 0 || u >= fp.labels.cols || v >= fp.labels.rows) continue;
      const int k = fp.labels(v, u);
      if (k >= 0) ++n[static_cast<std::size_t>(k)];
    }
    return n;
  };
  // Each footprint's owner: the blob with the most features on it (-1: none). The depth jumps
  // that separate objects also cut one object into parts (a head above its body, a wheel in
  // front of a frame): the chosen object is every footprint it owns, and every footprint no blob
  // owns within kPartGap of those.
  const std::size_t n_parts = fp.parts.size();
  std::vector<std::vector<int>> on(view.objects.size());  // per blob: its features per footprint
  std::vector<int> owner(n_parts, -1);
  std::vector<int> most(n_parts, 0);
  for (std::size_t b = 0; b < view.objects.size(); ++b) {
    on[b] = votes(view.objects[b]);
    for (std::size_t k = 0; k < n_parts; ++k) {
      if (on[b][k] > most[k]) {
        most[k] = on[b][k];
        owner[k] = static_cast<int>(b);
      }
    }
  }
  const std::vector<int>& cv = on[static_cast<std::size_t>(chosen)];
  const auto best = std::max_element(cv.begin(), cv.end());
  if (*best == 0) {
    out.why = "the chosen blob's features lie on no depth footprint";
    return out;
  }
  out.measured = true;
  out.footprint = static_cast<int>(best - cv.begin());
  std::vector<char> mine(n_parts, 0);
  mine[static_cast<std::size_t>(out.footprint)] = 1;
  const double part_gap = options.part_gap;
  for (std::size_t k = 0; part_gap > 0 && k < n_parts; ++k) {
    if (owner[k] == chosen) mine[k] = 1;
  }
  const auto gap_between = [&](std::size_t a, std::size_t b) {
    return hull_gap(fp.parts[a].hull, fp.parts[b].hull);
  };
  for (bool grew = part_gap > 0; grew;) {
    grew = false;
    for (std::size_t k = 0; k < n_parts; ++k) {
      if (mine[k] != 0 || owner[k] >= 0) continue;
      for (std::size_t j = 0; j < n_parts; ++j) {
        if (mine[j] != 0 && gap_between(k, j) < part_gap) {
          mine[k] = 1;
          grew = true;
          break;
        }
      }
    }
  }
  // Merged: the chosen blob's own footprints fall into two groups kPartGap or more apart, each
  // with at least a quarter of its features (two objects seen as one blob).
  {
    std::vector<int> group(n_parts, -1);
    std::vector<int> share;
    for (std::size_t k = 0; k < n_parts; ++k) {
      if (mine[k] == 0 || group[k] >= 0) continue;
      const int g = static_cast<int>(share.size());
      share.push_back(0);
      std::vector<std::size_t> stack{k};
      group[k] = g;
      while (!stack.empty()) {
        const std::size_t a = stack.back();
        stack.pop_back();
        share[static_cast<std::size_t>(g)] += cv[a];
        for (std::size_t j = 0; j < n_parts; ++j) {
          if (mine[j] != 0 && group[j] < 0 && gap_between(a, j) < part_gap) {
            group[j] = g;
            stack.push_back(j);
          }
        }
      }
    }
    const int total =
        static_cast<int>(view.objects[static_cast<std::size_t>(chosen)].pixels.size());
    int big = 0;
    for (const int s : share) big += 4 * s >= total ? 1 : 0;
    // part_gap 0: any other footprint with a quarter of its features.
    for (std::size_t k = 0; part_gap <= 0 && k < n_parts; ++k) {
      if (mine[k] == 0 && 4 * cv[k] >= total) ++big;
    }
    out.merged = big >= 2;
  }
  const auto gap_to_mine = [&](std::size_t k) {
    double g = std::numeric_limits<double>::infinity();
    for (std::size_t j = 0; j < n_parts; ++j) {
      if (mine[j] != 0) g = std::min(g, gap_between(k, j));
    }
    return g;
  };
  out.gap = std::numeric_limits<double>::infinity();
  for (std::size_t b = 0; b < view.objects.size(); ++b) {
    if (static_cast<int>(b) == chosen) continue;
    const auto m = std::max_element(on[b].begin(), on[b].end());
    if (*m == 0) continue;
    const auto k = static_cast<std::size_t>(m - on[b].begin());
    out.blob_gaps[b] = mine[k] != 0 ? 0.0 : gap_to_mine(k);
  }
  for (std::size_t k = 0; k < n_parts; ++k) {
    if (mine[k] == 0) out.gap = std::min(out.gap, gap_to_mine(k));
  }
  // Another blob on the chosen footprint: two objects touching (or one standing on the other).
  for (const auto& g : out.blob_gaps) {
    if (g && *g == 0.0) out.gap = 0;
  }
  out.alone = !out.merged && out.gap >= clearance;
  const std::string gap =
      std::isfinite(out.gap) ? core::printf_string("%.3f m", out.gap) : std::string("none other");
  out.why = core::cat({"depth: ", std::to_string(fp.parts.size()), " footprints, gap ", gap,
                       out.merged ? ", the chosen blob lies on two footprints" : "",
                       out.alone ? ": alone" : ": not alone"});
  return out;
}

}  // namespace proprio::loop
