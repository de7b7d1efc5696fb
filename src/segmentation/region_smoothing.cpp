#include "proprio/segmentation/region_smoothing.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <utility>

#include "proprio/core/error.hpp"
#include "proprio/core/text.hpp"

namespace proprio::segmentation {

void RegionSmoothingOptions::validate() const {
  require(
      std::isfinite(data_weight) && data_weight >= 0,
      core::cat({"RegionSmoothingOptions.data_weight must be >= 0, got ", core::num(data_weight)}));
  require(std::isfinite(colour_sigma) && colour_sigma > 0,
          core::cat(
              {"RegionSmoothingOptions.colour_sigma must be > 0, got ", core::num(colour_sigma)}));
  require(
      std::isfinite(depth_step) && depth_step >= 0,
      core::cat({"RegionSmoothingOptions.depth_step must be >= 0, got ", core::num(depth_step)}));
  require(max_sweeps >= 1, "RegionSmoothingOptions.max_sweeps must be >= 1");
  require(std::isfinite(tolerance) && tolerance > 0,
          "RegionSmoothingOptions.tolerance must be > 0");
}

// Written here: OpenCV has no smoothing on a region graph, and the graph has only a few hundred
// nodes a frame.
RegionSmoothingSummary smooth_region_scores(const cv::Mat1i& lab, const std::vector<int>& evidence,
                                            const std::vector<Eigen::Vector3f>& colour,
                                            const RegionSmoothingOptions& options,
                                            std::vector<float>& score, const cv::Mat1f& depth) {
  options.validate();
  assert(evidence.size() == colour.size() && evidence.size() == score.size());
  const bool cut = options.depth_step > 0 && !depth.empty();
  assert(!cut || depth.size() == lab.size());
  const auto step = static_cast<float>(options.depth_step);
  RegionSmoothingSummary summary;
  std::vector<int> local(evidence.size(), -1);
  std::vector<int> ids;  // local index -> label
  const auto index = [&](int t) {
    assert(t >= 0 && t < static_cast<int>(local.size()));
    if (local[t] < 0) {
      local[t] = static_cast<int>(ids.size());
      ids.push_back(t);
    }
    return local[t];
  };
  // (i << 32 | j), i < j local -> (length, length without a depth step)
  std::unordered_map<std::uint64_t, std::pair<int, int>> boundary;
  const auto touch = [&](int a, int b, float za, float zb) {
    const auto i = static_cast<std::uint64_t>(index(a));
    const auto j = static_cast<std::uint64_t>(index(b));
    if (i == j) return;
    auto& [length, joined] = boundary[(std::min(i, j) << 32) | std::max(i, j)];
    ++length;
    if (!(za > 0 && zb > 0 && std::abs(za - zb) > step)) ++joined;
  };
  for (int y = 0; y < lab.rows; ++y) {
    const int* row = lab[y];
    const int* below = y + 1 < lab.rows ? lab[y + 1] : nullptr;
    const float* z = cut ? depth[y] : nullptr;
    const float* zb = cut && below ? depth[y + 1] : nullptr;
    for (int x = 0; x < lab.cols; ++x) {
      const float z0 = z ? z[x] : 0.0F;
      if (x + 1 < lab.cols) touch(row[x], row[x + 1], z0, z ? z[x + 1] : 0.0F);
      if (below) touch(row[x], below[x], z0, zb ? zb[x] : 0.0F);
    }
  }
  const int n = static_cast<int>(ids.size());
  summary.regions = n;
  std::vector<std::vector<std::pair<int, double>>> neighbours(n);
  std::vector<double> perimeter(n, 0.0);
  const double k = 1.0 / (2.0 * options.colour_sigma * options.colour_sigma);
  for (const auto& [key, lengths] : boundary) {
    const auto i = static_cast<int>(key >> 32);
    const auto j = static_cast<int>(key & 0xffffffffU);
    const auto [length, joined] = lengths;
    if (joined > 0) {
      const double w = joined * std::exp(-k * (colour[ids[i]] - colour[ids[j]]).squaredNorm());
      neighbours[i].emplace_back(j, w);
      neighbours[j].emplace_back(i, w);
    }
    perimeter[i] += length;
    perimeter[j] += length;
  }
  // Id order makes the sweeps independent of the hash map's order.
  std::vector<int> order(n);
  for (int i = 0; i < n; ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](int a, int b) { return ids[a] < ids[b]; });
  for (auto& list : neighbours) std::sort(list.begin(), list.end());
  std::vector<double> alpha(n), own(n);
  // A region without evidence has no value until a neighbour gives it one; until then it does
  // not pull on its neighbours.
  std::vector<char> valued(n);
  for (int i = 0; i < n; ++i) {
    alpha[i] = options.data_weight * evidence[ids[i]] * perimeter[i];
    own[i] = score[ids[i]];
    valued[i] = evidence[ids[i]] > 0 ? 1 : 0;
    summary.without_evidence += valued[i] ? 0 : 1;
  }
  if (summary.without_evidence == n) return summary;  // nothing to anchor the field
  while (summary.sweeps < options.max_sweeps) {
    ++summary.sweeps;
    double change = 0.0;
    bool reached = false;  // a region got its first value: its neighbours change next sweep
    for (int i : order) {
      double sw = alpha[i];
      double sv = alpha[i] * own[i];
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
    if (!reached && change < options.tolerance) {
      summary.converged = true;
      break;
    }
  }
  return summary;
}

}  // namespace proprio::segmentation
