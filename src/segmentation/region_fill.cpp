#include "proprio/segmentation/region_fill.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <utility>

namespace proprio::segmentation {

// Written here: OpenCV has no label propagation on a region graph, and the graph has only a few
// hundred nodes a frame. Only boundaries that touch a region without evidence are counted.
RegionFillSummary fill_unknown_scores(const cv::Mat1i& lab, const std::vector<char>& known,
                                      const std::vector<Eigen::Vector3f>& colour, double sigma,
                                      std::vector<float>& score) {
  assert(sigma > 0 && known.size() == colour.size() && known.size() == score.size());
  RegionFillSummary summary;
  std::vector<int> local(known.size(), -1);
  std::vector<int> ids;  // local index -> label
  const auto index = [&](int t) {
    if (local[t] < 0) {
      local[t] = static_cast<int>(ids.size());
      ids.push_back(t);
    }
    return local[t];
  };
  // Boundary lengths between a region without evidence and any neighbour.
  std::unordered_map<std::uint64_t, int> boundary;
  const auto touch = [&](int a, int b) {
    if (a == b || (known[a] && known[b])) return;
    const auto i = static_cast<std::uint64_t>(index(std::min(a, b)));
    const auto j = static_cast<std::uint64_t>(index(std::max(a, b)));
    ++boundary[(i << 32) | j];
  };
  for (int y = 0; y < lab.rows; ++y) {
    const int* row = lab[y];
    assert(std::all_of(row, row + lab.cols,
                       [&](int l) { return l >= 0 && l < static_cast<int>(known.size()); }));
    const int* below = y + 1 < lab.rows ? lab[y + 1] : nullptr;
    for (int x = 0; x < lab.cols; ++x) {
      if (x + 1 < lab.cols) touch(row[x], row[x + 1]);
      if (below) touch(row[x], below[x]);
    }
  }
  for (int t : ids) summary.unknown += known[t] ? 0 : 1;
  if (boundary.empty()) return summary;
  std::vector<std::vector<std::pair<int, double>>> neighbours(ids.size());
  const double k = 1.0 / (2.0 * sigma * sigma);
  for (const auto& [key, length] : boundary) {
    const auto i = static_cast<int>(key >> 32);
    const auto j = static_cast<int>(key & 0xffffffffU);
    const double w = length * std::exp(-k * (colour[ids[i]] - colour[ids[j]]).squaredNorm());
    neighbours[i].emplace_back(j, w);
    neighbours[j].emplace_back(i, w);
  }
  // Unknown regions in label order (deterministic).
  std::vector<int> unknown;
  for (size_t i = 0; i < ids.size(); ++i)
    if (!known[ids[i]] && !neighbours[i].empty()) unknown.push_back(static_cast<int>(i));
  std::sort(unknown.begin(), unknown.end(), [&](int a, int b) { return ids[a] < ids[b]; });
  std::vector<char> valued(ids.size(), 0);
  for (size_t i = 0; i < ids.size(); ++i) valued[i] = known[ids[i]];
  constexpr int kMaxSweeps = 50;
  constexpr double kTolerance = 1e-4;
  while (summary.sweeps < kMaxSweeps) {
    ++summary.sweeps;
    double change = 0.0;
    bool reached = false;  // a region got its first score: its neighbours change next sweep
    for (int i : unknown) {
      double sw = 0.0, sv = 0.0;
      for (const auto& [j, w] : neighbours[i]) {
        if (!valued[j]) continue;
        sw += w;
        sv += w * score[ids[j]];
      }
      if (!(sw > 1e-12)) continue;
      const auto v = static_cast<float>(sv / sw);
      change = std::max(change, static_cast<double>(std::abs(v - score[ids[i]])));
      score[ids[i]] = v;
      reached = reached || !valued[i];
      valued[i] = 1;
    }
    if (!reached && change < kTolerance) {
      summary.converged = true;
      break;
    }
  }
  for (int i : unknown) summary.filled += valued[i];
  return summary;
}

}  // namespace proprio::segmentation
