#include "proprio/eval/mask_metrics.hpp"

#include <cassert>
#include <cmath>

namespace proprio::eval {

MaskMetrics compare_masks(const cv::Mat& result, const cv::Mat& truth) {
  assert(result.size() == truth.size() && result.type() == CV_8UC1 && truth.type() == CV_8UC1);
  const cv::Mat a = result != 0, b = truth != 0;
  MaskMetrics m;
  m.pixels = static_cast<std::int64_t>(result.total());
  m.true_positives = cv::countNonZero(a & b);
  m.false_positives = cv::countNonZero(a & ~b);
  m.false_negatives = cv::countNonZero(~a & b);
  const double tp = static_cast<double>(m.true_positives);
  const double fp = static_cast<double>(m.false_positives);
  const double fn = static_cast<double>(m.false_negatives);
  m.precision = tp + fp > 0 ? tp / (tp + fp) : 0.0;
  m.recall = tp + fn > 0 ? tp / (tp + fn) : 1.0;
  m.jaccard = tp + fp + fn > 0 ? tp / (tp + fp + fn) : 1.0;
  m.l2 = m.pixels > 0 ? std::sqrt((fp + fn) / static_cast<double>(m.pixels)) : 0.0;
  return m;
}

}  // namespace proprio::eval
