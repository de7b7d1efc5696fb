#include "proprio/segmentation/region_tracker.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <opencv2/ximgproc.hpp>
#include <utility>
#include <vector>

namespace proprio::segmentation {

namespace {

// Labels connected pixels of identical colour (the regions of mean-shift filtering).
cv::Mat1i label_equal_colours(const cv::Mat3b& img, int& count) {
  cv::Mat1i labels(img.size(), -1);
  std::vector<cv::Point> stack;
  count = 0;
  for (int y = 0; y < img.rows; ++y) {
    for (int x = 0; x < img.cols; ++x) {
      if (labels(y, x) >= 0) continue;
      const cv::Vec3b c = img(y, x);
      labels(y, x) = count;
      stack.assign(1, {x, y});
      while (!stack.empty()) {
        const cv::Point p = stack.back();
        stack.pop_back();
        const cv::Point nb[4] = {{p.x + 1, p.y}, {p.x - 1, p.y}, {p.x, p.y + 1}, {p.x, p.y - 1}};
        for (const auto& q : nb) {
          if (q.x < 0 || q.y < 0 || q.x >= img.cols || q.y >= img.rows) continue;
          if (labels(q) >= 0 || img(q) != c) continue;
          labels(q) = count;
          stack.push_back(q);
        }
      }
      ++count;
    }
  }
  return labels;
}

}  // namespace

cv::Mat1i split_at_depth_steps(const cv::Mat1i& labels, const cv::Mat1f& depth, double max_step,
                               int& count) {
  assert(labels.size() == depth.size() && max_step > 0);
  cv::Mat1i out(labels.size(), -1);
  std::vector<cv::Point> stack;
  count = 0;
  const auto step = static_cast<float>(max_step);
  for (int y = 0; y < labels.rows; ++y) {
    for (int x = 0; x < labels.cols; ++x) {
      if (out(y, x) >= 0) continue;
      out(y, x) = count;
      stack.assign(1, {x, y});
      while (!stack.empty()) {
        const cv::Point p = stack.back();
        stack.pop_back();
        const int l = labels(p);
        const float d = depth(p);
        const cv::Point nb[4] = {{p.x + 1, p.y}, {p.x - 1, p.y}, {p.x, p.y + 1}, {p.x, p.y - 1}};
        for (const auto& q : nb) {
          if (q.x < 0 || q.y < 0 || q.x >= labels.cols || q.y >= labels.rows) continue;
          if (out(q) >= 0 || labels(q) != l) continue;
          const float e = depth(q);
          if (d > 0 && e > 0 && std::abs(d - e) > step) continue;
          out(q) = count;
          stack.push_back(q);
        }
      }
      ++count;
    }
  }
  return out;
}

struct OverSegmenter::Impl {
  OverSegmentation method;
  int region_count;
  int iterations;
  cv::Size size;
  cv::Ptr<cv::ximgproc::SuperpixelSEEDS> seeds;
  cv::Mat lab;
};

OverSegmenter::OverSegmenter(OverSegmentation method, int region_count, int iterations,
                             cv::Size size)
    : impl_(std::make_unique<Impl>()) {
  assert(region_count > 0 && iterations > 0 && !size.empty());
  impl_->method = method;
  impl_->region_count = region_count;
  impl_->iterations = iterations;
  impl_->size = size;
  if (method == OverSegmentation::kSeeds) {
    impl_->seeds = cv::ximgproc::createSuperpixelSEEDS(size.width, size.height, 3, region_count,
                                                       /*num_levels=*/4, /*prior=*/2,
                                                       /*histogram_bins=*/5);
  }
}

OverSegmenter::~OverSegmenter() = default;
OverSegmenter::OverSegmenter(OverSegmenter&&) noexcept = default;
OverSegmenter& OverSegmenter::operator=(OverSegmenter&&) noexcept = default;

cv::Mat1i OverSegmenter::segment(const cv::Mat& bgr, int& count) {
  assert(bgr.size() == impl_->size && bgr.type() == CV_8UC3);
  cv::Mat1i labels;
  switch (impl_->method) {
    case OverSegmentation::kSeeds: {
      cv::cvtColor(bgr, impl_->lab, cv::COLOR_BGR2Lab);
      impl_->seeds->iterate(impl_->lab, impl_->iterations);
      impl_->seeds->getLabels(labels);
      count = impl_->seeds->getNumberOfSuperpixels();
      break;
    }
    case OverSegmentation::kSlic: {
      cv::cvtColor(bgr, impl_->lab, cv::COLOR_BGR2Lab);
      const int region_size = std::max(
          4, static_cast<int>(std::sqrt(impl_->size.area() / double(impl_->region_count))));
      auto slic = cv::ximgproc::createSuperpixelSLIC(impl_->lab, cv::ximgproc::SLICO, region_size);
      slic->iterate(5 * impl_->iterations);
      slic->enforceLabelConnectivity();
      slic->getLabels(labels);
      count = slic->getNumberOfSuperpixels();
      break;
    }
    case OverSegmentation::kMeanShift: {
      // The thesis's front end: mean-shift filtering in (x, y, colour), then its flat regions.
      cv::Mat3b filtered;
      cv::pyrMeanShiftFiltering(bgr, filtered, /*sp=*/8, /*sr=*/16, /*maxLevel=*/1);
      labels = label_equal_colours(filtered, count);
      break;
    }
  }
  return labels;
}

cv::Mat1i RegionTracker::update(const cv::Mat1i& superpixels, int count,
                                const cv::Mat2f& back_flow) {
  cv::Mat1i tracks(superpixels.size());
  std::vector<int> lut(count, -1);
  votes_.clear();
  ended_.clear();
  if (!previous_.empty() && !back_flow.empty()) {
    assert(back_flow.size() == superpixels.size() && previous_.size() == superpixels.size());
    // Votes of each superpixel for the tracks its pixels came from (every 2nd pixel each way).
    votes_.assign(count, {});
    auto& votes = votes_;
    std::vector<int> samples(count, 0);
    const int w = superpixels.cols, h = superpixels.rows;
    for (int y = 0; y < h; y += 2) {
      const int* sp = superpixels[y];
      const cv::Vec2f* f = back_flow[y];
      for (int x = 0; x < w; x += 2) {
        const int s = sp[x];
        ++samples[s];
        const int px = static_cast<int>(std::lround(x + f[x][0]));
        const int py = static_cast<int>(std::lround(y + f[x][1]));
        if (px < 0 || py < 0 || px >= w || py >= h) continue;
        const int t = previous_(py, px);
        auto& v = votes[s];
        auto it = std::find_if(v.begin(), v.end(), [t](const auto& e) { return e.first == t; });
        if (it == v.end()) {
          v.emplace_back(t, 1);
        } else {
          ++it->second;
        }
      }
    }
    for (int s = 0; s < count; ++s) {
      int best = -1, best_n = 0;
      for (const auto& [t, n] : votes[s]) {
        if (n > best_n) {
          best = t;
          best_n = n;
        }
      }
      if (best >= 0 && best_n >= min_overlap_ * samples[s]) lut[s] = best;
    }
  }
  std::vector<int> parent_of(count, -1);
  for (int s = 0; s < count; ++s) {
    if (lut[s] >= 0 || votes_.empty()) continue;
    int n_best = 0;
    for (const auto& [t, n] : votes_[s]) {
      if (n > n_best) {
        n_best = n;
        parent_of[s] = t;
      }
    }
  }
  // Superpixels that cover some pixel (a label may be unused).
  std::vector<char> present(count, 0);
  // Row pointers: a cv::Mat iterator compared with end() builds the end iterator (seek) at every
  // pixel, which cost more than the rest of the tracker.
  for (int y = 0; y < superpixels.rows; ++y) {
    const int* sp = superpixels[y];
    for (int x = 0; x < superpixels.cols; ++x) present[static_cast<size_t>(sp[x])] = 1;
  }
  created_.clear();
  for (int s = 0; s < count; ++s) {
    if (lut[s] < 0) {
      lut[s] = next_id_++;
      if (present[s]) created_.emplace_back(lut[s], parent_of[s]);
    }
  }
  // A previous track that claimed no superpixel ends; it hands over to the track that got most
  // of its pixels. Previous tracks are indexed by their place in live_ (sorted ids).
  const auto place = [this](int t) {
    const auto it = std::lower_bound(live_.begin(), live_.end(), t);
    assert(it != live_.end() && *it == t);
    return static_cast<size_t>(it - live_.begin());
  };
  std::vector<int> now;
  for (int s = 0; s < count; ++s)
    if (present[s]) now.push_back(lut[s]);
  std::sort(now.begin(), now.end());
  now.erase(std::unique(now.begin(), now.end()), now.end());
  std::vector<char> alive(live_.size(), 0);
  for (int t : now) {
    const auto it = std::lower_bound(live_.begin(), live_.end(), t);
    if (it != live_.end() && *it == t) alive[static_cast<size_t>(it - live_.begin())] = 1;
  }
  std::vector<std::pair<int, int>> best(live_.size(), {-1, 0});  // (superpixel, votes)
  for (int s = 0; s < static_cast<int>(votes_.size()); ++s) {
    for (const auto& [t, n] : votes_[s]) {
      const size_t k = place(t);
      if (!alive[k] && n > best[k].second) best[k] = {s, n};
    }
  }
  for (size_t k = 0; k < live_.size(); ++k) {
    if (!alive[k]) ended_.emplace_back(live_[k], best[k].first >= 0 ? lut[best[k].first] : -1);
  }
  live_ = std::move(now);
  for (int y = 0; y < tracks.rows; ++y) {
    const int* sp = superpixels[y];
    int* t = tracks[y];
    for (int x = 0; x < tracks.cols; ++x) t[x] = lut[sp[x]];
  }
  previous_ = tracks;
  return tracks;
}

}  // namespace proprio::segmentation
