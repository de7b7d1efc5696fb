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

  /// Output only: a mask's scores as segment.json records them ("metrics").
  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.precision, {"precision", "tp / (tp + fp) (eq 5.1)"});
    v(self.recall, {"recall", "tp / (tp + fn) (eq 5.2)"});
    v(self.jaccard, {"jaccard", "|A and B| / |A or B| (eq 5.4)"});
    v(self.tanimoto(), {"tanimoto", "1 - jaccard"});
    v(self.l2, {"l2", "RMS difference of the binary images (eq 5.3)"});
    v(self.true_positives, {"true_positives", "Pixels"});
    v(self.false_positives, {"false_positives", "Pixels"});
    v(self.false_negatives, {"false_negatives", "Pixels"});
  }
};

/// Compares `result` with `truth` (same size, 8-bit single channel, nonzero = object). Sizes
/// differing is a programming error (assert).
MaskMetrics compare_masks(const cv::Mat& result, const cv::Mat& truth);

}  // namespace proprio::eval
