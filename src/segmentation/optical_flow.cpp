#include "proprio/segmentation/optical_flow.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

namespace proprio::segmentation {

namespace {
// Grid spacing of the thesis's dense Lucas-Kanade, pixels.
constexpr int kLkGrid = 4;
}  // namespace

struct DenseFlow::Impl {
  FlowMethod method;
  cv::Ptr<cv::DISOpticalFlow> dis;
  cv::Ptr<cv::FarnebackOpticalFlow> farneback;
};

DenseFlow::DenseFlow(FlowMethod method) : impl_(std::make_unique<Impl>()) {
  impl_->method = method;
  switch (method) {
    case FlowMethod::kDisUltrafast:
      impl_->dis = cv::DISOpticalFlow::create(cv::DISOpticalFlow::PRESET_ULTRAFAST);
      break;
    case FlowMethod::kDisFast:
      impl_->dis = cv::DISOpticalFlow::create(cv::DISOpticalFlow::PRESET_FAST);
      break;
    case FlowMethod::kDisMedium:
      impl_->dis = cv::DISOpticalFlow::create(cv::DISOpticalFlow::PRESET_MEDIUM);
      break;
    case FlowMethod::kFarneback:
      impl_->farneback = cv::FarnebackOpticalFlow::create(3, 0.5, false, 15, 3, 5, 1.2);
      break;
    case FlowMethod::kLucasKanadeGrid:
      break;
  }
}

DenseFlow::~DenseFlow() = default;
DenseFlow::DenseFlow(DenseFlow&&) noexcept = default;
DenseFlow& DenseFlow::operator=(DenseFlow&&) noexcept = default;

cv::Mat2f DenseFlow::compute(const cv::Mat1b& from, const cv::Mat1b& to) {
  assert(from.size() == to.size() && !from.empty());
  cv::Mat2f flow;
  if (impl_->dis) {
    impl_->dis->calc(from, to, flow);
  } else if (impl_->farneback) {
    impl_->farneback->calc(from, to, flow);
  } else {
    // Pyramidal Lucas-Kanade (Bouguet) on a grid, then bilinear interpolation to every pixel.
    const int gw = (from.cols + kLkGrid - 1) / kLkGrid;
    const int gh = (from.rows + kLkGrid - 1) / kLkGrid;
    std::vector<cv::Point2f> p0;
    p0.reserve(static_cast<size_t>(gw) * gh);
    for (int y = 0; y < gh; ++y)
      for (int x = 0; x < gw; ++x)
        p0.emplace_back(static_cast<float>(std::min(x * kLkGrid, from.cols - 1)),
                        static_cast<float>(std::min(y * kLkGrid, from.rows - 1)));
    std::vector<cv::Point2f> p1;
    std::vector<uchar> status;
    std::vector<float> err;
    cv::calcOpticalFlowPyrLK(from, to, p0, p1, status, err, cv::Size(15, 15), 3);
    cv::Mat2f grid(gh, gw);
    for (int i = 0; i < gh * gw; ++i) {
      const cv::Point2f d = status[i] ? p1[i] - p0[i] : cv::Point2f(0, 0);
      grid(i / gw, i % gw) = cv::Vec2f(d.x, d.y);
    }
    cv::resize(grid, flow, from.size(), 0, 0, cv::INTER_LINEAR);
  }
  return flow;
}

GlobalMotion estimate_global_motion(const cv::Mat2f& flow, const cv::Mat1b& image,
                                    const GlobalMotionOptions& options) {
  assert(options.stride >= 1 && options.threshold > 0 && image.size() == flow.size());
  GlobalMotion g;
  std::vector<cv::Point2f> from, to;
  for (int y = std::max(1, options.stride / 2); y + 1 < flow.rows; y += options.stride) {
    const cv::Vec2f* f = flow[y];
    const uchar* up = image[y - 1];
    const uchar* row = image[y];
    const uchar* down = image[y + 1];
    for (int x = std::max(1, options.stride / 2); x + 1 < flow.cols; x += options.stride) {
      if (!std::isfinite(f[x][0]) || !std::isfinite(f[x][1])) continue;
      const int texture = std::abs(row[x + 1] - row[x - 1]) + std::abs(down[x] - up[x]);
      if (texture < options.min_texture) continue;
      from.emplace_back(static_cast<float>(x), static_cast<float>(y));
      to.emplace_back(static_cast<float>(x) + f[x][0], static_cast<float>(y) + f[x][1]);
    }
  }
  if (from.size() < 4) return g;
  cv::Mat inliers;
  const cv::Mat h = cv::findHomography(from, to, cv::RANSAC, options.threshold, inliers);
  if (h.empty()) return g;
  g.inlier_fraction = cv::countNonZero(inliers) / static_cast<double>(from.size());
  if (g.inlier_fraction < options.min_inlier_fraction) return g;
  float x0 = static_cast<float>(flow.cols), y0 = static_cast<float>(flow.rows), x1 = 0, y1 = 0;
  for (size_t i = 0; i < from.size(); ++i) {
    if (!inliers.at<uchar>(static_cast<int>(i))) continue;
    x0 = std::min(x0, from[i].x);
    y0 = std::min(y0, from[i].y);
    x1 = std::max(x1, from[i].x);
    y1 = std::max(y1, from[i].y);
  }
  if (x1 - x0 < options.min_inlier_extent * (flow.cols - 1) ||
      y1 - y0 < options.min_inlier_extent * (flow.rows - 1))
    return g;
  g.homography = cv::Matx33d(h);
  g.found = true;
  const cv::Vec3d c(0.5 * (flow.cols - 1), 0.5 * (flow.rows - 1), 1.0);
  const cv::Vec3d moved = g.homography * c;
  g.centre_motion = std::hypot(moved[0] / moved[2] - c[0], moved[1] / moved[2] - c[1]);
  return g;
}

void carry_points(std::vector<Eigen::Vector2f>& points, const cv::Mat2f& back_flow, double scale) {
  assert(scale > 0 && !back_flow.empty());
  const auto s = static_cast<float>(scale);
  const auto flow_at = [&](const Eigen::Vector2f& q) {
    const int x = std::clamp(static_cast<int>(std::lround(q.x())), 0, back_flow.cols - 1);
    const int y = std::clamp(static_cast<int>(std::lround(q.y())), 0, back_flow.rows - 1);
    const cv::Vec2f f = back_flow(y, x);
    return Eigen::Vector2f(f[0], f[1]);
  };
  for (Eigen::Vector2f& p : points) {
    const Eigen::Vector2f q = p / s;  // processing pixels
    Eigen::Vector2f x = q - flow_at(q);
    x = q - flow_at(x);
    p = x * s;
  }
}

}  // namespace proprio::segmentation
