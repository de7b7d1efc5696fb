#include "proprio/eval/segment_episode.hpp"

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "proprio/core/error.hpp"
#include "proprio/core/files.hpp"
#include "proprio/episode/episode.hpp"

namespace proprio::eval {
namespace fs = std::filesystem;

void SegmentEpisodeOptions::validate() const {
  require(!episode.empty(), "segment: no episode given");
  require(!out.empty(), "segment: no output directory given");
  eval.validate();
}

namespace {

void save_image(const fs::path& stage, const fs::path& final_dir, const std::string& name,
                const cv::Mat& img) {
  if (!cv::imwrite((stage / name).string(), img)) {
    throw Error::in_file(final_dir / name, "cannot write the image");
  }
}

}  // namespace

cv::Mat overlay_mask(const cv::Mat& frame, const cv::Mat1b& mask, const cv::Mat1b& truth) {
  cv::Mat out = frame.clone();
  cv::Mat green(frame.size(), frame.type(), cv::Scalar(0, 200, 0));
  cv::Mat blended;
  cv::addWeighted(frame, 0.55, green, 0.45, 0, blended);
  blended.copyTo(out, mask);
  std::vector<std::vector<cv::Point>> contours;
  if (!truth.empty()) {
    cv::findContours(truth.clone(), contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE);
    cv::drawContours(out, contours, -1, cv::Scalar(0, 230, 255), 1, cv::LINE_AA);
  }
  contours.clear();
  cv::findContours(mask.clone(), contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE);
  cv::drawContours(out, contours, -1, cv::Scalar(0, 0, 255), 1, cv::LINE_AA);
  return out;
}

SegmentEpisodeResult run_segment_episode(const SegmentEpisodeOptions& options,
                                         const core::Provenance& provenance) {
  options.validate();
  core::require_output_not_input(options.out, {options.episode}, "--out");
  EvalOptions o = options.eval;
  o.all_frames = false;
  const episode::Episode ep = episode::read_episode(options.episode);
  core::StagedDirectory dir(options.out, options.overwrite);
  const fs::path stage = dir.staging_path();
  SegmentEpisodeResult r;
  r.evaluation = evaluate_episode(ep, {options.method}, o, true);
  const MethodOutcome& oc = r.outcome();
  if (oc.status == "failed") {
    throw Error::in_file(options.episode,
                         oc.method == Method::kFm ? "fm: " + oc.message : oc.message);
  }
  if (!oc.mask.empty()) {
    cv::Mat1b truth;
    if (ep.info().has_masks && ep.info().target && oc.scored_frame >= 0) {
      truth = ep.mask(oc.scored_frame) == *ep.info().target;
    }
    if (!oc.map.empty()) {
      // 16-bit PNG: 65535 = probability 1 (for fm: 1 = moving, 0.375 = arm model).
      cv::Mat map16;
      oc.map.convertTo(map16, CV_16U, 65535.0);
      save_image(stage, options.out, "map.png", map16);
      r.files.push_back("map.png");
    }
    save_image(stage, options.out, "mask.png", oc.mask);
    save_image(stage, options.out, "overlay.png", overlay_mask(oc.frame, oc.mask, truth));
    save_image(stage, options.out, "frame.png", oc.frame);
    r.files.insert(r.files.end(), {"mask.png", "overlay.png", "frame.png"});
    if (!truth.empty()) {
      save_image(stage, options.out, "truth.png", truth);
      r.files.push_back("truth.png");
    }
  }
  r.episode = options.episode;
  r.method = to_string(options.method);
  r.options = o;
  r.document = core::result_document("proprio.segment", 1, provenance);
  core::fields_into_json(r, r.document);
  core::write_json_atomic(stage / "segment.json", r.document);
  dir.commit();
  r.message = core::first_line(r.brief());
  return r;
}

std::string SegmentEpisodeResult::brief() const {
  const MethodOutcome& oc = outcome();
  const std::string name = episode.string();
  if (oc.status == "no touch") {
    return fmt::format("{}: no touch ({}); nothing segmented\n", name, oc.message);
  }
  std::string s = fmt::format("{}: {} at frame {} in {:.2f} s\n", to_string(oc.method), oc.message,
                              oc.scored_frame, oc.seconds);
  if (oc.status == "ok") {
    s += fmt::format("precision {:.3f}, recall {:.3f}, Jaccard {:.3f}, L2 {:.4f}\n",
                     oc.metrics.precision, oc.metrics.recall, oc.metrics.jaccard, oc.metrics.l2);
  } else {
    s += fmt::format("{}: not scored\n", oc.status);
  }
  return s;
}

}  // namespace proprio::eval
