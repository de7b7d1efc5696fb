#pragma once
// Scores of a binary segmentation against ground truth (thesis 5.1.1, SPEC §3 metrics).

#include <cstdint>
#include <opencv2/core.hpp>

namespace proprio::eval {

struct MaskMetrics {
  std::int64_t true_positives = 0;
  std::int64_t false_positives = 0;
  std::int64_t false_negatives = 0;
  std::int64_t pixels = 0;
  /// tp / (tp + fp) (eq 5.1); 0 when nothing was segmented.
  double precision = 0.0;
  /// tp / (tp + fn) (eq 5.2); 1 when the truth is empty.
  double recall = 0.0;
  /// |A and B| / |A or B| = 1 - Tanimoto distance (eq 5.4); 1 when both are empty.
  double jaccard = 0.0;
  /// Root mean square difference of the two binary images, sqrt((fp + fn) / N): eq 5.3 without
  /// its extra division by sqrt(N K), which makes it unreadably small.
  double l2 = 0.0;
  [[nodiscard]] double tanimoto() const { return 1.0 - jaccard; }
};

/// Compares `result` with `truth` (same size, 8-bit single channel, nonzero = object). Sizes
/// differing is a programming error (assert).
MaskMetrics compare_masks(const cv::Mat& result, const cv::Mat& truth);

}  // namespace proprio::eval
