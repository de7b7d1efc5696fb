#pragma once
// The Fitzpatrick & Metta 2003 baseline of thesis 5.1.1 (SPEC §3): segmenting the object a robot
// pokes by frame differencing and graph cuts.
//
//  1. Frame differencing: a pixel moved between frames i-1 and i where its colour changed by more
//     than the difference threshold (any channel, 0-255) -- the method's one free parameter (5 in
//     the thesis, Fig 5-1's optimum).
//  2. The touch: the first frame the robot reports touching (default: the frame M-L and the
//     ground truth use, so that both are scored on the same frame), or, as Fitzpatrick & Metta do
//     without contact sensing, the first frame where motion appears near the end-effector that
//     the arm's own motion does not explain.
//  3. The frame before the touch models the arm: the pixels that moved between frames t-2 and
//     t-1 (only the arm moves then), dilated; they are hard background seeds.
//  4. The touch frame's moving pixels outside the arm model are evidence for the object; a graph
//     cut (graph_cut.hpp, contrast-weighted) builds the object region from them ("a hull around
//     these points", 5.1.1): a moving pixel costs motion_weight as background, a still one
//     still_weight as object unless it lies within the evidence's closing (fill_radius).
//  5. The connected region of the cut nearest the end-effector's image position is the object.

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <optional>
#include <string>

#include "proprio/core/fields.hpp"

#include "proprio/episode/episode.hpp"
#include "proprio/segmentation/graph_cut.hpp"

namespace proprio::segmentation {

/// Where the touch frame comes from.
enum class TouchSource { kRobot, kDifferencing };
[[nodiscard]] std::string to_string(TouchSource s);  ///< "robot" / "differencing"
inline constexpr core::ChoiceNames<TouchSource, 2> kTouchSourceNames = {
    {{"robot", TouchSource::kRobot}, {"differencing", TouchSource::kDifferencing}}};

struct FmOptions {
  /// Difference threshold on 0-255 colour levels (thesis 5.1.1: 5). The free parameter of the
  /// baseline's P-R curve.
  double difference_threshold = 5.0;
  TouchSource touch = TouchSource::kRobot;
  /// Dilation of the arm model, pixels (the arm moves on between t-1 and t).
  int arm_dilation = 4;
  /// Unary costs of the cut: a moving pixel labelled background, a still one labelled object.
  double motion_weight = 1.0;
  double still_weight = 0.3;
  /// Still pixels inside the morphological closing of the evidence by this radius, pixels, cost
  /// nothing as object: the cut fills the hull that a textured object's moving edges outline.
  int fill_radius = 8;
  /// Contrast-weighted smoothness etc. of the cut.
  GraphCutOptions graph_cut = {};
  /// kDifferencing: motion counts as a touch within this radius of the end-effector, pixels,
  /// when at least touch_min_pixels such pixels moved.
  double touch_radius = 60.0;
  int touch_min_pixels = 40;
  /// Throws Error naming the bad field.
  void validate() const;

  /// The options a command binds (`segment`, `evaluate segmentation`: --threshold, --touch).
  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.difference_threshold,
      {"difference_threshold", "Baseline's frame-difference threshold, 0-255 (thesis 5.1.1: 5)",
       core::between(0.0, 254.0), nullptr, "threshold"});
    v.choice(self.touch,
             {"touch", "Baseline's touch frame: robot (its touching flag, as M-L) or differencing"},
             kTouchSourceNames);
  }
};

struct FmSummary {
  bool touched = false;
  TouchSource touch_source = TouchSource::kRobot;
  long long moving_pixels = 0;    ///< pixels above the threshold between t-1 and t
  long long arm_pixels = 0;       ///< pixels of the (dilated) arm model
  long long evidence_pixels = 0;  ///< moving pixels outside the arm model
  int components = 0;             ///< connected regions of the cut
  /// Distance from the end-effector to the chosen region, pixels (0 inside it); -1 when the
  /// end-effector's image position is unknown (then the largest region is chosen).
  double ee_distance = -1.0;
  GraphCutSummary cut;
  double seconds = 0.0;  ///< wall clock, frame decoding included
  std::string message;   ///< one line: what happened
  /// What a person reads: the message.
  [[nodiscard]] std::string brief() const { return message; }
};

struct FmResult {
  std::optional<int> first_touch_frame;  ///< the robot's
  int scored_frame = -1;  ///< the touch frame t used; -1 = no touch ("no touch": mask empty)
  cv::Mat1b mask;         ///< 255 object, at the frames' size
  cv::Mat1b motion;       ///< 255 where frames t-1 and t differ above the threshold
  cv::Mat1b arm;          ///< 255 on the arm model (frames t-2, t-1)
  FmSummary summary;
};

/// The three frames the baseline needs, decoded once (a P-R sweep over the threshold reuses
/// them; with kDifferencing the touch depends on the threshold, so the sweep reloads).
struct FmFrames {
  std::optional<int> first_touch_frame;  ///< the robot's
  int touch_frame = -1;                  ///< -1: no touch
  cv::Mat before2, before, touch;        ///< BGR frames t-2, t-1, t
  std::optional<Eigen::Vector2d> ee;     ///< end-effector in frame t, pixels
  std::string message;                   ///< why there is no touch frame, if so
};

/// Finds the touch frame (options.touch) and decodes frames t-2..t. No touch, or a touch before
/// frame 2 (no arm-only frame pair before it), gives touch_frame -1 and a message. Throws Error
/// on an episode without frames or arm samples, or on frames of different sizes.
FmFrames load_fm_frames(const episode::Episode& episode, const FmOptions& options);

/// Steps 1 and 3-5 on decoded frames.
FmResult segment_fm(const FmFrames& frames, const FmOptions& options);

/// load_fm_frames + segment_fm.
FmResult segment_fm(const episode::Episode& episode, const FmOptions& options);

/// Step 1: 255 where any channel of `a` and `b` differs by more than `threshold` (same size and
/// type, else Error).
cv::Mat1b difference_mask(const cv::Mat& a, const cv::Mat& b, double threshold);

}  // namespace proprio::segmentation
