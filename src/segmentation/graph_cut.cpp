#include "proprio/segmentation/graph_cut.hpp"

#include <algorithm>
#include <array>
#include <boost/graph/boykov_kolmogorov_max_flow.hpp>
#include <boost/graph/compressed_sparse_row_graph.hpp>
#include <cassert>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <opencv2/imgproc.hpp>
#include <utility>
#include <vector>

#include "proprio/core/error.hpp"

namespace proprio::segmentation {
namespace {

using Clock = std::chrono::steady_clock;
using Cap = std::int64_t;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// Neighbour offsets in an order where direction k's opposite is n - 1 - k, so that the reverse
// of an edge is found without a search.
struct Offset {
  int dx, dy;
};
constexpr std::array<Offset, 8> kOffsets8 = {
    {{-1, -1}, {0, -1}, {1, -1}, {-1, 0}, {1, 0}, {-1, 1}, {0, 1}, {1, 1}}};
constexpr std::array<Offset, 4> kOffsets4 = {{{0, -1}, {-1, 0}, {1, 0}, {0, 1}}};

const Offset* offsets(int connectivity) {
  return connectivity == 8 ? kOffsets8.data() : kOffsets4.data();
}

cv::Mat3f as_float_image(const cv::Mat& image) {
  cv::Mat f;
  if (image.channels() == 1) {
    cv::Mat c3;
    cv::cvtColor(image, c3, cv::COLOR_GRAY2BGR);
    c3.convertTo(f, CV_32FC3);
  } else {
    image.convertTo(f, CV_32FC3);
  }
  return f;
}

float sq_diff(const cv::Vec3f& a, const cv::Vec3f& b) {
  const cv::Vec3f d = a - b;
  return d.dot(d);
}

void check_problem(const GraphCutProblem& p) {
  const cv::Size size = p.size();
  require(size.area() > 0, "graph cut: empty grid");
  auto same = [&](const cv::Mat& m, const char* what) {
    if (!m.empty() && m.size() != size) {
      std::string msg = "graph cut: ";
      msg += what;
      msg += " has a different size from the other inputs";
      throw Error(msg);
    }
  };
  same(p.image, "the image");
  same(p.cost_object, "the object cost");
  same(p.cost_background, "the background cost");
  same(p.seeds, "the seed image");
  require(p.image.empty() || p.image.type() == CV_8UC3 || p.image.type() == CV_8UC1,
          "graph cut: the image must be 8-bit grey or BGR");
  for (const cv::Mat1f* c : {&p.cost_object, &p.cost_background}) {
    if (c->empty()) continue;
    require(cv::checkRange(*c, true, nullptr, 0.0, 1e12),
            "graph cut: unary costs must be finite and >= 0");
  }
  if (!p.seeds.empty()) {
    double mx = 0;
    cv::minMaxLoc(p.seeds, nullptr, &mx);
    require(mx <= kSeedBackground, "graph cut: seed values must be 0, 1 or 2");
  }
}

// The problem on a grid of at most max_side pixels a side. Unary costs are area averages scaled
// by 1/s (s < 1 the reduction factor): a reduced cell stands for 1/s^2 pixels whose boundary is
// 1/s pixels long, so scaling the unary by 1/s keeps the balance of unary and pairwise terms that
// the full grid has. A seed survives where any of its pixels falls in a cell (thin arm seeds must
// not vanish); cells with both kinds become free.
GraphCutProblem reduce(const GraphCutProblem& p, cv::Size small, double s) {
  GraphCutProblem r;
  if (!p.image.empty()) cv::resize(p.image, r.image, small, 0, 0, cv::INTER_AREA);
  auto cost = [&](const cv::Mat1f& c, cv::Mat1f& out) {
    if (c.empty()) return;
    cv::Mat tmp;
    cv::resize(c, tmp, small, 0, 0, cv::INTER_AREA);
    out = tmp * (1.0 / s);
  };
  cost(p.cost_object, r.cost_object);
  cost(p.cost_background, r.cost_background);
  if (!p.seeds.empty()) {
    cv::Mat obj, bg;
    cv::resize(cv::Mat(p.seeds == kSeedObject), obj, small, 0, 0, cv::INTER_AREA);
    cv::resize(cv::Mat(p.seeds == kSeedBackground), bg, small, 0, 0, cv::INTER_AREA);
    r.seeds = cv::Mat1b(small, kSeedFree);
    r.seeds.setTo(kSeedObject, (obj > 0) & (bg == 0));
    r.seeds.setTo(kSeedBackground, (bg > 0) & (obj == 0));
  }
  return r;
}

// Quantised terms of the energy of a (full or reduced) problem.
struct Terms {
  int width = 0, height = 0, degree = 0;
  std::vector<Cap> to_object;      // cost of labelling p object (p -> sink capacity)
  std::vector<Cap> to_background;  // cost of labelling p background (source -> p capacity)
  std::vector<Cap> pair;           // w of (p, direction k), 0 where the neighbour is outside
  double beta = 0.0;
};

Terms build_terms(const GraphCutProblem& p, const GraphCutOptions& o) {
  Terms t;
  const cv::Size size = p.size();
  t.width = size.width;
  t.height = size.height;
  t.degree = o.connectivity;
  const std::size_t n = static_cast<std::size_t>(size.area());
  const Offset* off = offsets(o.connectivity);
  t.pair.assign(n * t.degree, 0);
  cv::Mat3f img;
  if (!p.image.empty()) {
    img = as_float_image(p.image);
    t.beta = o.contrast_beta > 0 ? o.contrast_beta : contrast_beta(p.image, o.connectivity);
  }
  std::vector<Cap> pair_sum(n, 0);
  for (int y = 0; y < t.height; ++y) {
    for (int x = 0; x < t.width; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * t.width + x;
      for (int k = 0; k < t.degree; ++k) {
        const int qx = x + off[k].dx, qy = y + off[k].dy;
        if (qx < 0 || qy < 0 || qx >= t.width || qy >= t.height) continue;
        const double dist = (off[k].dx != 0 && off[k].dy != 0) ? std::sqrt(2.0) : 1.0;
        double w = o.smoothness / dist;
        if (!img.empty()) w *= std::exp(-t.beta * sq_diff(img(y, x), img(qy, qx)));
        t.pair[i * t.degree + k] = std::llround(w * o.cost_resolution);
        pair_sum[i] += t.pair[i * t.degree + k];
      }
    }
  }
  // Boykov-Jolly's K: more than any cut through one pixel's neighbour edges.
  const Cap k_hard = 1 + *std::max_element(pair_sum.begin(), pair_sum.end());
  t.to_object.assign(n, 0);
  t.to_background.assign(n, 0);
  for (int y = 0; y < t.height; ++y) {
    for (int x = 0; x < t.width; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * t.width + x;
      const unsigned char seed = p.seeds.empty() ? kSeedFree : p.seeds(y, x);
      if (seed == kSeedObject) {
        t.to_background[i] = k_hard;
      } else if (seed == kSeedBackground) {
        t.to_object[i] = k_hard;
      } else {
        if (!p.cost_object.empty()) {
          t.to_object[i] = std::llround(p.cost_object(y, x) * o.cost_resolution);
        }
        if (!p.cost_background.empty()) {
          t.to_background[i] = std::llround(p.cost_background(y, x) * o.cost_resolution);
        }
      }
    }
  }
  return t;
}

using Graph =
    boost::compressed_sparse_row_graph<boost::directedS, boost::no_property, boost::no_property,
                                       boost::no_property, std::uint32_t, std::uint32_t>;
using Edge = boost::graph_traits<Graph>::edge_descriptor;

// Max flow of the terms; `object` gets 1 for the pixels on the source side. Returns the flow
// plus the constant removed from the terminal capacities (= the minimum energy, quantised).
Cap solve(const Terms& t, std::vector<unsigned char>& object, GraphCutSummary& summary) {
  const auto t0 = Clock::now();
  const std::uint32_t n = static_cast<std::uint32_t>(t.to_object.size());
  const std::uint32_t source = n, sink = n + 1;
  const Offset* off = offsets(t.degree);

  // Edges sorted by source vertex: each pixel's neighbours, then p -> source, p -> sink; then
  // source -> every pixel; then sink -> every pixel.
  std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
  std::vector<Cap> cap;
  std::vector<std::int64_t> dir_edge(static_cast<std::size_t>(n) * t.degree, -1);
  std::vector<std::uint32_t> back_to_source(n), to_sink(n);
  Cap offset = 0;
  edges.reserve(static_cast<std::size_t>(n) * (t.degree + 4));
  cap.reserve(edges.capacity());
  std::vector<Cap> s_cap(n), t_cap(n);
  for (std::uint32_t i = 0; i < n; ++i) {
    const Cap m = std::min(t.to_object[i], t.to_background[i]);
    offset += m;
    s_cap[i] = t.to_background[i] - m;
    t_cap[i] = t.to_object[i] - m;
  }
  for (std::uint32_t i = 0; i < n; ++i) {
    const int x = static_cast<int>(i % t.width), y = static_cast<int>(i / t.width);
    for (int k = 0; k < t.degree; ++k) {
      const int qx = x + off[k].dx, qy = y + off[k].dy;
      if (qx < 0 || qy < 0 || qx >= t.width || qy >= t.height) continue;
      dir_edge[static_cast<std::size_t>(i) * t.degree + k] =
          static_cast<std::int64_t>(edges.size());
      edges.emplace_back(i, static_cast<std::uint32_t>(qy * t.width + qx));
      cap.push_back(t.pair[static_cast<std::size_t>(i) * t.degree + k]);
    }
    back_to_source[i] = static_cast<std::uint32_t>(edges.size());
    edges.emplace_back(i, source);
    cap.push_back(0);
    to_sink[i] = static_cast<std::uint32_t>(edges.size());
    edges.emplace_back(i, sink);
    cap.push_back(t_cap[i]);
  }
  const std::uint32_t first_from_source = static_cast<std::uint32_t>(edges.size());
  for (std::uint32_t i = 0; i < n; ++i) {
    edges.emplace_back(source, i);
    cap.push_back(s_cap[i]);
  }
  const std::uint32_t first_from_sink = static_cast<std::uint32_t>(edges.size());
  for (std::uint32_t i = 0; i < n; ++i) {
    edges.emplace_back(sink, i);
    cap.push_back(0);
  }
  std::vector<std::uint32_t> rev(edges.size());
  for (std::uint32_t i = 0; i < n; ++i) {
    for (int k = 0; k < t.degree; ++k) {
      const std::int64_t e = dir_edge[static_cast<std::size_t>(i) * t.degree + k];
      if (e < 0) continue;
      const std::uint32_t q = edges[static_cast<std::size_t>(e)].second;
      rev[static_cast<std::size_t>(e)] = static_cast<std::uint32_t>(
          dir_edge[static_cast<std::size_t>(q) * t.degree + (t.degree - 1 - k)]);
    }
    rev[back_to_source[i]] = first_from_source + i;
    rev[first_from_source + i] = back_to_source[i];
    rev[to_sink[i]] = first_from_sink + i;
    rev[first_from_sink + i] = to_sink[i];
  }

  Graph g(boost::edges_are_sorted, edges.begin(), edges.end(), n + 2);
  std::vector<Edge> descriptors(edges.size());
  for (auto [it, end] = boost::edges(g); it != end; ++it) descriptors[it->idx] = *it;
  std::vector<Edge> rev_desc(edges.size());
  for (std::size_t e = 0; e < edges.size(); ++e) rev_desc[e] = descriptors[rev[e]];
  std::vector<Cap> residual(edges.size(), 0);
  std::vector<boost::default_color_type> color(n + 2);
  const auto eidx = boost::get(boost::edge_index, g);
  const auto vidx = boost::get(boost::vertex_index, g);
  summary.nodes = n;
  summary.edges = static_cast<long long>(edges.size());
  summary.seconds_build = seconds_since(t0);

  const auto t1 = Clock::now();
  const Cap flow = boost::boykov_kolmogorov_max_flow(
      g, boost::make_iterator_property_map(cap.begin(), eidx),
      boost::make_iterator_property_map(residual.begin(), eidx),
      boost::make_iterator_property_map(rev_desc.begin(), eidx),
      boost::make_iterator_property_map(color.begin(), vidx), vidx, source, sink);
  summary.seconds_flow = seconds_since(t1);
  object.assign(n, 0);
  for (std::uint32_t i = 0; i < n; ++i) {
    object[i] = color[i] == boost::color_traits<boost::default_color_type>::black() ? 1 : 0;
  }
  return flow + offset;
}

}  // namespace

void GraphCutOptions::validate() const {
  require(connectivity == 4 || connectivity == 8, "graph cut: connectivity must be 4 or 8");
  require(std::isfinite(smoothness) && smoothness >= 0 && smoothness <= 1e6,
          "graph cut: smoothness must be in [0, 1e6]");
  require(std::isfinite(contrast_beta) && contrast_beta <= 1e6,
          "graph cut: contrast beta must be finite and <= 1e6 (<= 0: from the image)");
  require(max_side == 0 || (max_side >= 8 && max_side <= 100000),
          "graph cut: max side must be 0 (full size) or 8..100000 pixels");
  require(std::isfinite(cost_resolution) && cost_resolution >= 1 && cost_resolution <= 1e6,
          "graph cut: cost resolution must be in [1, 1e6]");
}

cv::Size GraphCutProblem::size() const {
  for (const cv::Mat* m :
       {&image, static_cast<const cv::Mat*>(&cost_object),
        static_cast<const cv::Mat*>(&cost_background), static_cast<const cv::Mat*>(&seeds)}) {
    if (!m->empty()) return m->size();
  }
  return {};
}

double contrast_beta(const cv::Mat& image, int connectivity) {
  assert(connectivity == 4 || connectivity == 8);
  const cv::Mat3f img = as_float_image(image);
  const Offset* off = offsets(connectivity);
  double sum = 0;
  long long count = 0;
  for (int y = 0; y < img.rows; ++y) {
    for (int x = 0; x < img.cols; ++x) {
      // Each unordered pair once: the second half of the directions.
      for (int k = connectivity / 2; k < connectivity; ++k) {
        const int qx = x + off[k].dx, qy = y + off[k].dy;
        if (qx < 0 || qy < 0 || qx >= img.cols || qy >= img.rows) continue;
        sum += sq_diff(img(y, x), img(qy, qx));
        ++count;
      }
    }
  }
  return (count == 0 || sum <= 0) ? 0.0 : 1.0 / (2.0 * sum / count);
}

void unary_from_probability(const cv::Mat1f& probability, cv::Mat1f& cost_object,
                            cv::Mat1f& cost_background, double eps) {
  assert(eps > 0 && eps < 0.5);
  require(cv::checkRange(probability, true, nullptr, 0.0, 1.0 + 1e-6),
          "graph cut: probabilities must be in [0, 1] (no NaN)");
  cost_object.create(probability.size());
  cost_background.create(probability.size());
  for (int y = 0; y < probability.rows; ++y) {
    for (int x = 0; x < probability.cols; ++x) {
      const double p = std::clamp(static_cast<double>(probability(y, x)), 0.0, 1.0);
      // max(0, .) turns -0.0 (= -log 1) into +0.0, which checkRange would refuse.
      cost_object(y, x) = static_cast<float>(std::max(0.0, -std::log(std::max(p, eps))));
      cost_background(y, x) = static_cast<float>(std::max(0.0, -std::log(std::max(1.0 - p, eps))));
    }
  }
}

double cut_energy(const GraphCutProblem& problem, const GraphCutOptions& options,
                  const cv::Mat1b& mask) {
  options.validate();
  check_problem(problem);
  assert(mask.size() == problem.size());
  const Terms t = build_terms(problem, options);
  const Offset* off = offsets(t.degree);
  Cap e = 0;
  for (int y = 0; y < t.height; ++y) {
    for (int x = 0; x < t.width; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * t.width + x;
      const bool obj = mask(y, x) != 0;
      e += obj ? t.to_object[i] : t.to_background[i];
      // Each unordered pair once.
      for (int k = t.degree / 2; k < t.degree; ++k) {
        const int qx = x + off[k].dx, qy = y + off[k].dy;
        if (qx < 0 || qy < 0 || qx >= t.width || qy >= t.height) continue;
        if (obj != (mask(qy, qx) != 0)) e += t.pair[i * t.degree + k];
      }
    }
  }
  return static_cast<double>(e) / options.cost_resolution;
}

GraphCutResult graph_cut(const GraphCutProblem& problem, const GraphCutOptions& options) {
  options.validate();
  check_problem(problem);
  const cv::Size size = problem.size();
  GraphCutResult r;
  r.summary.message = "minimum cut found";
  const int side = std::max(size.width, size.height);
  const bool reduce_grid = options.max_side > 0 && side > options.max_side;
  GraphCutProblem reduced;
  cv::Size grid = size;
  if (reduce_grid) {
    const double s = static_cast<double>(options.max_side) / side;
    grid = cv::Size(std::max(1, static_cast<int>(std::lround(size.width * s))),
                    std::max(1, static_cast<int>(std::lround(size.height * s))));
    reduced = reduce(problem, grid, s);
  }
  const GraphCutProblem& p = reduce_grid ? reduced : problem;
  const Terms t = build_terms(p, options);
  std::vector<unsigned char> object;
  const Cap energy = solve(t, object, r.summary);
  r.summary.width = grid.width;
  r.summary.height = grid.height;
  r.summary.reduced = reduce_grid;
  r.summary.beta = t.beta;
  r.summary.flow = static_cast<double>(energy) / options.cost_resolution;

  cv::Mat1b small(grid);
  for (int y = 0; y < grid.height; ++y) {
    for (int x = 0; x < grid.width; ++x) {
      small(y, x) = object[static_cast<std::size_t>(y) * grid.width + x] ? 255 : 0;
    }
  }
  if (reduce_grid) {
    cv::Mat up;
    cv::resize(small, up, size, 0, 0, cv::INTER_LINEAR);
    r.mask = up >= 128;
    if (!problem.seeds.empty()) {
      r.mask.setTo(255, problem.seeds == kSeedObject);
      r.mask.setTo(0, problem.seeds == kSeedBackground);
    }
  } else {
    r.mask = small;
  }
  r.summary.object_pixels = cv::countNonZero(r.mask);
  return r;
}

void MlGraphCutOptions::validate() const {
  require(std::isfinite(mask_fraction) && mask_fraction > 0 && mask_fraction <= 1,
          "ml-graphcut: mask fraction must be in (0, 1]");
  require(std::isfinite(unary_weight) && unary_weight > 0 && unary_weight <= 1e4,
          "ml-graphcut: unary weight must be in (0, 1e4]");
  graph_cut.validate();
}

GraphCutResult ml_graph_cut(const cv::Mat& image, const cv::Mat1f& map,
                            const MlGraphCutOptions& options) {
  options.validate();
  require(!map.empty() && image.size() == map.size(),
          "ml-graphcut: the frame and the map have different sizes");
  require(cv::checkRange(map, true, nullptr, 0.0, 1e30), "ml-graphcut: the map holds NaN or < 0");
  double mx = 0;
  cv::minMaxLoc(map, nullptr, &mx);
  GraphCutResult r;
  if (mx <= 0) {
    r.mask = cv::Mat1b(map.size(), uchar(0));
    r.summary.message = "the map is zero: no object";
    return r;
  }
  const cv::Mat1f m = map * (1.0 / mx);
  const float f = static_cast<float>(options.mask_fraction);
  const float w = static_cast<float>(options.unary_weight);
  GraphCutProblem p;
  p.image = image;
  p.cost_object = cv::Mat1f(map.size());
  p.cost_background = cv::Mat1f(map.size());
  for (int y = 0; y < m.rows; ++y) {
    for (int x = 0; x < m.cols; ++x) {
      const float d = m(y, x) - f;
      p.cost_object(y, x) = d < 0 ? -w * d : 0.f;
      p.cost_background(y, x) = d > 0 ? w * d : 0.f;
    }
  }
  return graph_cut(p, options.graph_cut);
}

}  // namespace proprio::segmentation
