#include "proprio/segmentation/ml_segmentation.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cassert>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <unordered_map>
#include <vector>

#include "proprio/core/error.hpp"
#include "proprio/core/text.hpp"
#include "proprio/features/mask_morphology.hpp"
#include "proprio/geometry/camera.hpp"
#include "proprio/segmentation/fm_baseline.hpp"
#include "proprio/segmentation/motion_models.hpp"
#include "proprio/segmentation/optical_flow.hpp"
#include "proprio/segmentation/region_smoothing.hpp"
#include "proprio/segmentation/region_tracker.hpp"
#include "touch_refine.hpp"

namespace proprio::segmentation {

namespace {

using Clock = std::chrono::steady_clock;

void require_positive(double v, const char* name) {
  require(std::isfinite(v) && v > 0,
          core::cat({"MlOptions.", name, " must be > 0, got ", core::num(v)}));
}

// Flow samples per track: every kSampleStride-th pixel each way.
constexpr int kSampleStride = 2;

// Homography model: points per track carried through an interval (interval_homography).
constexpr size_t kHomographyPoints = 96;

// Grey levels: a pixel that changed more than this between frames changed (global_change).
constexpr int kGlobalChangeLevel = 3;

// Per-track state: integrated evidence (eq 4.21, kept as sums) and the motion accumulated in
// the open evidence interval.
struct Track {
  double post_sum = 0.0;  // sum of p over post-touch intervals
  int post_n = 0;
  double pre_sum = 0.0;  // sum of (1 - p) / kappa over pre-touch intervals where it moved
  int pre_n = 0;
  int pre_still = 0;  // pre-touch intervals judged in which it did not move (arm_removal_seen)
  int interval = -1;  // interval its accumulator belongs to
  Eigen::Vector2d start_ee = Eigen::Vector2d::Zero();     // arm position when it joined it
  int start_frame = -1;                                   // frame it joined the interval at
  Eigen::Vector2d at = Eigen::Vector2d::Zero();           // mean sampled position, last frame
  Eigen::Vector2d shift = Eigen::Vector2d::Zero();        // translation since the interval's start
  Eigen::Matrix3d h = Eigen::Matrix3d::Identity();        // homography since the interval's start
  Eigen::Vector2d last_motion = Eigen::Vector2d::Zero();  // robust mean of the last frame pair
  // Depth variant: 3-D translation since the interval's start (camera frame, mm), the arm's 3-D
  // position when it joined, and whether every frame pair of its span had enough depth.
  Eigen::Vector3d shift3 = Eigen::Vector3d::Zero();
  std::optional<Eigen::Vector3d> start_ee3;
  bool depth_ok = true;
  int last_frame = -1;  // frame of last_motion
  int successor = -1;   // where its evidence continues once it ended (see scores())
  // Memory (release_ended): a track is kept after it ends only while a kept label image (the
  // first touch's) names it or one of its predecessors: `root` when the first touch's labels
  // name it, `needed` when they name it or a predecessor, `preds` its needed predecessors.
  bool root = false;
  bool needed = false;
  std::vector<int> preds;
  bool untrusted = false;        // too little texture in a frame of the open interval
  double photo_gain = 0.0;       // sum over the interval of |I_t - I_t-1(x)| - |I_t - I_t-1(x - m)|
  double photo_expect = 0.0;     // sum over the interval of |I_t-1(x) - I_t-1(x - m)|
  int photo_n = 0;               // pixels in photo_gain
  int photo_contrasted = 0;      // of them, those whose own term of photo_expect is at least
                                 // min_photometric_contrast
  double last_gain = 0.0;        // mean photometric gain of the last frame pair
  double last_expect = 0.0;      // mean gain its contrast predicts for the last frame pair's motion
  double last_contrasted = 0.0;  // fraction of its pixels contrasted (photo_contrasted)
  Eigen::Vector3f colour = Eigen::Vector3f::Zero();  // mean BGR where last seen (smoothing)
  // Homography model: some of the region's points where it joined the interval, and the same
  // points carried along the flow to the last frame (full-size pixels).
  std::vector<Eigen::Vector2f> h_from, h_to;

  // eq 4.21's mean over the window; a track seen in fewer than min_count of the window's
  // intervals is averaged over min_count (unseen intervals count as 0), so that a region
  // with one lucky interval does not score as high as one matched all along.
  // With `seen` (MlOptions::arm_removal_seen) the arm-removal term is averaged over every
  // pre-touch interval the track was judged in, a still one counting 1 (no arm evidence).
  [[nodiscard]] double score(double min_count, bool seen) const {
    const double n = std::max<double>(post_n, min_count);
    const double post = n > 0 ? post_sum / n : 0.0;
    const int pre_count = seen ? pre_n + pre_still : pre_n;
    const double pre = pre_count > 0 ? (pre_sum + (seen ? pre_still : 0)) / pre_count : 1.0;
    return std::clamp(post * pre, 0.0, 1.0);
  }
  // The same without eq 4.18's arm-removal term (MlOptions::pixel_arm_removal).
  [[nodiscard]] double post_score(double min_count) const {
    const double n = std::max<double>(post_n, min_count);
    return std::clamp(n > 0 ? post_sum / n : 0.0, 0.0, 1.0);
  }
};

}  // namespace

void MlOptions::validate() const {
  require(region_count >= 4 && region_count <= 100000,
          core::cat({"MlOptions.region_count must be in [4, 100000], got ",
                     std::to_string(region_count)}));
  require_positive(lambda, "lambda");
  require(std::isfinite(mask_fraction) && mask_fraction > 0 && mask_fraction <= 1,
          core::cat({"MlOptions.mask_fraction must be in (0, 1], got ", core::num(mask_fraction)}));
  require(
      std::isfinite(depth_mask_fraction) && depth_mask_fraction >= 0 && depth_mask_fraction <= 1,
      core::cat({"MlOptions.depth_mask_fraction must be in [0, 1], got ",
                 core::num(depth_mask_fraction)}));
  require(std::isfinite(kappa) && kappa >= 1,
          core::cat({"MlOptions.kappa must be >= 1 (p stays in [0, 1]), got ", core::num(kappa)}));
  require_positive(robust_bandwidth, "robust_bandwidth");
  require_positive(robust_tolerance, "robust_tolerance");
  require(robust_max_iterations >= 1, "MlOptions.robust_max_iterations must be >= 1");
  require_positive(ransac_threshold, "ransac_threshold");
  require(homography_min_points >= 4, "MlOptions.homography_min_points must be >= 4");
  require(
      std::isfinite(homography_selection) && homography_selection >= 0 && homography_selection <= 1,
      core::cat({"MlOptions.homography_selection must be in [0, 1], got ",
                 core::num(homography_selection)}));
  require_positive(evidence_step, "evidence_step");
  require_positive(arm_removal_step, "arm_removal_step");
  require_positive(pixel_still_span, "pixel_still_span");
  require_positive(carried_span, "carried_span");
  require_positive(carried_step, "carried_step");
  require(std::isfinite(carried_match) && carried_match >= 0,
          core::cat({"MlOptions.carried_match must be >= 0, got ", core::num(carried_match)}));
  require(std::isfinite(carried_fb) && carried_fb >= 0,
          core::cat({"MlOptions.carried_fb must be >= 0, got ", core::num(carried_fb)}));
  require(std::isfinite(touch_fm) && touch_fm >= 0 && touch_fm <= 1,
          core::cat({"MlOptions.touch_fm must be in [0, 1], got ", core::num(touch_fm)}));
  require(std::isfinite(touch_fm_fraction) && touch_fm_fraction > 0 && touch_fm_fraction <= 1,
          core::cat({"MlOptions.touch_fm_fraction must be in (0, 1], got ",
                     core::num(touch_fm_fraction)}));
  require(
      std::isfinite(touch_fm_agree) && touch_fm_agree >= 0 && touch_fm_agree <= 1,
      core::cat({"MlOptions.touch_fm_agree must be in [0, 1], got ", core::num(touch_fm_agree)}));
  require(std::isfinite(touch_fm_fill) && touch_fm_fill >= 0 && touch_fm_fill <= 1,
          core::cat({"MlOptions.touch_fm_fill must be in [0, 1], got ", core::num(touch_fm_fill)}));
  require(std::isfinite(touch_fm_refine) && touch_fm_refine >= 0 && touch_fm_refine <= 16,
          core::cat({"MlOptions.touch_fm_refine must be in [0, 16] px, got ",
                     core::num(touch_fm_refine)}));
  require(std::isfinite(touch_fm_margin) && touch_fm_margin >= 0 && touch_fm_margin <= 100,
          core::cat(
              {"MlOptions.touch_fm_margin must be in [0, 100], got ", core::num(touch_fm_margin)}));
  require(std::isfinite(carried_colour) && carried_colour >= 0,
          core::cat({"MlOptions.carried_colour must be >= 0, got ", core::num(carried_colour)}));
  require(smoothing_keep_evidence >= 0,
          core::cat({"MlOptions.smoothing_keep_evidence must be >= 0, got ",
                     core::num(smoothing_keep_evidence)}));
  require(std::isfinite(pixel_motion_margin) && pixel_motion_margin >= 0,
          core::cat({"MlOptions.pixel_motion_margin must be >= 0, got ",
                     core::num(pixel_motion_margin)}));
  require(std::isfinite(pixel_still_gradient) && pixel_still_gradient >= 0,
          core::cat({"MlOptions.pixel_still_gradient must be >= 0, got ",
                     core::num(pixel_still_gradient)}));
  require(std::isfinite(min_region_motion) && min_region_motion >= 0,
          "MlOptions.min_region_motion must be >= 0");
  require(std::isfinite(scale) && scale >= 0.1 && scale <= 1.0,
          core::cat({"MlOptions.scale must be in [0.1, 1], got ", core::num(scale)}));
  require(std::isfinite(handover_motion) && handover_motion >= 0,
          "MlOptions.handover_motion must be >= 0");
  require_positive(direction_ramp, "direction_ramp");
  require_positive(contact_radius, "contact_radius");
  require(std::isfinite(contact_gap) && contact_gap >= 0,
          core::cat({"MlOptions.contact_gap must be >= 0, got ", core::num(contact_gap)}));
  require(
      std::isfinite(smoothing_weight) && smoothing_weight >= 0,
      core::cat({"MlOptions.smoothing_weight must be >= 0, got ", core::num(smoothing_weight)}));
  require_positive(smoothing_colour_sigma, "smoothing_colour_sigma");
  require(std::isfinite(min_gradient) && min_gradient >= 0, "MlOptions.min_gradient must be >= 0");
  require(min_textured_samples >= 1, "MlOptions.min_textured_samples must be >= 1");
  require(std::isfinite(min_evidence_fraction) && min_evidence_fraction >= 0 &&
              min_evidence_fraction <= 1,
          "MlOptions.min_evidence_fraction must be in [0, 1]");
  require(std::isfinite(peak_area) && peak_area >= 0 && peak_area < 1,
          core::cat({"MlOptions.peak_area must be in [0, 1), got ", core::num(peak_area)}));
  require(std::isfinite(min_photometric_gain) && min_photometric_gain >= 0,
          "MlOptions.min_photometric_gain must be >= 0");
  require(
      std::isfinite(photometric_relative) && photometric_relative >= 0 && photometric_relative <= 1,
      core::cat({"MlOptions.photometric_relative must be in [0, 1], got ",
                 core::num(photometric_relative)}));
  require(std::isfinite(min_photometric_contrast) && min_photometric_contrast >= 0,
          core::cat({"MlOptions.min_photometric_contrast must be >= 0, got ",
                     core::num(min_photometric_contrast)}));
  require(std::isfinite(handover_evidence) && handover_evidence >= 0 && handover_evidence <= 1,
          core::cat({"MlOptions.handover_evidence must be in [0, 1], got ",
                     core::num(handover_evidence)}));
  require(std::isfinite(min_camera_motion) && min_camera_motion >= 0,
          "MlOptions.min_camera_motion must be >= 0");
  require(region_iterations >= 1 && region_iterations <= 100,
          "MlOptions.region_iterations must be in [1, 100]");
  require_positive(depth_lambda, "depth_lambda");
  require(std::isfinite(depth_relative) && depth_relative >= 0,
          core::cat({"MlOptions.depth_relative must be >= 0, got ", core::num(depth_relative)}));
  require_positive(depth_bandwidth, "depth_bandwidth");
  require(std::isfinite(depth_edge) && depth_edge >= 0,
          core::cat({"MlOptions.depth_edge must be >= 0, got ", core::num(depth_edge)}));
  require(min_depth_samples >= 1, "MlOptions.min_depth_samples must be >= 1");
  require(std::isfinite(table_clearance) && table_clearance >= 0,
          core::cat({"MlOptions.table_clearance must be >= 0, got ", core::num(table_clearance)}));
  if (!prior.empty()) {
    double lo = 0, hi = 0;
    cv::minMaxLoc(prior, &lo, &hi);
    require(cv::checkRange(prior) && lo >= 0 && hi <= 1,
            "MlOptions.prior must hold values in [0, 1] (no NaN)");
  }
}

cv::Mat1f table_heights(const cv::Mat1f& depth, const Eigen::Matrix3d& k_inv,
                        const Eigen::Vector3d& up, double pixel_scale, double min_table_share) {
  ensure(up.allFinite() && std::abs(up.norm() - 1.0) < 1e-6 && pixel_scale > 0,
         "table_heights: up must be a unit vector and pixel_scale > 0");
  constexpr float kUnknown = std::numeric_limits<float>::infinity();
  constexpr double kNear = 2.0;  // mm either side of the modal bin that count as the table
  cv::Mat1f h(depth.size(), kUnknown);
  // h = up . (z K^-1 (x, y, 1)) = z (a x + b y + c), with (a, b, c) = up^T K^-1 in full-size
  // pixels.
  const Eigen::Vector3d row = k_inv.transpose() * up;
  // 1 mm bins over +-kReach of the camera: a table farther than 65 m is no robot's table (such
  // heights still count as known). A flat histogram, not a map: a frame is 10^5 pixels or more.
  constexpr long kReach = 32768;
  std::vector<int> bins(static_cast<std::size_t>(2 * kReach), 0);
  int known = 0;
  for (int y = 0; y < depth.rows; ++y) {
    const float* z = depth[y];
    float* o = h[y];
    for (int x = 0; x < depth.cols; ++x) {
      if (!(z[x] > 0) || !std::isfinite(z[x])) continue;
      const double v = z[x] * (row.x() * x * pixel_scale + row.y() * y * pixel_scale + row.z());
      o[x] = static_cast<float>(v);
      ++known;
      if (v >= -static_cast<double>(kReach) && v < static_cast<double>(kReach)) {
        ++bins[static_cast<std::size_t>(static_cast<long>(std::floor(v)) + kReach)];
      }
    }
  }
  if (known == 0) return h;
  // The fullest bin, the lowest of equals.
  const auto fullest = std::max_element(bins.begin(), bins.end());
  if (*fullest == 0) {
    h.setTo(kUnknown);
    return h;
  }
  const long mode = static_cast<long>(fullest - bins.begin()) - kReach;
  const double centre = static_cast<double>(mode) + 0.5;
  double sum = 0;
  int near = 0;
  for (int y = 0; y < h.rows; ++y) {
    const float* o = h[y];
    for (int x = 0; x < h.cols; ++x) {
      if (std::isfinite(o[x]) && std::abs(o[x] - centre) <= kNear + 0.5) {
        sum += o[x];
        ++near;
      }
    }
  }
  if (near < min_table_share * known) {
    h.setTo(kUnknown);
    return h;
  }
  const auto table = static_cast<float>(sum / near);
  for (int y = 0; y < h.rows; ++y) {
    float* o = h[y];
    for (int x = 0; x < h.cols; ++x)
      if (std::isfinite(o[x])) o[x] -= table;
  }
  return h;
}

cv::Mat1b threshold_map(const cv::Mat1f& map, double fraction) {
  cv::Mat1b mask(map.size(), uchar{0});
  if (map.empty()) return mask;
  double hi = 0;
  cv::minMaxLoc(map, nullptr, &hi);
  if (!(hi > 0)) return mask;
  return map >= static_cast<float>(fraction * hi);
}

int apply_contact_prior(cv::Mat1f& m, const Eigen::Vector2d& ee, double fraction, double radius,
                        double gap) {
  assert(radius > 0 && gap >= 0);
  const cv::Mat1b mask = threshold_map(m, fraction);
  if (cv::countNonZero(mask) == 0) return 0;
  const cv::Mat1b joined = features::dilated(mask, static_cast<int>(std::lround(gap / 2)));
  cv::Mat1i blob;
  const int n = cv::connectedComponents(joined, blob, 8, CV_32S);
  std::vector<char> near(static_cast<size_t>(n), 0);
  const double r2 = radius * radius;
  const int x0 = std::max(0, static_cast<int>(std::floor(ee.x() - radius)));
  const int x1 = std::min(m.cols - 1, static_cast<int>(std::ceil(ee.x() + radius)));
  const int y0 = std::max(0, static_cast<int>(std::floor(ee.y() - radius)));
  const int y1 = std::min(m.rows - 1, static_cast<int>(std::ceil(ee.y() + radius)));
  bool any = false;
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) {
      const int b = blob(y, x);
      const double dx = x - ee.x(), dy = y - ee.y();
      if (b == 0 || !mask(y, x) || dx * dx + dy * dy > r2) continue;
      near[static_cast<size_t>(b)] = 1;
      any = true;
    }
  }
  if (!any) return 0;  // nothing bright at the contact: no reason to prefer one blob
  int dropped = 0;
  for (int b = 1; b < n; ++b) dropped += near[static_cast<size_t>(b)] ? 0 : 1;
  for (int y = 0; y < m.rows; ++y) {
    const int* b = blob[y];
    float* o = m[y];
    for (int x = 0; x < m.cols; ++x)
      if (b[x] > 0 && !near[static_cast<size_t>(b[x])]) o[x] = 0.0F;
  }
  return dropped;
}

struct MlSegmenter::Impl {
  MlOptions opt;
  cv::Size size;       // full image size
  cv::Size proc_size;  // processing size
  double inv_scale = 1.0;
  OverSegmenter segmenter;
  RegionTracker tracker;
  DenseFlow flow;

  int frames = 0;
  std::optional<int> first_touch;
  cv::Mat1b prev_gray;
  std::vector<cv::Mat1i> labels;  // per frame (or only the first touch's)
  cv::Mat1i touch_labels;
  // Arm removal per pixel (pixel_arm_removal): per processing pixel, the last frame whose grey
  // level differed from the previous frame's by more than kGlobalChangeLevel (-1: none), kept
  // until the first touch; the arm's recent positions before it; and the first-touch frame's
  // pixels found still then (empty: not judged).
  cv::Mat1i last_change;
  std::vector<std::pair<int, Eigen::Vector2d>> pre_touch_ee;
  cv::Mat1b touch_still;
  // ... and, once the arm has moved evidence_step pixels after the touch, whether each of them
  // then matched the touch frame displaced by the arm's motion (touch_gray, touch_arm).
  cv::Mat1b touch_gray;
  Eigen::Vector2d touch_arm = Eigen::Vector2d::Zero();
  bool touch_judged = false;
  // Carried touch pixels (carried_pixels): each first-touch pixel's position in the current
  // frame and its motion over the last frame pair (processing pixels; x < 0: lost), the track
  // it fell in at each sample (-1: lost), and the arm's motion past its touch position at
  // which the next sample is taken.
  cv::Mat2f carry_at, carry_motion;
  std::vector<cv::Mat1i> carry_ids;
  cv::Mat1f carry_look;    // the first-touch frame's grey levels, 5x5 means
  cv::Mat3b carry_colour;  // the first-touch frame's colours (carried_colour)
  // The baseline's evidence at the touch (touch_fm): the last two frames' colours before the
  // touch, and the baseline's cut of the touch frame (processing size; empty: none).
  cv::Mat3b fm_before2, fm_before;
  cv::Mat1b touch_fm, touch_fm_arm;
  cv::Mat3b touch_colour;  // the first-touch frame's colours (touch_fm_refine)
  double carry_next = 0.0;
  bool carrying = false;
  // Depth variant with depth_smoothing: the depth of every frame whose labels are kept.
  std::vector<cv::Mat1f> depths;
  cv::Mat1f touch_depth;
  // Tracks by id: the live ones and the ended ones a kept label image still needs (their
  // evidence; release_ended frees the others).
  std::unordered_map<int, Track> tracks;

  // Open evidence interval.
  int interval = 0;
  int interval_start = -1;
  std::optional<Eigen::Vector2d> interval_ee;
  cv::Mat1b interval_gray;  // the open interval's first frame (camera motion compensation)
  double sum_camera_motion = 0;
  int camera_fits = 0, camera_failures = 0;
  std::optional<Eigen::Vector2d> prev_ee;
  // Depth variant: this frame's and the previous frame's depth (processing size, mm, 0 =
  // unknown), the arm in the camera frame (mm), and K^-1 (full-size pixels).
  cv::Mat1f depth_now, prev_depth;
  std::optional<Eigen::Vector3d> up;  // the world's up in the camera frame (table cut), last given
  std::optional<Eigen::Vector3d> ee3_now, prev_ee3;
  Eigen::Matrix3d k_inv = Eigen::Matrix3d::Identity();
  // Every frame's arm position when keep_frame_labels, else only the first touch's and the
  // last frame's (a stream keeps no per-frame history).
  std::vector<std::optional<Eigen::Vector2d>> ee_track;
  std::optional<Eigen::Vector2d> touch_ee, last_ee;
  // The arm's path since the first touch (push_direction): its first and last known positions
  // and its length, pixels.
  std::optional<Eigen::Vector2d> path_start, path_last;
  double path_length = 0;

  int intervals_closed = 0;
  int post_intervals = 0;
  double sum_regions = 0, sum_flow = 0, sum_model = 0, sum_total = 0;

  Impl(const MlOptions& o, cv::Size s)
      : opt(o),
        size(s),
        proc_size(std::max(8, static_cast<int>(std::lround(s.width * o.scale))),
                  std::max(8, static_cast<int>(std::lround(s.height * o.scale)))),
        segmenter(o.regions, o.region_count, o.region_iterations, proc_size),
        flow(o.flow) {
    inv_scale = static_cast<double>(size.width) / proc_size.width;
  }

  void start_interval(const std::optional<Eigen::Vector2d>& ee, const cv::Mat1b& gray) {
    ++interval;
    interval_start = frames;
    interval_ee = ee;
    interval_gray = gray;
  }

  // Adds this frame pair's motion to the accumulators of the tracks in this frame; a track not
  // yet in the open interval joins it now, from the previous frame's arm position (tracks that
  // appear mid-interval still count, over their own span). Returns the ids of the tracks.
  std::vector<int> accumulate(const cv::Mat1i& current, const cv::Mat2f& back_flow,
                              const cv::Mat1b& textured, const cv::Mat1b& gray,
                              const cv::Mat3b& colour, bool photometric_ok) {
    std::unordered_map<int, int> local;  // track id -> index in ids
    int cached_id = -1, cached_l = -1;   // consecutive pixels mostly share a track
    std::vector<int> ids;
    std::vector<Track*> track_of;  // tracks[ids[l]] (unordered_map keeps references)
    std::vector<std::vector<Eigen::Vector2f>> motion;   // prev -> current, full-size pixels
    std::vector<std::vector<Eigen::Vector2f>> at;       // positions in the current frame
    std::vector<std::vector<cv::Point>> region_pixels;  // sampled pixels, processing scale
    std::vector<Eigen::Vector2d> at_sum;                // sum of sampled positions
    std::vector<int> samples;                           // how many
    std::vector<Eigen::Vector3f> colour_sum;            // sum of sampled BGR
    std::vector<std::vector<Eigen::Vector3f>> motion3;  // depth variant: prev -> current, mm
    const bool depth = opt.use_depth && !depth_now.empty() && !prev_depth.empty();
    const bool homography = opt.model == MotionModel::kHomography;
    const bool photometric = opt.min_photometric_gain > 0 && photometric_ok;
    const auto s = static_cast<float>(inv_scale);
    for (int y = 0; y < current.rows; y += kSampleStride) {
      const int* t = current[y];
      const cv::Vec2f* f = back_flow[y];
      for (int x = 0; x < current.cols; x += kSampleStride) {
        const int id = t[x];
        int l = cached_l;
        if (id != cached_id) {
          const auto [slot, inserted] = local.try_emplace(id, -1);
          if (inserted) {
            slot->second = static_cast<int>(ids.size());
            ids.push_back(id);
            track_of.push_back(&tracks[id]);
          }
          l = cached_l = slot->second;
          cached_id = id;
        }
        if (ids.size() > motion.size()) {  // track l joined this frame pair just now
          Track& tr = *track_of[l];
          if (tr.interval != interval) {
            tr.interval = interval;
            tr.shift.setZero();
            tr.h.setIdentity();
            tr.h_from.clear();
            tr.h_to.clear();
            tr.start_ee = *prev_ee;
            tr.start_frame = frames - 1;
            tr.untrusted = false;
            tr.photo_gain = 0.0;
            tr.photo_expect = 0.0;
            tr.photo_n = 0;
            tr.photo_contrasted = 0;
            tr.shift3.setZero();
            tr.start_ee3 = prev_ee3;
            tr.depth_ok = true;
          }
          motion.emplace_back();
          if (depth) motion3.emplace_back();
          region_pixels.emplace_back();
          at_sum.emplace_back(Eigen::Vector2d::Zero());
          samples.push_back(0);
          colour_sum.emplace_back(Eigen::Vector3f::Zero());
          if (homography) at.emplace_back();
        }
        at_sum[l] += Eigen::Vector2d(x, y);
        ++samples[l];
        const cv::Vec3b& c = colour(y, x);
        colour_sum[l] += Eigen::Vector3f(c[0], c[1], c[2]);
        if (photometric) region_pixels[l].emplace_back(x, y);
        if (!textured(y, x)) continue;
        motion[l].emplace_back(-f[x][0] * s, -f[x][1] * s);
        if (depth) add_motion_3d(x, y, f[x], motion3[l]);
        if (homography) at[l].emplace_back(x * s, y * s);
      }
    }
    for (size_t l = 0; l < ids.size(); ++l) {
      Track& tr = *track_of[l];
      tr.at = at_sum[l] * (inv_scale / samples[l]);
      tr.colour = colour_sum[l] / static_cast<float>(samples[l]);
      if (static_cast<int>(motion[l].size()) < opt.min_textured_samples) {
        tr.untrusted = true;  // flow in texture-less regions is filled in from the neighbours
        tr.last_frame = -1;
        continue;
      }
      const RobustMeanResult m = robust_mean(motion[l], opt.robust_bandwidth, opt.robust_tolerance,
                                             opt.robust_max_iterations);
      if (!depth || static_cast<int>(motion3[l].size()) < opt.min_depth_samples) {
        tr.depth_ok = false;
      } else {
        tr.shift3 += robust_mean_3d(motion3[l], opt.depth_bandwidth, opt.robust_tolerance,
                                    opt.robust_max_iterations);
      }
      tr.shift += m.mean;
      tr.last_motion = m.mean;
      tr.last_frame = frames;
      if (photometric) {
        add_photometric_gain(tr, gray, region_pixels[l], m.mean);
      } else {
        tr.last_gain = std::numeric_limits<double>::infinity();  // not judged: the flow stands
        tr.last_expect = 0.0;
        tr.last_contrasted = 0.0;
      }
      if (homography) {
        std::vector<Eigen::Vector2f> from(at[l].size());
        for (size_t k = 0; k < from.size(); ++k) from[k] = at[l][k] - motion[l][k];
        const auto h = fit_homography(from, at[l], opt.ransac_threshold, opt.homography_min_points);
        Eigen::Matrix3d step = Eigen::Matrix3d::Identity();
        if (h) {
          step = *h;
        } else {  // too few points or no consensus: the region's robust translation
          step(0, 2) = m.mean.x();
          step(1, 2) = m.mean.y();
        }
        tr.h = step * tr.h;
        if (tr.start_frame == frames - 1) {  // joined the interval with this frame pair
          const size_t every = std::max<size_t>(1, at[l].size() / kHomographyPoints);
          for (size_t k = 0; k < at[l].size(); k += every) {
            tr.h_from.push_back(at[l][k] - motion[l][k]);
            tr.h_to.push_back(at[l][k]);
          }
        } else {
          carry_points(tr.h_to, back_flow, inv_scale);
        }
      }
    }
    return ids;
  }

  // Depth variant: the 3-D motion (mm, camera frame) of the sample at processing pixel (x, y),
  // whose backward flow is f, when its depth is known in both frames.
  void add_motion_3d(int x, int y, const cv::Vec2f& f, std::vector<Eigen::Vector3f>& out) const {
    const float z1 = depth_now(y, x);
    if (!(z1 > 0)) return;
    const double px = x + f[0], py = y + f[1];
    const int ix = static_cast<int>(std::lround(px)), iy = static_cast<int>(std::lround(py));
    if (ix < 0 || iy < 0 || ix >= prev_depth.cols || iy >= prev_depth.rows) return;
    const float z0 = prev_depth(iy, ix);
    if (!(z0 > 0)) return;
    const Eigen::Vector3d now = z1 * (k_inv * Eigen::Vector3d(x * inv_scale, y * inv_scale, 1.0));
    const Eigen::Vector3d before =
        z0 * (k_inv * Eigen::Vector3d(px * inv_scale, py * inv_scale, 1.0));
    out.push_back((now - before).cast<float>());
  }

  // The region's homography over the open interval (Algorithm 2): fitted once to its points
  // carried from where it joined the interval, since a frame pair's motion of a pixel or two
  // leaves a small region's homography to the noise; the product of the frame pairs' fits when
  // that fails. None when the region's translation explains its points nearly as well
  // (homography_selection): the homography's eight parameters, fitted to a small region and
  // extrapolated to the arm, then add noise and no information.
  [[nodiscard]] std::optional<Eigen::Matrix3d> interval_homography(const Track& tr) const {
    if (!opt.homography_over_interval) return tr.h;
    auto h = fit_homography(tr.h_from, tr.h_to, opt.ransac_threshold, opt.homography_min_points);
    if (!h) return tr.h;
    if (opt.homography_selection <= 0) return h;
    std::vector<Eigen::Vector2f> moved(tr.h_from.size());
    for (size_t k = 0; k < moved.size(); ++k) moved[k] = tr.h_to[k] - tr.h_from[k];
    const Eigen::Vector2d t =
        robust_mean(moved, opt.ransac_threshold, opt.robust_tolerance, opt.robust_max_iterations)
            .mean;
    int by_h = 0, by_t = 0;
    for (size_t k = 0; k < moved.size(); ++k) {
      const Eigen::Vector2d from = tr.h_from[k].cast<double>();
      const Eigen::Vector2d to = tr.h_to[k].cast<double>();
      by_h += (apply_homography(*h, from) - to).norm() <= opt.ransac_threshold ? 1 : 0;
      by_t += (from + t - to).norm() <= opt.ransac_threshold ? 1 : 0;
    }
    if (by_h - by_t < opt.homography_selection * static_cast<double>(moved.size()))
      return std::nullopt;
    return h;
  }

  // How much better the region's pixels match the previous frame displaced by its motion m
  // (full-size pixels) than undisplaced: the image's own support for the flow. Dense flow fills
  // texture-less areas (a plain table beside the pushed object) from their neighbours; there
  // both hypotheses match equally and the gain stays near 0. Also the gain the region's own
  // contrast predicts for m, |I_t-1(x) - I_t-1(x - m)|: what the gain is when the region did
  // move by m (then I_t(x) = I_t-1(x - m)); it bounds the gain (triangle inequality), which is
  // its negative when the region stood still.
  void add_photometric_gain(Track& tr, const cv::Mat1b& gray, const std::vector<cv::Point>& px,
                            const Eigen::Vector2d& m) const {
    const double mx = m.x() / inv_scale, my = m.y() / inv_scale;
    const int w = prev_gray.cols, h = prev_gray.rows;
    double gain = 0.0, expect = 0.0;
    int n = 0, contrasted = 0;
    for (const cv::Point& p : px) {
      const double sx = p.x - mx, sy = p.y - my;
      if (sx < 0 || sy < 0 || sx > w - 1.001 || sy > h - 1.001) continue;
      const int x0 = static_cast<int>(sx), y0 = static_cast<int>(sy);
      const double fx = sx - x0, fy = sy - y0;
      const uchar* r0 = prev_gray[y0];
      const uchar* r1 = prev_gray[y0 + 1];
      const double moved = (1 - fy) * ((1 - fx) * r0[x0] + fx * r0[x0 + 1]) +
                           fy * ((1 - fx) * r1[x0] + fx * r1[x0 + 1]);
      const double now = gray(p);
      const double before = prev_gray(p);
      gain += std::abs(now - before) - std::abs(now - moved);
      const double predicted = std::abs(before - moved);
      expect += predicted;
      contrasted += predicted >= opt.min_photometric_contrast ? 1 : 0;
      ++n;
    }
    tr.photo_gain += gain;
    tr.photo_expect += expect;
    tr.photo_n += n;
    tr.photo_contrasted += contrasted;
    tr.last_gain = n > 0 ? gain / n : 0.0;
    tr.last_expect = n > 0 ? expect / n : 0.0;
    tr.last_contrasted = n > 0 ? static_cast<double>(contrasted) / n : 0.0;
  }

  // Whether the image supports a motion whose mean photometric gain per pixel and frame is
  // `gain` where the region's contrast predicts `expect` for it, and a fraction `contrasted` of
  // its pixels predict at least min_photometric_contrast (MlOptions::min_photometric_gain,
  // photometric_relative). True when the check is off. The relative floor needs most pixels
  // contrasted: a region straddling a plain table and the pushed object's edge has the edge's
  // gain and prediction alike, and is left to the absolute floor, which its plain part dilutes.
  [[nodiscard]] bool photometric_support(double gain, double expect, double contrasted) const {
    if (opt.min_photometric_gain <= 0) return true;
    double floor = opt.min_photometric_gain;
    if (opt.photometric_relative > 0 && contrasted >= 0.5)
      floor = std::min(floor, opt.photometric_relative * expect);
    return gain >= floor;
  }

  // The motion of the last frame pair as the image supports it: none when the photometric
  // check is on and the image does not support it.
  [[nodiscard]] Eigen::Vector2d supported_last_motion(const Track& tr) const {
    if (!photometric_support(tr.last_gain, tr.last_expect, tr.last_contrasted))
      return Eigen::Vector2d::Zero();
    return tr.last_motion;
  }

  // Carried touch pixels: every pixel of the first-touch frame starts where it is, still.
  void start_carrying(const cv::Mat1b& gray, const cv::Mat3b& colour) {
    carry_at.create(proc_size);
    for (int y = 0; y < carry_at.rows; ++y) {
      cv::Vec2f* a = carry_at[y];
      for (int x = 0; x < carry_at.cols; ++x)
        a[x] = cv::Vec2f(static_cast<float>(x), static_cast<float>(y));
    }
    carry_motion = cv::Mat2f(proc_size, cv::Vec2f(0.0F, 0.0F));
    carry_ids.clear();
    carry_next = opt.carried_step;
    cv::boxFilter(gray, carry_look, CV_32F, cv::Size(5, 5));
    if (opt.carried_colour > 0) colour.copyTo(carry_colour);
    carrying = true;
  }

  // The backward flow at (x, y), bilinear; (x, y) within the image.
  [[nodiscard]] static cv::Vec2f flow_at(const cv::Mat2f& f, float x, float y) {
    const int x0 = std::min(static_cast<int>(x), f.cols - 2);
    const int y0 = std::min(static_cast<int>(y), f.rows - 2);
    const float fx = x - static_cast<float>(x0), fy = y - static_cast<float>(y0);
    const cv::Vec2f* r0 = f[y0];
    const cv::Vec2f* r1 = f[y0 + 1];
    return (1 - fy) * ((1 - fx) * r0[x0] + fx * r0[x0 + 1]) +
           fy * ((1 - fx) * r1[x0] + fx * r1[x0 + 1]);
  }

  // Carries each first-touch pixel from the previous frame into this one: the point q of this
  // frame whose backward flow b(q) takes it to the pixel's position p, q + b(q) = p, found by
  // the iteration q <- p - b(q) from p plus the pixel's last motion. A pixel for which none is
  // found within 1 px (it was covered, or it left the image) is lost. With a forward flow
  // (carried_fb), so is a pixel whose forward flow from p does not land within carried_fb of q.
  void carry(const cv::Mat2f& back_flow, const cv::Mat2f& fwd_flow) {
    const auto w = static_cast<float>(back_flow.cols - 1);
    const auto h = static_cast<float>(back_flow.rows - 1);
    const auto inside = [&](const cv::Vec2f& q) {
      return q[0] >= 0 && q[1] >= 0 && q[0] <= w && q[1] <= h;
    };
    constexpr int kIterations = 4;
    constexpr float kMaxResidual = 1.0F;
    const auto fb = static_cast<float>(opt.carried_fb);
    for (int y = 0; y < carry_at.rows; ++y) {
      cv::Vec2f* a = carry_at[y];
      cv::Vec2f* v = carry_motion[y];
      for (int x = 0; x < carry_at.cols; ++x) {
        const cv::Vec2f p = a[x];
        if (p[0] < 0) continue;
        cv::Vec2f q = p + v[x];
        bool found = false;
        for (int it = 0; it < kIterations && inside(q); ++it) {
          const cv::Vec2f next = p - flow_at(back_flow, q[0], q[1]);
          if (cv::norm(next - q) <= 0.05) {
            found = true;
            break;
          }
          q = next;
        }
        if (!found && inside(q))
          found = cv::norm(q + flow_at(back_flow, q[0], q[1]) - p) <= kMaxResidual;
        if (found && inside(q) && !fwd_flow.empty())
          found = cv::norm(p + flow_at(fwd_flow, p[0], p[1]) - q) <= fb;
        if (!found || !inside(q)) {
          a[x] = cv::Vec2f(-1.0F, -1.0F);
          continue;
        }
        v[x] = q - p;
        a[x] = q;
      }
    }
  }

  // Notes the track each carried pixel stands in (this frame's labels) and keeps those tracks
  // and their successors (release_ended): their scores are read when the touch frame is painted.
  void note_carried(const cv::Mat1i& lab, const cv::Mat1b& gray) {
    cv::Mat1i ids(proc_size, -1);
    cv::Mat1f look;
    cv::boxFilter(gray, look, CV_32F, cv::Size(5, 5));
    const auto match = static_cast<float>(opt.carried_match);
    const bool by_colour = opt.carried_colour > 0 && carry_colour.size() == ids.size();
    const auto colour_sq = static_cast<float>(opt.carried_colour * opt.carried_colour);
    int last = -1;
    int colour_id = -1;  // the track whose colour is in track_colour
    Eigen::Vector3f track_colour = Eigen::Vector3f::Zero();
    for (int y = 0; y < ids.rows; ++y) {
      const cv::Vec2f* a = carry_at[y];
      int* o = ids[y];
      for (int x = 0; x < ids.cols; ++x) {
        if (a[x][0] < 0) continue;
        const int qy = static_cast<int>(std::lround(a[x][1]));
        const int qx = static_cast<int>(std::lround(a[x][0]));
        // A pixel that no longer looks as it did (the flow carried a piece of the background
        // along the object's edge) says nothing.
        if (match > 0 && std::abs(look(qy, qx) - carry_look(y, x)) > match) continue;
        const int id = lab(qy, qx);
        if (by_colour) {
          // ... nor does one whose touch colour is unlike the track it stands in.
          if (id != colour_id) {
            const auto tr = tracks.find(id);
            track_colour = tr != tracks.end() ? tr->second.colour : Eigen::Vector3f::Zero();
            colour_id = id;
          }
          const cv::Vec3b& c = carry_colour(y, x);
          const Eigen::Vector3f d = Eigen::Vector3f(c[0], c[1], c[2]) - track_colour;
          if (d.squaredNorm() > colour_sq) continue;
        }
        o[x] = id;
        if (id != last) {
          Track& t = tracks[id];
          t.root = true;
          t.needed = true;
          last = id;
        }
      }
    }
    carry_ids.push_back(ids);
  }

  // Arm removal per pixel, before the touch: notes which pixels changed in this frame pair
  // (every pixel when most of the image did, global_change) and where the arm is.
  void note_pre_touch_change(const cv::Mat1b& gray, bool photometric_ok,
                             const std::optional<Eigen::Vector2d>& ee) {
    if (last_change.empty()) last_change = cv::Mat1i(gray.size(), -1);
    if (!prev_gray.empty()) {
      if (photometric_ok) {
        cv::Mat1b diff;
        cv::absdiff(gray, prev_gray, diff);
        last_change.setTo(frames, diff > kGlobalChangeLevel);
      } else {
        last_change.setTo(frames);
      }
    }
    if (ee) pre_touch_ee.emplace_back(frames, *ee);
    constexpr size_t kKeep = 512;  // a long approach: its last frames are the ones that count
    if (pre_touch_ee.size() > 2 * kKeep)
      pre_touch_ee.erase(pre_touch_ee.begin(),
                         pre_touch_ee.end() - static_cast<std::ptrdiff_t>(kKeep));
  }

  // At the first touch: the pixels that did not change since the arm was last pixel_still_span
  // pixels from where it touches, and whose gradient would have shown a motion. None when the
  // arm's position is unknown or it never moved that far.
  void find_still_pixels(const cv::Mat1b& gray, const std::optional<Eigen::Vector2d>& ee) {
    touch_still.release();
    if (!ee || last_change.empty()) return;
    int since = -1;
    for (auto it = pre_touch_ee.rbegin(); it != pre_touch_ee.rend(); ++it) {
      if ((it->second - *ee).norm() >= opt.pixel_still_span) {
        since = it->first;
        break;
      }
    }
    if (since < 0) return;
    cv::Mat1s gx, gy;
    cv::Sobel(gray, gx, CV_16S, 1, 0);
    cv::Sobel(gray, gy, CV_16S, 0, 1);
    const cv::Mat1s mag = cv::abs(gx) + cv::abs(gy);
    touch_still = (last_change <= since) & (mag >= opt.pixel_still_gradient);
    touch_gray = gray;
    touch_arm = *ee;
  }

  // After the touch, once the arm has moved evidence_step pixels from where it touched (d): a
  // still pixel x of the touch frame keeps its place in touch_still only when the current frame
  // displaced by d matches it better than undisplaced, |I(x + d) - I_touch(x)| + margin <
  // |I(x) - I_touch(x)| (5x5 means, pixel_motion_margin): it moved as the arm did (the
  // pushed object), not stood (the background beside it, which a region straddling the object's
  // outline joins to it). The kept pixels are closed (5x5) so that the plain gaps between textured
  // pixels of the object count with them; what no longer is in the region after that is left to the
  // region.
  void judge_still_pixels(const cv::Mat1b& gray, const std::optional<Eigen::Vector2d>& ee) {
    if (touch_judged || touch_still.empty() || !ee) return;
    const Eigen::Vector2d d = (*ee - touch_arm) / inv_scale;
    if (d.norm() * inv_scale < opt.evidence_step) return;
    cv::Mat1b shifted;
    const cv::Matx23d to(1, 0, d.x(), 0, 1, d.y());
    cv::warpAffine(gray, shifted, to, gray.size(), cv::INTER_LINEAR | cv::WARP_INVERSE_MAP,
                   cv::BORDER_REPLICATE);
    cv::Mat1f e_arm, e_still;
    cv::Mat1b a, b;
    cv::absdiff(shifted, touch_gray, a);
    cv::absdiff(gray, touch_gray, b);
    cv::boxFilter(a, e_arm, CV_32F, cv::Size(5, 5));
    cv::boxFilter(b, e_still, CV_32F, cv::Size(5, 5));
    const auto margin = static_cast<float>(opt.pixel_motion_margin);
    cv::Mat1b moved = (e_arm + margin < e_still) & touch_still;
    cv::morphologyEx(moved, moved, cv::MORPH_CLOSE, features::disc(2));
    touch_still = moved;
    touch_judged = true;
    touch_gray.release();
  }

  // Whether most of the image changed between the frames (the light moved, the exposure
  // jumped): then no pixel's brightness says whether it moved, and the photometric checks
  // stand aside for this frame pair.
  [[nodiscard]] bool global_change(const cv::Mat1b& gray) const {
    cv::Mat1b r0;
    cv::absdiff(gray, prev_gray, r0);
    const int changed = cv::countNonZero(r0 > kGlobalChangeLevel);
    return changed > 0.5 * static_cast<double>(r0.total());
  }

  // Closes the interval ending at this frame: one term of eq 4.21 per track in it whose own
  // span saw the arm move at least half the step.
  void evaluate(const std::vector<int>& ids, const Eigen::Vector2d& ee_now, bool pre_touch,
                const cv::Mat1b& gray) {
    const double min_span = 0.5 * (pre_touch ? opt.arm_removal_step : opt.evidence_step);
    const std::optional<Eigen::Matrix3d> camera = camera_motion(gray);
    for (int id : ids) {
      Track& tr = tracks[id];
      const Eigen::Vector2d d = ee_now - tr.start_ee;  // the arm's displacement, eq 4.12
      if (d.norm() < min_span || tr.untrusted) continue;
      // eq 4.12-4.13: error of the region's motion applied to the arm's position. A motion the
      // image does not support (photometric gain below the threshold; before the touch only
      // with photometric_pre_touch) is taken as no motion at all.
      // An interval whose frame pairs were all left out (global_change) is not judged.
      const bool unsupported =
          (!pre_touch || opt.photometric_pre_touch) && tr.photo_n > 0 &&
          !photometric_support(tr.photo_gain / tr.photo_n, tr.photo_expect / tr.photo_n,
                               static_cast<double>(tr.photo_contrasted) / tr.photo_n);
      // In the interval's first frame's camera (tracks that joined later: as seen).
      const bool compensate = camera && tr.start_frame == interval_start;
      const std::optional<Eigen::Matrix3d> h = opt.model == MotionModel::kHomography && !unsupported
                                                   ? interval_homography(tr)
                                                   : std::nullopt;
      Eigen::Vector2d e = -d;
      if (h) {
        e = to_interval_start(camera, compensate, apply_homography(*h, tr.start_ee)) - ee_now;
      } else if (!unsupported) {
        e = to_interval_start(camera, compensate, tr.at) - tr.at + tr.shift - d;
      }
      double p = motion_likelihood(e, opt.lambda);
      if (opt.use_depth && tr.depth_ok && tr.start_ee3 && ee3_now) {
        // The depth variant: the region's 3-D translation against the arm's (mm); a motion the
        // image does not support is none.
        const Eigen::Vector3d d3 = *ee3_now - *tr.start_ee3;
        const double p3 =
            motion_likelihood_3d((unsupported ? Eigen::Vector3d::Zero() : tr.shift3) - d3,
                                 opt.depth_lambda + opt.depth_relative * d3.squaredNorm());
        p = opt.depth_with_2d ? p * p3 : p3;
      }
      if (pre_touch) {
        // eq 4.18: before the touch, what moves like the arm is the arm; only moving regions
        // count, a still one is no evidence either way.
        if (!unsupported && tr.shift.norm() >= opt.min_region_motion) {
          tr.pre_sum += (1.0 - p) / opt.kappa;
          ++tr.pre_n;
        } else if (tr.shift.norm() < opt.min_region_motion) {
          ++tr.pre_still;  // its flow says still (an unsupported flow of the arm's plain links
                           // that follows the arm is no evidence either way)
        }
      } else {
        tr.post_sum += p;
        ++tr.post_n;
      }
    }
    ++intervals_closed;
    if (!pre_touch) ++post_intervals;
  }

  // The camera's own motion over the open interval (compensate_camera_motion): the homography
  // that takes the current frame's points to the interval's first frame, from the flow between
  // the two directly. Registering the interval's ends once, rather than chaining each frame
  // pair's motion, keeps the error of one fit: a shaking camera jitters about a mean pose, and
  // chained fits add their errors up over the interval.
  [[nodiscard]] std::optional<Eigen::Matrix3d> camera_motion(const cv::Mat1b& gray) {
    if (!opt.compensate_camera_motion || interval_gray.empty()) return std::nullopt;
    const GlobalMotion g = estimate_global_motion(flow.compute(gray, interval_gray), gray);
    if (!g.found) {
      ++camera_failures;
      return std::nullopt;
    }
    ++camera_fits;
    sum_camera_motion += g.centre_motion * inv_scale;
    if (g.centre_motion * inv_scale < opt.min_camera_motion) return std::nullopt;
    Eigen::Matrix3d h;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) h(r, c) = g.homography(r, c);
    return h;
  }

  // A current-frame point (full-size pixels) in the interval's first frame's camera.
  // The camera's homography works in processing pixels.
  [[nodiscard]] Eigen::Vector2d to_interval_start(const std::optional<Eigen::Matrix3d>& camera,
                                                  bool compensate, const Eigen::Vector2d& x) const {
    if (!compensate) return x;
    return apply_homography(*camera, x / inv_scale) * inv_scale;
  }

  // Per-track scores. A track that ended lives on in its successor (region_tracker.hpp): its
  // post-touch evidence is its own plus its successor's (when they agree, handover_evidence), so a
  // region split or merged by the over-segmentation keeps receiving evidence from later frames. Its
  // arm-removal evidence (eq 4.18) is its own: after the touch the object moves as the arm does,
  // and a piece of the object handed over to a track of the pusher must not take on the pusher's
  // pre-touch record.
  struct Scored {
    float score = 0.0F;
    int evidence = 0;   // post-touch intervals, own and inherited
    float post = 0.0F;  // the score without the arm-removal term (pixel_arm_removal)
  };

  [[nodiscard]] std::unordered_map<int, Scored> scores() const {
    std::unordered_map<int, Track> total;
    std::vector<int> order;
    order.reserve(tracks.size());
    for (const auto& [id, tr] : tracks) order.push_back(id);
    std::sort(order.begin(), order.end());
    // An ended track never comes back, so successor chains have no cycles; each is resolved
    // once, from its live end.
    std::vector<int> chain;
    for (int i : order) {
      if (total.count(i) != 0) continue;
      chain.clear();
      int t = i;
      while (t >= 0 && tracks.count(t) != 0 && total.count(t) == 0) {
        chain.push_back(t);
        t = tracks.at(t).successor;
      }
      Track acc;
      if (t >= 0 && total.count(t) != 0) {
        const Track& done = total.at(t);
        acc.post_sum = done.post_sum;
        acc.post_n = done.post_n;
      }
      for (auto it = chain.rbegin(); it != chain.rend(); ++it) {
        const Track& own = tracks.at(*it);
        // Evidence that disagrees cuts the chain: a still background region that the pushed
        // object slides over hands over to the object's track (their motions differ by less
        // than handover_motion at walking pace), but its own intervals said "still".
        if (own.post_n > 0 && acc.post_n > 0 &&
            std::abs(own.post_sum / own.post_n - acc.post_sum / acc.post_n) >
                opt.handover_evidence) {
          acc = Track{};
        }
        acc.post_sum += own.post_sum;
        acc.post_n += own.post_n;
        Track& out = total[*it];
        out.post_sum = acc.post_sum;
        out.post_n = acc.post_n;
        out.pre_sum = own.pre_sum;
        out.pre_n = own.pre_n;
        out.pre_still = own.pre_still;
      }
    }
    std::unordered_map<int, Scored> score;
    score.reserve(total.size());
    const double min_count = opt.min_evidence_fraction * post_intervals;
    for (const auto& [id, tr] : total)
      score[id] = {static_cast<float>(tr.score(min_count, opt.arm_removal_seen)), tr.post_n,
                   static_cast<float>(tr.post_score(min_count))};
    return score;
  }

  // The push direction: the arm's net image displacement since the first touch, when its path
  // is straight (net >= 0.9 of the path length) and long enough; none otherwise.
  [[nodiscard]] std::optional<Eigen::Vector2d> push_direction() const {
    if (!first_touch || !path_start) return std::nullopt;
    const Eigen::Vector2d net = *path_last - *path_start;
    if (net.norm() < opt.evidence_step || net.norm() < 0.9 * path_length) return std::nullopt;
    return net.normalized();
  }

  // The arm's image position in frame i (one that was kept: see ee_track).
  [[nodiscard]] std::optional<Eigen::Vector2d> ee_at(int i) const {
    if (opt.keep_frame_labels) return ee_track[static_cast<size_t>(i)];
    if (i == frames - 1) return last_ee;
    assert(first_touch && i == *first_touch);
    return touch_ee;
  }

  // `depth`: the frame's depth (processing size) for depth_smoothing; empty: none.
  [[nodiscard]] cv::Mat1f paint(const cv::Mat1i& lab, int frame, const cv::Mat1f& depth) const {
    // Before the first touch no track has post-touch evidence (every score is 0), and no prior
    // can raise a 0: the map is all 0 without painting it.
    if (!first_touch) return cv::Mat1f::zeros(size);
    const std::unordered_map<int, Scored> scored = scores();
    // The frame's tracks, numbered 0.. in increasing id order (the smoothing visits them in
    // that order).
    std::vector<int> ids;
    {
      std::unordered_map<int, char> seen;
      int last = -1;
      for (int y = 0; y < lab.rows; ++y) {
        const int* l = lab[y];
        for (int x = 0; x < lab.cols; ++x) {
          if (l[x] == last) continue;
          last = l[x];
          if (seen.try_emplace(last, 0).second) ids.push_back(last);
        }
      }
    }
    std::sort(ids.begin(), ids.end());
    std::unordered_map<int, int> index;
    std::vector<float> score(ids.size(), 0.0F);
    std::vector<int> evidence(ids.size(), 0);
    std::vector<float> post(ids.size(), 0.0F);
    std::vector<Eigen::Vector3f> colour(ids.size(), Eigen::Vector3f::Zero());
    for (size_t k = 0; k < ids.size(); ++k) {
      index[ids[k]] = static_cast<int>(k);
      const auto sc = scored.find(ids[k]);
      if (sc != scored.end()) {
        score[k] = sc->second.score;
        evidence[k] = sc->second.evidence;
        post[k] = sc->second.post;
      }
      const auto tr = tracks.find(ids[k]);
      if (tr != tracks.end()) colour[k] = tr->second.colour;
    }
    cv::Mat1i compact(lab.size());
    {
      int last = -1, last_k = -1;
      for (int y = 0; y < lab.rows; ++y) {
        const int* l = lab[y];
        int* o = compact[y];
        for (int x = 0; x < lab.cols; ++x) {
          if (l[x] != last) {
            last = l[x];
            last_k = index.at(last);
          }
          o[x] = last_k;
        }
      }
    }
    if (opt.region_smoothing && first_touch) {
      RegionSmoothingOptions so;
      so.data_weight = opt.smoothing_weight;
      so.colour_sigma = opt.smoothing_colour_sigma;
      const bool by_depth = opt.use_depth && opt.depth_smoothing && opt.depth_edge > 0;
      so.depth_step = by_depth ? opt.depth_edge : 0.0;
      const std::vector<float> own = score;
      (void)smooth_region_scores(compact, evidence, colour, so, score,
                                 by_depth ? depth : cv::Mat1f());
      if (opt.smoothing_keep_evidence > 0) keep_evidenced(compact, evidence, own, score);
    }
    cv::Mat1f m(lab.size());
    for (int y = 0; y < lab.rows; ++y) {
      const int* l = compact[y];
      float* o = m[y];
      for (int x = 0; x < lab.cols; ++x) o[x] = score[static_cast<size_t>(l[x])];
    }
    if (frame == *first_touch && !carry_ids.empty() && carry_ids.front().size() == m.size()) {
      // Carried touch pixels (carried_pixels): the median score of the tracks the pixel fell
      // in, where at least half the samples still had it.
      const size_t samples = carry_ids.size();
      double peak_d = 0;
      cv::minMaxLoc(m, nullptr, &peak_d);
      const auto region_peak = static_cast<float>(peak_d);
      std::vector<float> votes;
      votes.reserve(samples);
      std::vector<int> last_id(samples, -2);
      std::vector<float> last_score(samples, 0.0F);
      for (int y = 0; y < m.rows; ++y) {
        float* o = m[y];
        for (int x = 0; x < m.cols; ++x) {
          votes.clear();
          for (size_t k = 0; k < samples; ++k) {
            const int id = carry_ids[k](y, x);
            if (id < 0) continue;
            if (id != last_id[k]) {
              const auto sc = scored.find(id);
              last_id[k] = id;
              last_score[k] = sc != scored.end() ? sc->second.score : 0.0F;
            }
            votes.push_back(last_score[k]);
          }
          if (2 * votes.size() < samples) continue;
          const size_t half = votes.size() / 2;
          std::nth_element(votes.begin(), votes.begin() + static_cast<std::ptrdiff_t>(half),
                           votes.end());
          float med = votes[half];
          if (votes.size() % 2 == 0) {
            med =
                0.5F * (med + *std::max_element(votes.begin(),
                                                votes.begin() + static_cast<std::ptrdiff_t>(half)));
          }
          med = std::min(med, region_peak);
          o[x] = opt.carried_max ? std::max(o[x], med) : med;
        }
      }
    }
    if (frame == *first_touch && touch_fm.size() == m.size()) {
      // The baseline's evidence (touch_fm): a region mostly inside its cut scores at least
      // touch_fm x the map's peak.
      double peak_d = 0;
      cv::minMaxLoc(m, nullptr, &peak_d);
      const auto floor = static_cast<float>(opt.touch_fm * peak_d);
      std::vector<int> in(ids.size(), 0), all(ids.size(), 0);
      for (int y = 0; y < m.rows; ++y) {
        const int* l = compact[y];
        const uchar* f = touch_fm[y];
        for (int x = 0; x < m.cols; ++x) {
          ++all[static_cast<size_t>(l[x])];
          if (f[x]) ++in[static_cast<size_t>(l[x])];
        }
      }
      std::vector<char> raise(ids.size(), 0);
      for (size_t k = 0; k < ids.size(); ++k)
        raise[k] = all[k] > 0 && in[k] >= opt.touch_fm_fraction * all[k] ? 1 : 0;
      for (int y = 0; y < m.rows; ++y) {
        const int* l = compact[y];
        float* o = m[y];
        for (int x = 0; x < m.cols; ++x)
          if (raise[static_cast<size_t>(l[x])]) o[x] = std::max(o[x], floor);
      }
    }
    if (frame == *first_touch && touch_judged && touch_still.size() == m.size()) {
      // Arm removal per pixel (pixel_arm_removal): a pixel that did not move before the touch
      // is not the arm, whatever the rest of its region did.
      for (int y = 0; y < m.rows; ++y) {
        const int* l = compact[y];
        const uchar* still = touch_still[y];
        float* o = m[y];
        for (int x = 0; x < m.cols; ++x)
          if (still[x]) o[x] = std::max(o[x], post[static_cast<size_t>(l[x])]);
      }
    }
    if (opt.use_depth && opt.table_clearance > 0 && up && depth.size() == m.size()) {
      // The table cut: what lies on the table's plane is not the object standing on it.
      const cv::Mat1f above = table_heights(depth, k_inv, *up, inv_scale);
      m.setTo(0.0F, above < static_cast<float>(opt.table_clearance));
    }
    if (lab.size() != size) {
      cv::Mat1f full;
      cv::resize(m, full, size, 0, 0, cv::INTER_NEAREST);
      m = full;
    }
    if (!opt.prior.empty()) cv::multiply(m, opt.prior, m);  // 4.6
    const auto dir = opt.direction_prior ? push_direction() : std::nullopt;
    const std::optional<Eigen::Vector2d> ee = ee_at(frame);
    if (dir && ee) {
      // 4.6's position prior from proprioception: a pushed object lies ahead of the pusher's
      // tip; the arm behind it. 1 ahead of the tip, falling to 0 over direction_ramp behind.
      const Eigen::Vector2d& e = *ee;
      const double ramp = opt.direction_ramp;
      for (int y = 0; y < m.rows; ++y) {
        float* o = m[y];
        for (int x = 0; x < m.cols; ++x) {
          const double along = (x - e.x()) * dir->x() + (y - e.y()) * dir->y();
          o[x] *= static_cast<float>(std::clamp(1.0 + along / ramp, 0.0, 1.0));
        }
      }
    }
    clip_to_peak(m);
    if (opt.contact_prior && ee) {
      (void)apply_contact_prior(m, *ee, opt.effective_mask_fraction(), opt.contact_radius,
                                opt.contact_gap);
    }
    if ((opt.touch_fm_against || opt.touch_fm_fill > 0 || opt.touch_fm_refine > 0) &&
        frame == *first_touch && !touch_fm.empty()) {
      with_touch_cut(m);
    }
    return m;
  }

  // Frees the tracks that ended in the last update and that no kept label image needs: with
  // keep_frame_labels off the only kept labels are the first touch's, and a track's score
  // (scores()) depends only on its own evidence and its successors'. So a track is kept after it
  // ends only when it is named by the first touch's labels (root) or is a successor of one that
  // is (needed). A needed track that is no root and has no post-touch evidence of its own adds
  // nothing to the chain through it: its predecessors are handed straight to its successor and
  // it is freed too. The scores of every kept track stay exactly as they were.
  void release_ended() {
    for (const auto& [t, next] : tracker.ended()) {
      const auto it = tracks.find(t);
      if (it == tracks.end()) continue;
      Track& a = it->second;
      const int succ = a.successor;
      if (!a.needed) {
        tracks.erase(it);
        continue;
      }
      if (succ >= 0) tracks[succ].needed = true;
      if (!a.root && a.post_n == 0) {
        for (int p : a.preds) {
          tracks.at(p).successor = succ;
          if (succ >= 0) tracks[succ].preds.push_back(p);
        }
        tracks.erase(it);
        continue;
      }
      if (succ >= 0) tracks[succ].preds.push_back(t);
    }
  }

  // Where the baseline's touch cut and the mask agree (their intersection over union at least
  // touch_fm_agree): touch_fm_fill, the cut's pixels outside the baseline's arm model score at
  // least touch_fm_fill x the map's peak; touch_fm_against, the mask's pixels farther than
  // touch_fm_margin from the cut and from the arm model are set to 0.
  void with_touch_cut(cv::Mat1f& m) const {
    cv::Mat1b cut = touch_fm, arm = touch_fm_arm;
    if (cut.size() != m.size()) cv::resize(touch_fm, cut, m.size(), 0, 0, cv::INTER_NEAREST);
    if (arm.empty()) arm = cv::Mat1b(m.size(), uchar{0});
    if (arm.size() != m.size()) cv::resize(touch_fm_arm, arm, m.size(), 0, 0, cv::INTER_NEAREST);
    const cv::Mat1b mask = threshold_map(m, opt.effective_mask_fraction());
    const int both = cv::countNonZero(mask & cut);
    const int either = cv::countNonZero(mask | cut);
    if (either == 0 || both < opt.touch_fm_agree * either) return;
    if (opt.touch_fm_fill > 0) {
      double peak = 0;
      cv::minMaxLoc(m, nullptr, &peak);
      const cv::Mat1f raised = cv::max(m, opt.touch_fm_fill * peak);
      raised.copyTo(m, cut & ~arm);
    }
    if (opt.touch_fm_against) {
      cv::Mat1b keep = cut | arm;
      const int r = static_cast<int>(std::lround(opt.touch_fm_margin));
      if (r > 0) keep = features::dilated(keep, r);
      m.setTo(0.0F, ~keep);
    }
    if (opt.touch_fm_refine > 0) refine_outline(m, arm);
  }

  // touch_fm_refine: GrabCut on the touch frame round the mask's outline (refine_touch_outline).
  void refine_outline(cv::Mat1f& m, const cv::Mat1b& arm) const {
    if (touch_colour.empty()) return;
    cv::Mat3b img = touch_colour;
    if (img.size() != m.size()) cv::resize(touch_colour, img, m.size(), 0, 0, cv::INTER_LINEAR);
    refine_touch_outline(m, threshold_map(m, opt.effective_mask_fraction()), img, arm,
                         static_cast<int>(std::lround(opt.touch_fm_refine)),
                         opt.touch_fm_refine_arm);
  }

  void keep_evidenced(const cv::Mat1i& compact, const std::vector<int>& evidence,
                      const std::vector<float>& own, std::vector<float>& score) const {
    std::vector<std::ptrdiff_t> area(score.size(), 0);
    for (int y = 0; y < compact.rows; ++y) {
      const int* l = compact[y];
      for (int x = 0; x < compact.cols; ++x) ++area[static_cast<size_t>(l[x])];
    }
    std::vector<size_t> order(score.size());
    for (size_t k = 0; k < order.size(); ++k) order[k] = k;
    std::sort(order.begin(), order.end(), [&](size_t a, size_t b) {
      return score[a] > score[b] || (score[a] == score[b] && a < b);
    });
    const auto need = std::max<std::ptrdiff_t>(
        1, static_cast<std::ptrdiff_t>(
               std::ceil(opt.peak_area * static_cast<double>(compact.total()))));
    float peak = 0.0F;
    std::ptrdiff_t reached = 0;
    for (size_t k : order) {
      peak = score[k];
      reached += area[k];
      if (reached >= need) break;
    }
    for (size_t k = 0; k < score.size(); ++k)
      if (evidence[k] >= opt.smoothing_keep_evidence)
        score[k] = std::max(score[k], std::min(own[k], peak));
  }

  // Clips the map at its robust peak: the value that at least peak_area of the pixels reach. The
  // mask's threshold is a fraction of the map's maximum, and a sliver brighter than the object
  // (a piece of the pusher) would otherwise raise it above most of the object.
  void clip_to_peak(cv::Mat1f& m) const {
    if (opt.peak_area <= 0 || !m.isContinuous()) return;
    const auto n = static_cast<std::ptrdiff_t>(m.total());
    const auto k = std::clamp<std::ptrdiff_t>(
        static_cast<std::ptrdiff_t>(std::ceil(opt.peak_area * static_cast<double>(n))), 1, n);
    std::vector<float> v(m.begin(), m.end());
    std::nth_element(v.begin(), v.begin() + (k - 1), v.end(), std::greater<>());
    const float peak = v[static_cast<std::size_t>(k - 1)];
    if (peak > 0) m = cv::min(m, peak);
  }
};

MlSegmenter::MlSegmenter(const MlOptions& options, cv::Size image_size) {
  options.validate();
  require(image_size.width > 0 && image_size.height > 0,
          "MlSegmenter: image size must be positive");
  require(options.prior.empty() || options.prior.size() == image_size,
          "MlOptions.prior must have the frames' size");
  impl_ = std::make_unique<Impl>(options, image_size);
}

MlSegmenter::~MlSegmenter() = default;
MlSegmenter::MlSegmenter(MlSegmenter&&) noexcept = default;
MlSegmenter& MlSegmenter::operator=(MlSegmenter&&) noexcept = default;

namespace {

// The depth image as CV_32F millimetres with every unknown value (0, NaN, infinite, negative)
// 0, at `size` (nearest neighbour). Error naming the frame for a missing, empty, mis-sized or
// mis-typed image.
cv::Mat1f checked_depth(const MlSegmenter::DepthFrame* d, int frame, cv::Size full, cv::Size size) {
  const std::string f = core::cat({"frame ", std::to_string(frame)});
  require(d != nullptr && !d->depth.empty(),
          core::cat({f, ": depth asked for (MlOptions::use_depth) but the frame has none"}));
  require(d->depth.size() == full,
          core::cat({f, ": depth image is ", std::to_string(d->depth.cols), "x",
                     std::to_string(d->depth.rows), ", the frames are ", std::to_string(full.width),
                     "x", std::to_string(full.height)}));
  require(d->depth.type() == CV_16UC1 || d->depth.type() == CV_32FC1,
          core::cat({f, ": depth must be 16-bit or float single-channel millimetres"}));
  require(d->intrinsics.allFinite() && std::abs(d->intrinsics.determinant()) > 0,
          core::cat({f, ": the camera intrinsics are singular or not finite"}));
  cv::Mat1f mm;
  d->depth.convertTo(mm, CV_32F);
  for (int y = 0; y < mm.rows; ++y) {
    float* z = mm[y];
    for (int x = 0; x < mm.cols; ++x)
      if (!std::isfinite(z[x]) || z[x] < 0) z[x] = 0.0F;
  }
  if (size != full) cv::resize(mm, mm, size, 0, 0, cv::INTER_NEAREST);
  return mm;
}

}  // namespace

MlSegmenter::FrameOutput MlSegmenter::push(const cv::Mat& bgr,
                                           std::optional<Eigen::Vector2d> ee_image, bool touching,
                                           const DepthFrame* depth) {
  Impl& m = *impl_;
  require(!bgr.empty() && bgr.depth() == CV_8U && (bgr.channels() == 3 || bgr.channels() == 1),
          core::cat({"frame ", std::to_string(m.frames), ": expected an 8-bit BGR image"}));
  if (bgr.size() != m.size) {
    throw Error(core::cat({"frame ", std::to_string(m.frames), " is ", std::to_string(bgr.cols),
                           "x", std::to_string(bgr.rows), ", the episode's frames are ",
                           std::to_string(m.size.width), "x", std::to_string(m.size.height)}));
  }
  if (ee_image && !ee_image->allFinite()) ee_image.reset();
  if (m.opt.use_depth) {
    m.depth_now = checked_depth(depth, m.frames, m.size, m.proc_size);
    m.ee3_now = depth->ee_camera;
    if (m.ee3_now && !m.ee3_now->allFinite()) m.ee3_now.reset();
    m.k_inv = depth->intrinsics.inverse();
    if (depth->up) {
      require(depth->up->allFinite() && depth->up->norm() > 0,
              core::cat({"frame ", std::to_string(m.frames),
                         ": the up direction is not finite or is zero"}));
      m.up = depth->up->normalized();
    }
  }
  const auto t0 = Clock::now();
  FrameOutput out;
  out.frame = m.frames;

  // Flow from this frame to the previous one (backward: it carries the labels, exactly).
  cv::Mat colour;
  if (bgr.channels() == 1) {
    cv::cvtColor(bgr, colour, cv::COLOR_GRAY2BGR);
  } else {
    colour = bgr;
  }
  if (m.proc_size != m.size) cv::resize(colour, colour, m.proc_size, 0, 0, cv::INTER_AREA);
  cv::Mat1b gray;
  cv::cvtColor(colour, gray, cv::COLOR_BGR2GRAY);
  cv::Mat2f back_flow;
  bool photometric_ok = true;
  if (!m.prev_gray.empty()) {
    back_flow = m.flow.compute(gray, m.prev_gray);
    photometric_ok = !m.global_change(gray);
  }
  const auto t1 = Clock::now();
  out.ms_flow = std::chrono::duration<double, std::milli>(t1 - t0).count();

  int count = 0;
  cv::Mat1i sp = m.segmenter.segment(colour, count);
  if (m.opt.use_depth && m.opt.depth_edge > 0)
    sp = split_at_depth_steps(sp, m.depth_now, m.opt.depth_edge, count);
  const cv::Mat1i lab = m.tracker.update(sp, count, back_flow);
  // A new track inherits the arm evidence (eq 4.18) of the track it grew out of: the
  // over-segmentation keeps re-cutting the moving arm, and a fresh piece of it is still arm.
  for (const auto& [t, parent] : m.tracker.created()) {
    Track& fresh = m.tracks[t];
    const auto p = parent >= 0 && parent < t ? m.tracks.find(parent) : m.tracks.end();
    if (p != m.tracks.end()) {
      fresh.pre_sum = p->second.pre_sum;
      fresh.pre_n = p->second.pre_n;
      fresh.pre_still = p->second.pre_still;
    }
  }
  const auto t2 = Clock::now();
  out.ms_regions = std::chrono::duration<double, std::milli>(t2 - t1).count();

  const bool first_touch_now = touching && !m.first_touch;
  const bool pixel_arm_removal = m.opt.pixel_arm_removal && !m.opt.use_depth;
  if (pixel_arm_removal && !m.first_touch) {
    m.note_pre_touch_change(gray, photometric_ok, ee_image);
    if (first_touch_now) {
      m.find_still_pixels(gray, ee_image);
      m.last_change.release();
      m.pre_touch_ee.clear();
      m.pre_touch_ee.shrink_to_fit();
    }
  }
  if (pixel_arm_removal && m.first_touch && !first_touch_now) m.judge_still_pixels(gray, ee_image);
  if (m.opt.touch_fm > 0 && !m.opt.use_depth && !m.first_touch) {
    if (first_touch_now && !m.fm_before2.empty()) {
      FmFrames f;
      f.touch_frame = m.frames;
      f.before2 = m.fm_before2;
      f.before = m.fm_before;
      f.touch = colour;
      if (ee_image) f.ee = *ee_image / m.inv_scale;
      FmResult fm = segment_fm(f, FmOptions{});
      m.touch_fm = fm.mask;
      m.touch_fm_arm = fm.arm;
      if (m.opt.touch_fm_refine > 0) m.touch_colour = cv::Mat3b(colour).clone();
    }
    if (first_touch_now) {
      m.fm_before2.release();
      m.fm_before.release();
    } else {
      m.fm_before2 = m.fm_before;
      m.fm_before = cv::Mat3b(colour).clone();
    }
  }
  if (first_touch_now) m.first_touch = m.frames;
  if (m.frames == 0 || !ee_image || !m.prev_ee || !m.interval_ee) {
    m.start_interval(ee_image, gray);  // arm unknown: the open interval carries no evidence
  } else {
    cv::Mat1b textured;
    {
      cv::Mat1s gx, gy;
      cv::Sobel(gray, gx, CV_16S, 1, 0);
      cv::Sobel(gray, gy, CV_16S, 0, 1);
      cv::Mat1s mag = cv::abs(gx) + cv::abs(gy);
      textured = mag >= m.opt.min_gradient;
    }
    const double moved = (*ee_image - *m.interval_ee).norm();
    // Before the touch the arm's approach is slow: shorter intervals for arm removal. The first
    // touch closes the pre-touch interval (eq 4.18's T' ends there).
    const bool pre_touch = !m.first_touch || first_touch_now;
    const double step = pre_touch ? m.opt.arm_removal_step : m.opt.evidence_step;
    const std::vector<int> ids =
        m.accumulate(lab, back_flow, textured, gray, colour, photometric_ok);
    if (moved >= step || first_touch_now) {
      m.evaluate(ids, *ee_image, pre_touch, gray);
      m.start_interval(ee_image, gray);
    }
  }
  m.prev_ee = ee_image;
  if (m.opt.keep_frame_labels) m.ee_track.push_back(ee_image);
  m.last_ee = ee_image;
  if (first_touch_now) m.touch_ee = ee_image;
  if (m.first_touch && ee_image) {
    if (!m.path_start) m.path_start = ee_image;
    if (m.path_last) m.path_length += (*ee_image - *m.path_last).norm();
    m.path_last = ee_image;
  }
  // A track that ended hands its evidence on only to a track moving as it did: a background
  // region covered by the pushed object must not inherit the object's evidence.
  for (const auto& [t, next] : m.tracker.ended()) {
    if (next < 0) continue;
    Track& a = m.tracks.at(t);
    const Track& b = m.tracks.at(next);
    if (a.last_frame == m.frames - 1 && b.last_frame == m.frames &&
        (m.supported_last_motion(a) - m.supported_last_motion(b)).norm() <= m.opt.handover_motion)
      a.successor = next;
  }
  const bool keep_depth = m.opt.use_depth && (m.opt.depth_smoothing || m.opt.table_clearance > 0);
  if (m.opt.keep_frame_labels) {
    m.labels.push_back(lab);
    if (keep_depth) m.depths.push_back(m.depth_now);
  }
  if (first_touch_now) {
    m.touch_labels = lab;
    if (keep_depth) m.touch_depth = m.depth_now;
    for (int t : m.tracker.live()) {
      Track& r = m.tracks.at(t);
      r.root = true;
      r.needed = true;
    }
  }
  if (m.opt.carried_pixels && (!m.opt.use_depth || m.opt.carried_with_depth)) {
    if (first_touch_now) {
      m.start_carrying(gray, colour);
    } else if (m.carrying && !back_flow.empty()) {
      cv::Mat2f fwd_flow;
      if (m.opt.carried_fb > 0) fwd_flow = m.flow.compute(m.prev_gray, gray);
      m.carry(back_flow, fwd_flow);
      if (!m.touch_ee) {
        m.carrying = false;  // no touch position: no arm motion to sample by
      } else if (ee_image && (*ee_image - *m.touch_ee).norm() >= m.carry_next) {
        m.note_carried(lab, gray);
        const double moved = (*ee_image - *m.touch_ee).norm();
        m.carry_next = (std::floor(moved / m.opt.carried_step) + 1) * m.opt.carried_step;
        if (m.carry_next > m.opt.carried_span + 1e-9) m.carrying = false;
      }
      if (!m.carrying) {
        m.carry_at.release();
        m.carry_motion.release();
        m.carry_look.release();
        m.carry_colour.release();
      }
    }
  }
  if (!m.opt.keep_frame_labels) m.release_ended();
  m.prev_gray = gray;
  m.prev_depth = m.depth_now;
  m.prev_ee3 = m.ee3_now;
  ++m.frames;
  const auto t3 = Clock::now();
  out.ms_model = std::chrono::duration<double, std::milli>(t3 - t2).count();
  out.ms_total = std::chrono::duration<double, std::milli>(t3 - t0).count();
  m.sum_flow += out.ms_flow;
  m.sum_regions += out.ms_regions;
  m.sum_model += out.ms_model;
  m.sum_total += out.ms_total;
  if (m.opt.stream_maps) out.map = m.paint(lab, out.frame, m.depth_now);
  return out;
}

int MlSegmenter::frames() const { return impl_->frames; }

std::optional<int> MlSegmenter::first_touch_frame() const { return impl_->first_touch; }

cv::Mat1f MlSegmenter::map_for_frame(int i) const {
  const Impl& m = *impl_;
  require(i >= 0 && i < m.frames, core::cat({"map_for_frame: frame ", std::to_string(i),
                                             " out of range [0, ", std::to_string(m.frames), ")"}));
  if (m.opt.keep_frame_labels)
    return m.paint(m.labels[i], i, m.depths.empty() ? cv::Mat1f() : m.depths[i]);
  require(m.first_touch && *m.first_touch == i,
          "map_for_frame: only the first-touch frame's labels were kept (keep_frame_labels)");
  return m.paint(m.touch_labels, i, m.touch_depth);
}

MlSummary MlSegmenter::summary() const {
  const Impl& m = *impl_;
  MlSummary s;
  s.frames = m.frames;
  s.touched = m.first_touch.has_value();
  s.scored_frame = m.first_touch.value_or(-1);
  s.evidence_intervals = m.intervals_closed;
  s.tracks = m.tracker.track_count();
  s.tracks_kept = static_cast<int>(m.tracks.size());
  s.camera_fits = m.camera_fits;
  s.camera_failures = m.camera_failures;
  if (m.camera_fits > 0) s.mean_camera_motion = m.sum_camera_motion / m.camera_fits;
  if (m.frames > 0) {
    s.mean_ms_regions = m.sum_regions / m.frames;
    s.mean_ms_flow = m.sum_flow / m.frames;
    s.mean_ms_model = m.sum_model / m.frames;
    s.mean_ms_total = m.sum_total / m.frames;
  }
  return s;
}

namespace {

// Checks shared by both variants; returns the arm's image track.
std::vector<std::optional<Eigen::Vector2d>> checked_arm_track(const episode::Episode& ep) {
  const std::string dir = ep.dir().string();
  if (ep.frame_count() <= 0) throw Error::in_file(ep.dir(), "the episode has no frames");
  if (static_cast<int>(ep.arm().size()) != ep.frame_count()) {
    throw Error::in_file(
        ep.dir(), core::cat({"the episode has ", std::to_string(ep.arm().size()),
                             " arm samples for ", std::to_string(ep.frame_count()), " frames"}));
  }
  auto track = ep.ee_image_track();
  if (std::none_of(track.begin(), track.end(), [](const auto& e) { return e.has_value(); }))
    throw Error::in_file(ep.dir(), "no frame has the end-effector's image position (arm data)");
  return track;
}

}  // namespace

MlResult segment_ml(const episode::Episode& episode, const MlOptions& options) {
  options.validate();
  const auto track = checked_arm_track(episode);
  if (options.use_depth && !episode.info().has_depth) {
    throw Error::in_file(episode.dir(),
                         "depth asked for (ml-depth, MlOptions::use_depth) but the episode has no "
                         "depth images (record it with `sim record --depth`)");
  }
  MlResult r;
  r.first_touch_frame = episode.first_touch_frame();
  if (!r.first_touch_frame) {
    r.summary.frames = episode.frame_count();
    r.summary.message = "no touch: the arm never touches anything, nothing to segment";
    return r;
  }
  MlOptions o = options;
  o.keep_frame_labels = options.keep_frame_maps;
  o.stream_maps = false;
  const cv::Size size(episode.info().width, episode.info().height);
  MlSegmenter seg(o, size);
  const geometry::Camera& cam = episode.camera();
  for (int i = 0; i < episode.frame_count(); ++i) {
    const cv::Mat bgr = episode.frame(i);
    MlSegmenter::DepthFrame d;
    if (options.use_depth) {
      d.depth = episode.depth(i);
      d.intrinsics = cam.K;
      // Metres (robot frame) -> millimetres in the camera frame; behind the camera: unknown.
      const Eigen::Vector3d x = cam.R * episode.arm()[i].ee + cam.t;
      if (x.allFinite() && x.z() > 0) d.ee_camera = 1000.0 * x;
      d.up = cam.R.col(2);  // the world's +z: the table is level in the robot's frame
    }
    try {
      (void)seg.push(bgr, track[i], episode.arm()[i].touching, options.use_depth ? &d : nullptr);
    } catch (const Error& e) {
      throw Error::in_file(episode::image_path(episode.dir(), "frames", i), e.what());
    }
  }
  r.summary = seg.summary();
  r.scored_frame = *r.first_touch_frame;
  r.map = seg.map_for_frame(r.scored_frame);
  r.mask = threshold_map(r.map, options.effective_mask_fraction());
  if (options.keep_frame_maps) {
    r.frame_maps.reserve(episode.frame_count());
    for (int i = 0; i < episode.frame_count(); ++i) r.frame_maps.push_back(seg.map_for_frame(i));
  }
  r.summary.message = core::cat({"scored at first touch, frame ", std::to_string(r.scored_frame),
                                 "; ", std::to_string(r.summary.evidence_intervals),
                                 " evidence intervals over ", std::to_string(r.summary.frames),
                                 " frames, ", std::to_string(r.summary.tracks), " region tracks"});
  if (options.compensate_camera_motion) {
    const MlSummary& c = r.summary;
    r.summary.message +=
        core::cat({"; camera motion ", core::num(c.mean_camera_motion),
                   " px an interval (registered in ", std::to_string(c.camera_fits), " of ",
                   std::to_string(c.camera_fits + c.camera_failures), ")"});
  }
  return r;
}

}  // namespace proprio::segmentation
