#pragma once
// `proprio segment` as a library call: one segmentation method run on one episode and scored at
// the first touch (thesis Ch 4-5), with its images and segment.json written into a directory.

#include <filesystem>
#include <string>
#include <vector>

#include "proprio/core/fields.hpp"
#include "proprio/core/json_io.hpp"
#include "proprio/core/provenance.hpp"
#include "proprio/eval/segmentation_eval.hpp"

namespace proprio::eval {

struct SegmentEpisodeOptions {
  std::filesystem::path episode;  ///< the episode directory (required)
  /// Directory to write (required): map.png (16-bit, 65535 = probability 1; methods with a map),
  /// mask.png, overlay.png, frame.png, truth.png (with ground truth) and segment.json.
  std::filesystem::path out;
  bool overwrite = false;  ///< replace `out` when it exists (else it must not)
  Method method = Method::kMl;
  /// The methods' options; all_frames is not used here (one frame is scored).
  EvalOptions eval = {};

  /// Throws Error naming the first bad option.
  void validate() const;
};

// The implicit noexcept move of core::Json (nlohmann's) calls its assert_invariant(), which
// clang-tidy 14 cannot prove free of exceptions.
// NOLINTNEXTLINE(bugprone-exception-escape)
struct SegmentEpisodeResult {
  /// The method's outcome on the episode (images included) and the episode's facts.
  EpisodeEvaluation evaluation;
  std::filesystem::path episode;
  std::string method;              ///< the method's name
  EvalOptions options;             ///< the evaluation options used
  std::vector<std::string> files;  ///< images written into `out`, in the order written
  /// segment.json as written (format "proprio.segment", docs/formats/schemas/segment.schema.json):
  /// the fields described below.
  core::Json document;

  [[nodiscard]] const MethodOutcome& outcome() const { return evaluation.outcomes.front(); }
  /// What happened, in a few lines for a person (what the CLI prints).
  std::string message;  ///< one line: what happened (brief()'s first line)
  [[nodiscard]] std::string brief() const;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    const MethodOutcome& oc = self.outcome();
    const EpisodeEvaluation& e = self.evaluation;
    v(self.episode, {"episode", "The episode"});
    v(self.method, {"method", "The segmentation method"});
    v(oc.status, {"status", "ok, no touch, no ground truth or failed"});
    v(oc.message, {"message", "Why, when not ok"});
    v(oc.scored_frame, {"scored_frame", "The frame scored (-1: none)"});
    v(core::or_null(e.first_touch_frame), {"first_touch_frame", "The first touch (null: none)"});
    v(e.background, {"background", "static, moving or unknown"});
    v(e.object, {"object", "The target's name"});
    v(oc.seconds, {"seconds", "The method's time"});
    v(self.options, {"options", "The evaluation options"});
    v(core::or_null(oc.status == "ok" ? std::optional<MaskMetrics>(oc.metrics) : std::nullopt),
      {"metrics", "The mask's scores at the scored frame (null unless ok)"});
    v(self.files, {"files", "Images written"});
  }
};

/// Reads the episode, runs the method, writes `out` atomically (a staged directory that appears
/// whole or not at all) and returns what it wrote. A method that fails on the episode is an
/// Error naming the episode; "no touch" and "no ground truth" are results.
SegmentEpisodeResult run_segment_episode(const SegmentEpisodeOptions& options,
                                         const core::Provenance& provenance);

/// The frame with `mask` tinted green, its outline red, and `truth`'s outline yellow (BGR).
cv::Mat overlay_mask(const cv::Mat& frame, const cv::Mat1b& mask, const cv::Mat1b& truth);

}  // namespace proprio::eval
