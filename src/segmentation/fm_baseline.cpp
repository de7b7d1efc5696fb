#include "proprio/segmentation/fm_baseline.hpp"

#include <chrono>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>

#include "proprio/core/error.hpp"
#include "proprio/features/mask_morphology.hpp"

namespace proprio::segmentation {
namespace {

using Clock = std::chrono::steady_clock;

void check_episode(const episode::Episode& ep) {
  if (ep.frame_count() < 1) throw Error::in_file(ep.dir(), "the episode has no frames");
  if (static_cast<int>(ep.arm().size()) != ep.frame_count()) {
    throw Error::in_file(ep.dir(), "the episode has no arm sample for every frame");
  }
}

cv::Mat frame_checked(const episode::Episode& ep, int i, cv::Size size) {
  cv::Mat f = ep.frame(i);
  if (f.size() != size) {
    throw Error::in_file(episode::image_path(ep.dir(), "frames", i),
                         "frame of a different size from the episode's first frame");
  }
  return f;
}

// Touch by differencing: the first frame whose moving pixels near the end-effector, outside the
// dilated motion of the frame pair before, number at least touch_min_pixels.
std::optional<int> touch_by_differencing(const episode::Episode& ep, const FmOptions& o,
                                         cv::Size size) {
  cv::Mat f1;
  cv::Mat1b prev_motion;
  for (int i = 0; i < ep.frame_count(); ++i) {
    cv::Mat f = frame_checked(ep, i, size);
    if (i >= 1) {
      const cv::Mat1b motion = difference_mask(f1, f, o.difference_threshold);
      if (i >= 2) {
        const auto ee = ep.ee_image(i);
        if (ee) {
          cv::Mat1b near(size, uchar(0));
          cv::circle(near,
                     cv::Point(static_cast<int>(std::lround(ee->x())),
                               static_cast<int>(std::lround(ee->y()))),
                     static_cast<int>(std::lround(o.touch_radius)), cv::Scalar(255), cv::FILLED);
          const cv::Mat1b evidence =
              motion & ~features::dilated(prev_motion, o.arm_dilation) & near;
          // The arm must be moving (else the first jitter would count).
          if (cv::countNonZero(prev_motion) > 0 &&
              cv::countNonZero(evidence) >= o.touch_min_pixels) {
            return i;
          }
        }
      }
      prev_motion = motion;
    }
    f1 = f;
  }
  return std::nullopt;
}

}  // namespace

std::string to_string(TouchSource s) { return s == TouchSource::kRobot ? "robot" : "differencing"; }

void FmOptions::validate() const {
  require(std::isfinite(difference_threshold) && difference_threshold >= 0 &&
              difference_threshold < 255,
          "fm: difference threshold must be in [0, 255)");
  require(arm_dilation >= 0 && arm_dilation <= 100, "fm: arm dilation must be 0..100 pixels");
  require(std::isfinite(motion_weight) && motion_weight >= 0 && motion_weight <= 1e3,
          "fm: motion weight must be in [0, 1000]");
  require(std::isfinite(still_weight) && still_weight >= 0 && still_weight <= 1e3,
          "fm: still weight must be in [0, 1000]");
  require(std::isfinite(touch_radius) && touch_radius > 0 && touch_radius <= 1e5,
          "fm: touch radius must be in (0, 1e5] pixels");
  require(fill_radius >= 0 && fill_radius <= 200, "fm: fill radius must be 0..200 pixels");
  require(touch_min_pixels >= 1, "fm: touch min pixels must be >= 1");
  graph_cut.validate();
}

cv::Mat1b difference_mask(const cv::Mat& a, const cv::Mat& b, double threshold) {
  require(!a.empty() && a.size() == b.size() && a.type() == b.type(),
          "frame differencing: frames of different sizes or types");
  cv::Mat d;
  cv::absdiff(a, b, d);
  if (d.channels() > 1) {
    std::vector<cv::Mat> ch;
    cv::split(d, ch);
    cv::Mat m = ch[0];
    for (std::size_t c = 1; c < ch.size(); ++c) cv::max(m, ch[c], m);
    d = m;
  }
  return d > threshold;
}

FmFrames load_fm_frames(const episode::Episode& episode, const FmOptions& options) {
  options.validate();
  check_episode(episode);
  FmFrames f;
  f.first_touch_frame = episode.first_touch_frame();
  const cv::Mat first = episode.frame(0);
  const cv::Size size = first.size();
  std::optional<int> t;
  if (options.touch == TouchSource::kRobot) {
    t = f.first_touch_frame;
    if (!t) f.message = "no touch: the arm never touches anything";
  } else {
    t = touch_by_differencing(episode, options, size);
    if (!t) f.message = "no touch: differencing found no motion near the end-effector";
  }
  if (t && *t < 2) {
    f.message = "no touch before frame 2: no arm-only frame pair to model the arm";
    t.reset();
  }
  if (!t) return f;
  f.touch_frame = *t;
  f.before2 = frame_checked(episode, *t - 2, size);
  f.before = frame_checked(episode, *t - 1, size);
  f.touch = frame_checked(episode, *t, size);
  f.ee = episode.ee_image(*t);
  return f;
}

FmResult segment_fm(const FmFrames& frames, const FmOptions& options) {
  options.validate();
  const auto t0 = Clock::now();
  FmResult r;
  r.first_touch_frame = frames.first_touch_frame;
  r.summary.touch_source = options.touch;
  if (frames.touch_frame < 0) {
    r.summary.message = frames.message.empty() ? "no touch" : frames.message;
    return r;
  }
  r.scored_frame = frames.touch_frame;
  r.summary.touched = true;
  const cv::Size size = frames.touch.size();

  r.arm = features::dilated(
      difference_mask(frames.before2, frames.before, options.difference_threshold),
      options.arm_dilation);
  r.motion = difference_mask(frames.before, frames.touch, options.difference_threshold);
  const cv::Mat1b evidence = r.motion & ~r.arm;
  r.summary.moving_pixels = cv::countNonZero(r.motion);
  r.summary.arm_pixels = cv::countNonZero(r.arm);
  r.summary.evidence_pixels = cv::countNonZero(evidence);

  GraphCutProblem p;
  p.image = frames.touch;
  p.cost_object = cv::Mat1f(size, static_cast<float>(options.still_weight));
  p.cost_background = cv::Mat1f(size, 0.f);
  // The hull: between evidence pixels less than 2 fill_radius apart a still pixel costs nothing
  // as object, so the cut fills the gaps that a textured object's moving edges leave.
  cv::Mat1b hull;
  cv::morphologyEx(evidence, hull, cv::MORPH_CLOSE, features::disc(options.fill_radius));
  p.cost_object.setTo(0.f, hull);
  p.cost_background.setTo(static_cast<float>(options.motion_weight), evidence);
  p.seeds = cv::Mat1b(size, kSeedFree);
  p.seeds.setTo(kSeedBackground, r.arm);
  const GraphCutResult cut = graph_cut(p, options.graph_cut);
  r.summary.cut = cut.summary;

  // The connected region nearest the end-effector.
  cv::Mat labels, stats, centroids;
  const int n = cv::connectedComponentsWithStats(cut.mask, labels, stats, centroids, 8, CV_32S);
  r.summary.components = n - 1;
  r.mask = cv::Mat1b(size, uchar(0));
  if (n <= 1) {
    r.summary.message = "the graph cut found no object region";
  } else {
    int best = -1;
    if (frames.ee) {
      // Distance of every pixel to the end-effector; the region with the nearest pixel wins.
      std::vector<double> nearest(static_cast<std::size_t>(n),
                                  std::numeric_limits<double>::infinity());
      for (int y = 0; y < size.height; ++y) {
        const int* row = labels.ptr<int>(y);
        for (int x = 0; x < size.width; ++x) {
          if (row[x] == 0) continue;
          const double d = std::hypot(x - frames.ee->x(), y - frames.ee->y());
          nearest[static_cast<std::size_t>(row[x])] =
              std::min(nearest[static_cast<std::size_t>(row[x])], d);
        }
      }
      best = 1;
      for (int k = 2; k < n; ++k) {
        if (nearest[static_cast<std::size_t>(k)] < nearest[static_cast<std::size_t>(best)]) {
          best = k;
        }
      }
      r.summary.ee_distance = nearest[static_cast<std::size_t>(best)];
    } else {
      best = 1;
      for (int k = 2; k < n; ++k) {
        if (stats.at<int>(k, cv::CC_STAT_AREA) > stats.at<int>(best, cv::CC_STAT_AREA)) best = k;
      }
    }
    r.mask.setTo(255, labels == best);
    r.summary.message = "segmented at the touch frame " + std::to_string(frames.touch_frame);
    if (!frames.ee) r.summary.message += " (end-effector not in view: largest region)";
  }
  r.summary.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  return r;
}

FmResult segment_fm(const episode::Episode& episode, const FmOptions& options) {
  const auto t0 = Clock::now();
  const FmFrames frames = load_fm_frames(episode, options);
  FmResult r = segment_fm(frames, options);
  r.summary.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  return r;
}

}  // namespace proprio::segmentation
