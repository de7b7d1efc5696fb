#include "proprio/segmentation/optical_flow.hpp"

#include <cassert>
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

}  // namespace proprio::segmentation
