#include "proprio/features/colour_words.hpp"

#include <algorithm>
#include <opencv2/imgproc.hpp>
#include <string>

#include "proprio/core/error.hpp"

namespace proprio::features {

void ColourWordOptions::validate() const { core::check_field_bounds(*this, "colour words"); }

namespace {

// The word of an HSV colour as OpenCV's 8-bit COLOR_BGR2HSV has it: H 0..179 (2 degrees), S and
// V 0..255.
std::int32_t hsv_word(int h, int s, int v, const ColourWordOptions& o) {
  const double sat = s / 255.0;
  const int chromatic = o.hue_bins * o.saturation_levels;
  if (sat < o.grey_below || o.grey_below >= 1.0) {
    return chromatic + std::min(o.grey_levels - 1, v * o.grey_levels / 256);
  }
  const int hue = std::min(o.hue_bins - 1, h * o.hue_bins / 180);
  const double above = (sat - o.grey_below) / (1.0 - o.grey_below);  // 0..1
  const int level =
      std::min(o.saturation_levels - 1, static_cast<int>(above * o.saturation_levels));
  return hue * o.saturation_levels + level;
}

}  // namespace

std::int32_t colour_word(const cv::Vec3b& bgr, const ColourWordOptions& options) {
  options.validate();
  const cv::Mat3b one(1, 1, bgr);
  cv::Mat3b hsv;
  cv::cvtColor(one, hsv, cv::COLOR_BGR2HSV);
  const cv::Vec3b p = hsv(0, 0);
  return hsv_word(p[0], p[1], p[2], options);
}

namespace {

// Each pixel's patch mean (a box filter of side 2 radius + 1, the border replicated) in HSV; the
// mean goes into a new matrix (the caller's image shares `bgr`'s data). `who` names the caller in
// errors.
cv::Mat3b patch_means_hsv(const cv::Mat& image, const ColourWordOptions& options, const char* who) {
  options.validate();
  if (image.empty()) throw Error(std::string(who) + ": empty image");
  if (image.depth() != CV_8U || (image.channels() != 1 && image.channels() != 3)) {
    throw Error(std::string(who) + ": images must be 8-bit grey or BGR");
  }
  cv::Mat bgr = image;
  if (image.channels() == 1) cv::cvtColor(image, bgr, cv::COLOR_GRAY2BGR);
  cv::Mat mean;
  if (options.radius > 0) {
    const int side = 2 * options.radius + 1;
    cv::blur(bgr, mean, cv::Size(side, side), cv::Point(-1, -1), cv::BORDER_REPLICATE);
  } else {
    mean = bgr;
  }
  cv::Mat3b hsv;
  cv::cvtColor(mean, hsv, cv::COLOR_BGR2HSV);
  return hsv;
}

}  // namespace

std::vector<std::int32_t> colour_words(const cv::Mat& image,
                                       const std::vector<cv::KeyPoint>& keypoints,
                                       const ColourWordOptions& options) {
  std::vector<std::int32_t> out;
  out.reserve(keypoints.size());
  // One conversion for the whole image; a keypoint reads its pixel.
  const cv::Mat3b hsv = patch_means_hsv(image, options, "colour_words");
  for (const cv::KeyPoint& k : keypoints) {
    const int x = cvRound(k.pt.x);
    const int y = cvRound(k.pt.y);
    if (x < 0 || y < 0 || x >= hsv.cols || y >= hsv.rows) {
      throw Error("colour_words: keypoint (" + std::to_string(k.pt.x) + ", " +
                  std::to_string(k.pt.y) + ") lies outside the " + std::to_string(hsv.cols) +
                  " x " + std::to_string(hsv.rows) + " image");
    }
    const cv::Vec3b& p = hsv(y, x);
    out.push_back(hsv_word(p[0], p[1], p[2], options));
  }
  return out;
}

std::vector<double> colour_word_counts(const cv::Mat& image, const cv::Mat& mask,
                                       const ColourWordOptions& options) {
  const cv::Mat3b hsv = patch_means_hsv(image, options, "colour_word_counts");
  if (mask.type() != CV_8UC1 || mask.size() != image.size()) {
    throw Error("colour_word_counts: the mask must be 8-bit, one channel, the image's size");
  }
  std::vector<double> counts(static_cast<std::size_t>(options.count()), 0.0);
  for (int y = 0; y < mask.rows; ++y) {
    const auto* m = mask.ptr<uchar>(y);
    for (int x = 0; x < mask.cols; ++x) {
      if (m[x] == 0) continue;
      const cv::Vec3b& p = hsv(y, x);
      counts[static_cast<std::size_t>(hsv_word(p[0], p[1], p[2], options))] += 1.0;
    }
  }
  return counts;
}

std::vector<std::int32_t> with_colour_words(std::vector<std::int32_t> words,
                                            const std::vector<std::int32_t>& colours,
                                            int vocabulary_size) {
  if (words.size() != colours.size()) {
    throw Error("with_colour_words: " + std::to_string(words.size()) + " words but " +
                std::to_string(colours.size()) + " colour words");
  }
  words.reserve(2 * colours.size());
  for (const std::int32_t c : colours) {
    if (c < 0) throw Error("with_colour_words: a negative colour word");
    words.push_back(vocabulary_size + c);
  }
  return words;
}

int document_vocabulary_size(const Vocabulary& vocabulary,
                             const std::optional<ColourWordOptions>& colour) {
  return vocabulary.size() + (colour ? colour->count() : 0);
}

std::vector<std::int32_t> document_words(const Vocabulary& vocabulary, const cv::Mat& image,
                                         const Features& f,
                                         const std::optional<ColourWordOptions>& colour) {
  if (f.size() == 0) return {};
  std::vector<std::int32_t> words = bag_of_words(vocabulary, f.descriptors);
  if (!colour) return words;
  return with_colour_words(std::move(words), colour_words(image, f.keypoints, *colour),
                           vocabulary.size());
}

}  // namespace proprio::features
