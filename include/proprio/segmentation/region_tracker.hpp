#pragma once
// Low-level over-segmentation tracked through a video (step 1 of thesis 4.1).
//
// The thesis segments the whole video at once by mean shift in (r, g, b, x, y, frame); its
// regions keep one identity over time, but its cost grows with the video. Per-frame superpixels
// (SEEDS, SLIC) are fast but carry no identity between frames, so identities are carried here by
// the flow: the previous frame's track labels are warped into the current frame (backward flow,
// nearest neighbour) and every new superpixel takes the track that covers most of it; a
// superpixel covered less than half by any one track (newly uncovered background, image borders)
// starts a new track. Several superpixels may join one track; a track that no superpixel
// claims ends. Cost per frame is constant, as 4.7 asks.

#include <memory>
#include <opencv2/core.hpp>
#include <utility>
#include <vector>

#include "proprio/segmentation/ml_segmentation.hpp"

namespace proprio::segmentation {

/// Per-frame over-segmentation: labels (CV_32S, 0..count-1) of an 8-bit BGR image.
class OverSegmenter {
 public:
  OverSegmenter(OverSegmentation method, int region_count, int iterations, cv::Size size);
  ~OverSegmenter();
  OverSegmenter(OverSegmenter&&) noexcept;
  OverSegmenter& operator=(OverSegmenter&&) noexcept;
  /// Labels of `bgr` (of the constructor's size); `count` receives the number of labels.
  [[nodiscard]] cv::Mat1i segment(const cv::Mat& bgr, int& count);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Depth discontinuities as region boundaries (the depth variant, thesis 9.2): `labels`' regions
/// (CV_32S, 0..count-1) cut into their 4-connected pieces that no depth step crosses. Two
/// neighbouring pixels are joined when they have the same label and their depths (`depth`,
/// CV_32F, millimetres, of labels' size; 0 = unknown) differ by at most `max_step` mm or either
/// is unknown (holes neither cut nor join regions of their own). Returns the new labels
/// (0..count'-1, numbered in scan order) and sets `count` to their number.
cv::Mat1i split_at_depth_steps(const cv::Mat1i& labels, const cv::Mat1f& depth, double max_step,
                               int& count);

/// Track identities across frames (see above).
class RegionTracker {
 public:
  /// `min_overlap`: the fraction of a superpixel one warped track must cover to claim it.
  explicit RegionTracker(double min_overlap = 0.5) : min_overlap_(min_overlap) {}
  /// Track labels (CV_32S, >= 0) of a frame given its superpixels (`count` labels) and the flow
  /// from this frame to the previous one (`back_flow`, CV_32FC2; empty for the first frame).
  [[nodiscard]] cv::Mat1i update(const cv::Mat1i& superpixels, int count,
                                 const cv::Mat2f& back_flow);
  /// Tracks created so far (ids are 0..track_count()-1, never reused).
  [[nodiscard]] int track_count() const { return next_id_; }
  /// The tracks that ended in the last update (alive in the previous frame, in none of this
  /// frame's superpixels), in increasing id order, each with the track that received most of its
  /// pixels (-1 when its pixels all left the image). Its evidence continues there.
  [[nodiscard]] const std::vector<std::pair<int, int>>& ended() const { return ended_; }
  /// The tracks created in the last update, in increasing id order, each with the track that
  /// covered most of its superpixel (-1: none, e.g. the first frame or pixels from outside the
  /// image).
  [[nodiscard]] const std::vector<std::pair<int, int>>& created() const { return created_; }
  /// The tracks alive in the last frame, in increasing id order. The tracker keeps no state per
  /// ended track: its memory is bounded by the frame's size, however long the video.
  [[nodiscard]] const std::vector<int>& live() const { return live_; }

 private:
  double min_overlap_;
  cv::Mat1i previous_;
  int next_id_ = 0;
  std::vector<int> live_;
  std::vector<std::pair<int, int>> ended_;
  std::vector<std::pair<int, int>> created_;
  std::vector<std::vector<std::pair<int, int>>> votes_;  // per superpixel: (track, votes)
};

}  // namespace proprio::segmentation
