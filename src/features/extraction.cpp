#include "proprio/features/extraction.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/features2d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "proprio/core/error.hpp"
#include "proprio/geometry/image_file.hpp"

namespace proprio::features {
namespace fs = std::filesystem;

FeatureKind parse_feature_kind(const std::string& name) {
  if (name == "dense") return FeatureKind::kDense;
  if (name == "sift") return FeatureKind::kSift;
  std::string m = "unknown feature kind '";
  m += name;
  m += "' (known: dense, sift)";
  throw Error(m);
}

std::string to_string(FeatureKind kind) { return kind == FeatureKind::kDense ? "dense" : "sift"; }

void ExtractOptions::validate() const {
  core::check_field_bounds(*this, "feature options");
  dense.validate();
  sift.validate();
}

namespace {

cv::Mat grey_of(const cv::Mat& image) {
  if (image.empty()) throw Error("empty image");
  if (image.depth() != CV_8U || (image.channels() != 1 && image.channels() != 3)) {
    throw Error("images must be 8-bit grey or BGR");
  }
  if (image.channels() == 1) return image;
  cv::Mat g;
  cv::cvtColor(image, g, cv::COLOR_BGR2GRAY);
  return g;
}

bool inside(const cv::Mat& mask, const cv::Point2f& p) {
  const int x = static_cast<int>(std::lround(p.x));
  const int y = static_cast<int>(std::lround(p.y));
  return x >= 0 && y >= 0 && x < mask.cols && y < mask.rows && mask.at<uchar>(y, x) != 0;
}

}  // namespace

Features extract_features(const cv::Mat& image, const ExtractOptions& options,
                          const cv::Mat& region) {
  options.validate();
  if (!region.empty() && (region.type() != CV_8UC1 || region.size() != image.size())) {
    throw Error("a feature mask must be 8-bit single-channel of the image's size");
  }
  cv::Mat mask = region;
  if (options.center_crop < 1 && !image.empty()) {
    const int w = static_cast<int>(std::lround(options.center_crop * image.cols));
    const int h = static_cast<int>(std::lround(options.center_crop * image.rows));
    const cv::Rect centre((image.cols - w) / 2, (image.rows - h) / 2, w, h);
    cv::Mat crop = cv::Mat::zeros(image.size(), CV_8UC1);
    crop(centre).setTo(255);
    if (mask.empty()) {
      mask = crop;
    } else {
      cv::bitwise_and(mask, crop, crop);
      mask = crop;
    }
  }
  if (options.kind == FeatureKind::kSift) {
    Features f = detect_sift(image, options.sift);
    if (mask.empty()) return f;
    std::vector<int> rows;
    for (int i = 0; i < f.size(); ++i)
      if (inside(mask, f.keypoints[static_cast<std::size_t>(i)].pt)) rows.push_back(i);
    return select_features(f, rows);
  }
  // Only the grid points on the mask with some contrast: a small object costs a small fraction
  // of the frame.
  const cv::Mat grey = grey_of(image);
  std::vector<cv::KeyPoint> grid = dense_grid(image.size(), options.dense);
  if (!mask.empty())
    std::erase_if(grid, [&](const cv::KeyPoint& k) { return !inside(mask, k.pt); });
  if (options.min_contrast > 0 && !grid.empty()) {
    // Local variance E[I^2] - E[I]^2 over the patch by box filters.
    cv::Mat g, mean, mean_sq;
    grey.convertTo(g, CV_32F);
    const int side = std::max(1, static_cast<int>(std::lround(options.dense.size)));
    cv::boxFilter(g, mean, CV_32F, cv::Size(side, side));
    cv::boxFilter(g.mul(g), mean_sq, CV_32F, cv::Size(side, side));
    const double min_var = options.min_contrast * options.min_contrast;
    std::erase_if(grid, [&](const cv::KeyPoint& k) {
      const int x = std::clamp(static_cast<int>(std::lround(k.pt.x)), 0, g.cols - 1);
      const int y = std::clamp(static_cast<int>(std::lround(k.pt.y)), 0, g.rows - 1);
      const float m = mean.at<float>(y, x);
      return mean_sq.at<float>(y, x) - m * m < min_var;
    });
  }
  Features f;
  f.descriptors = cv::Mat(0, kDescriptorLength, CV_32F);
  if (grid.empty()) return f;
  cv::Mat desc;
  cv::SIFT::create()->compute(grey, grid, desc);
  f.keypoints = std::move(grid);
  f.descriptors = desc;
  return f;
}

Features select_features(const Features& f, const std::vector<int>& rows) {
  Features out;
  out.descriptors.create(static_cast<int>(rows.size()), kDescriptorLength, CV_32F);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    out.keypoints.push_back(f.keypoints[static_cast<std::size_t>(rows[i])]);
    f.descriptors.row(rows[i]).copyTo(out.descriptors.row(static_cast<int>(i)));
  }
  return out;
}

cv::Mat read_image(const fs::path& path) { return geometry::read_image(path, cv::IMREAD_COLOR); }

cv::Mat read_alpha_mask(const fs::path& path) {
  const cv::Mat all = geometry::read_image(path, cv::IMREAD_UNCHANGED);
  if (all.channels() != 4) {
    throw Error::in_file(path, "--alpha-mask: the image has no alpha channel (" +
                                   std::to_string(all.channels()) + " channels)");
  }
  cv::Mat alpha;
  cv::extractChannel(all, alpha, 3);
  return alpha != 0;
}

Features extract_file_features(const fs::path& path, const ExtractOptions& options, bool grey) {
  return extract_file_features(
      path, geometry::read_image(path, grey ? cv::IMREAD_GRAYSCALE : cv::IMREAD_COLOR), options);
}

Features extract_file_features(const fs::path& path, const cv::Mat& image,
                               const ExtractOptions& options) {
  const cv::Mat mask = options.alpha_mask ? read_alpha_mask(path) : cv::Mat();
  try {
    return extract_features(image, options, mask);
  } catch (const Error& e) {
    throw Error::in_file(path, e.what());
  }
}

}  // namespace proprio::features
