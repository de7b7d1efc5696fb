// The sparse variant of M-L (thesis 4.5, Algorithm 3).
#include <chrono>
#include <cmath>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

#include "proprio/core/error.hpp"
#include "proprio/core/text.hpp"
#include "proprio/segmentation/ml_segmentation.hpp"
#include "proprio/segmentation/motion_models.hpp"

namespace proprio::segmentation {

namespace {

using Clock = std::chrono::steady_clock;

// Flat-kernel mean shift from every sample (Algorithm 3's meanShift): returns, per sample, the
// index of its cluster and the cluster centres (modes closer than half the bandwidth merged).
std::vector<int> mean_shift_clusters(const std::vector<Eigen::Vector2f>& v, double bandwidth,
                                     std::vector<Eigen::Vector2d>& centres) {
  const double c2 = bandwidth * bandwidth;
  std::vector<int> label(v.size(), -1);
  centres.clear();
  for (size_t i = 0; i < v.size(); ++i) {
    Eigen::Vector2d m = v[i].cast<double>();
    for (int it = 0; it < 50; ++it) {
      Eigen::Vector2d acc = Eigen::Vector2d::Zero();
      int n = 0;
      for (const auto& s : v) {
        if ((s.cast<double>() - m).squaredNorm() < c2) {
          acc += s.cast<double>();
          ++n;
        }
      }
      const Eigen::Vector2d next = acc / std::max(n, 1);
      const double moved = (next - m).norm();
      m = next;
      if (moved < 1e-3) break;
    }
    int k = 0;
    for (; k < static_cast<int>(centres.size()); ++k)
      if ((centres[k] - m).norm() < 0.5 * bandwidth) break;
    if (k == static_cast<int>(centres.size())) centres.push_back(m);
    label[i] = k;
  }
  return label;
}

struct Keyframe {
  int frame = -1;
  Eigen::Vector2d ee;
  std::vector<cv::KeyPoint> points;
  cv::Mat descriptors;
};

}  // namespace

void SparseOptions::validate() const {
  const auto positive = [](double v, const char* name) {
    require(std::isfinite(v) && v > 0,
            core::cat({"SparseOptions.", name, " must be > 0, got ", core::num(v)}));
  };
  positive(lambda, "lambda");
  positive(velocity_bandwidth, "velocity_bandwidth");
  positive(density_sigma, "density_sigma");
  positive(evidence_step, "evidence_step");
  require(std::isfinite(tau) && tau >= 0 && tau <= 1, "SparseOptions.tau must be in [0, 1]");
  require(std::isfinite(mask_fraction) && mask_fraction > 0 && mask_fraction <= 1,
          "SparseOptions.mask_fraction must be in (0, 1]");
  require(std::isfinite(kappa) && kappa >= 1, "SparseOptions.kappa must be >= 1");
  require(std::isfinite(ratio) && ratio > 0 && ratio < 1, "SparseOptions.ratio must be in (0, 1)");
  require(max_features >= 10, "SparseOptions.max_features must be >= 10");
}

MlResult segment_ml_sparse(const episode::Episode& episode, const SparseOptions& options) {
  options.validate();
  if (episode.frame_count() <= 0) throw Error::in_file(episode.dir(), "the episode has no frames");
  if (static_cast<int>(episode.arm().size()) != episode.frame_count())
    throw Error::in_file(episode.dir(), "the episode's arm samples do not match its frames");
  const auto track = episode.ee_image_track();
  if (std::none_of(track.begin(), track.end(), [](const auto& e) { return e.has_value(); }))
    throw Error::in_file(episode.dir(),
                         "no frame has the end-effector's image position (arm data)");
  MlResult r;
  r.first_touch_frame = episode.first_touch_frame();
  r.summary.frames = episode.frame_count();
  if (!r.first_touch_frame) {
    r.summary.message = "no touch: the arm never touches anything, nothing to segment";
    return r;
  }
  const int touch = *r.first_touch_frame;
  const cv::Size size(episode.info().width, episode.info().height);
  // The touch frame's arm position: features are carried there along the arm's displacement
  // (they move with it), since single frames' features are not tracked.
  std::optional<Eigen::Vector2d> ee_touch;
  for (int d = 0; d < episode.frame_count() && !ee_touch; ++d) {
    if (touch - d >= 0 && track[touch - d])
      ee_touch = track[touch - d];
    else if (touch + d < episode.frame_count() && track[touch + d])
      ee_touch = track[touch + d];
  }
  cv::Mat1f object(size, 0.0f), arm(size, 0.0f);
  auto sift = cv::SIFT::create(options.max_features);
  cv::BFMatcher matcher(cv::NORM_L2);
  Keyframe key;
  double ms_features = 0, ms_model = 0;
  int intervals = 0;
  for (int i = 0; i < episode.frame_count(); ++i) {
    if (!track[i]) continue;
    const bool first_touch_now = i == touch;
    const double moved = key.frame >= 0 ? (*track[i] - key.ee).norm() : 0.0;
    const bool close = key.frame < 0 || moved >= options.evidence_step ||
                       (first_touch_now && moved >= 0.5 * options.evidence_step);
    if (!close && !first_touch_now) continue;
    const auto t0 = Clock::now();
    cv::Mat gray;
    cv::cvtColor(episode.frame(i), gray, cv::COLOR_BGR2GRAY);
    Keyframe next;
    next.frame = i;
    next.ee = *track[i];
    sift->detectAndCompute(gray, cv::noArray(), next.points, next.descriptors);
    const auto t1 = Clock::now();
    ms_features += std::chrono::duration<double, std::milli>(t1 - t0).count();
    if (close && key.frame >= 0 && !key.descriptors.empty() && !next.descriptors.empty()) {
      std::vector<std::vector<cv::DMatch>> knn;
      matcher.knnMatch(key.descriptors, next.descriptors, knn, 2);
      std::vector<Eigen::Vector2f> velocity, from;
      for (const auto& m : knn) {
        if (m.size() < 2 || m[0].distance >= options.ratio * m[1].distance) continue;
        const cv::Point2f a = key.points[m[0].queryIdx].pt, b = next.points[m[0].trainIdx].pt;
        velocity.emplace_back(b.x - a.x, b.y - a.y);
        from.emplace_back(a.x, a.y);
      }
      std::vector<Eigen::Vector2d> centres;
      const std::vector<int> label =
          mean_shift_clusters(velocity, options.velocity_bandwidth, centres);
      const Eigen::Vector2d d = next.ee - key.ee;
      const bool pre_touch = i <= touch;
      std::vector<char> keep(centres.size());
      for (size_t k = 0; k < centres.size(); ++k)
        keep[k] = motion_likelihood(centres[k] - d, options.lambda) >= options.tau;
      // Positions carried to the touch frame along the arm's displacement.
      const Eigen::Vector2d carry = *ee_touch - key.ee;
      for (size_t k = 0; k < velocity.size(); ++k) {
        if (!keep[label[k]]) continue;
        const Eigen::Vector2d at = from[k].cast<double>() + carry;
        const cv::Point p(static_cast<int>(std::lround(at.x())),
                          static_cast<int>(std::lround(at.y())));
        if (p.x < 0 || p.y < 0 || p.x >= size.width || p.y >= size.height) continue;
        (pre_touch ? arm : object)(p) += 1.0f;
      }
      ++intervals;
    }
    key = std::move(next);
    ms_model += std::chrono::duration<double, std::milli>(Clock::now() - t1).count();
  }
  // Spatial density of the kept features; pre-touch arm features removed (eq 4.18's role).
  cv::GaussianBlur(object, object, cv::Size(), options.density_sigma);
  cv::GaussianBlur(arm, arm, cv::Size(), options.density_sigma);
  double hi_obj = 0, hi_arm = 0;
  cv::minMaxLoc(object, nullptr, &hi_obj);
  cv::minMaxLoc(arm, nullptr, &hi_arm);
  if (hi_obj > 0) object /= hi_obj;
  if (hi_arm > 0) {
    arm /= hi_arm;
    cv::Mat1f keep_weight = 1.0 - arm / options.kappa;
    object = object.mul(keep_weight);
  }
  cv::max(object, 0.0, object);
  cv::min(object, 1.0, object);
  r.scored_frame = touch;
  r.map = object;
  r.mask = threshold_map(r.map, options.mask_fraction);
  r.summary.scored_frame = touch;
  r.summary.touched = true;
  r.summary.evidence_intervals = intervals;
  r.summary.mean_ms_flow = ms_features / episode.frame_count();
  r.summary.mean_ms_model = ms_model / episode.frame_count();
  r.summary.mean_ms_total = r.summary.mean_ms_flow + r.summary.mean_ms_model;
  r.summary.message = core::cat({"sparse: scored at first touch, frame ", std::to_string(touch),
                                 "; ", std::to_string(intervals), " keyframe pairs"});
  return r;
}

}  // namespace proprio::segmentation
