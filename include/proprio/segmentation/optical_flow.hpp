#pragma once
// Dense optical flow between consecutive frames (step 2 of thesis 4.1).

#include <Eigen/Core>
#include <memory>
#include <opencv2/core.hpp>
#include <vector>

#include "proprio/segmentation/ml_segmentation.hpp"

namespace proprio::segmentation {

/// Dense flow from one 8-bit grey image to another of the same size: flow(x) (CV_32FC2, pixels)
/// is where pixel x of `from` lies in `to`, x + flow(x). Keeps its state (DIS instance) between
/// calls; not thread-safe.
class DenseFlow {
 public:
  explicit DenseFlow(FlowMethod method);
  ~DenseFlow();
  DenseFlow(DenseFlow&&) noexcept;
  DenseFlow& operator=(DenseFlow&&) noexcept;
  [[nodiscard]] cv::Mat2f compute(const cv::Mat1b& from, const cv::Mat1b& to);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Carries points of the previous frame into the current one along the backward flow
/// (`back_flow`: current -> previous, as DenseFlow::compute(current, previous) gives it, in
/// processing pixels): each point p becomes x with x + back_flow(x) = p, by two fixed-point
/// steps from x = p, the flow read at the nearest pixel (clamped to the image). Points are in
/// full-size pixels, `scale` = full-size / processing pixels.
void carry_points(std::vector<Eigen::Vector2f>& points, const cv::Mat2f& back_flow, double scale);

/// The image's own (camera) motion in a flow field: the homography that most of the flow follows
/// (cv::findHomography by RANSAC), mapping x to where x's flow takes it. A moving camera moves
/// the image of a plane by a homography; the table and what stands on it fill most of the view,
/// while the pushed object and the arm cover a small part of it and are outliers. (A similarity
/// is not enough: a camera that shifts by millimetres moves the near table more than the far
/// one, and the view then fits no similarity.)
struct GlobalMotion {
  /// x -> homography * [x; 1], pixels. Identity when none was found.
  cv::Matx33d homography = cv::Matx33d::eye();
  bool found = false;            ///< a fit with enough inliers, spread wide enough
  double inlier_fraction = 0.0;  ///< of the sampled flow vectors
  double centre_motion = 0.0;    ///< |H(c) - c| at the image centre c, pixels
};

/// Options of estimate_global_motion.
struct GlobalMotionOptions {
  /// Flow sampled every `stride` pixels each way.
  int stride = 8;
  /// RANSAC inlier threshold, pixels. 2 px: objects standing on the table sit off its plane, and
  /// a camera that also shifts moves them a little differently (parallax); 1 px rejected half the
  /// fits on the shaking-camera episodes, 3 px let the pusher and object in.
  double threshold = 2.0;
  /// A fit followed by fewer of the samples than this is rejected (found = false).
  double min_inlier_fraction = 0.5;
  /// The inliers' bounding box must span at least this fraction of the image's width and of its
  /// height: a camera's motion moves the whole view, and a fit that only a compact patch follows
  /// (a textured object on a plain table) is that patch's motion.
  double min_inlier_extent = 0.5;
  /// Only samples where the image has texture: central differences |dI/dx| + |dI/dy| of at least
  /// this, grey levels. Flow on a plain surface (the table) is filled in from around it and
  /// says little of how it moved.
  double min_texture = 16.0;
};

/// Global motion of a dense flow field (CV_32FC2, as DenseFlow::compute returns) computed from
/// the 8-bit grey image `image` (same size; its texture picks the samples). Deterministic:
/// RANSAC's sampling uses OpenCV's fixed-seed generator.
/// The homography maps image points; apply it with homogeneous division.
GlobalMotion estimate_global_motion(const cv::Mat2f& flow, const cv::Mat1b& image,
                                    const GlobalMotionOptions& options = {});

}  // namespace proprio::segmentation
