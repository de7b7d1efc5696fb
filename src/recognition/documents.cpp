#include "proprio/recognition/documents.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/features2d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "proprio/core/error.hpp"

namespace proprio::recognition {
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
  dense.validate();
  sift.validate();
  if (!(min_contrast >= 0 && min_contrast < 256)) {
    throw Error("the dense patches' minimum contrast must be in [0, 256) grey levels");
  }
  if (!(center_crop > 0 && center_crop <= 1)) throw Error("the centre crop must be in (0, 1]");
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

features::Features keep(const features::Features& f, const std::vector<int>& rows) {
  features::Features out;
  out.descriptors.create(static_cast<int>(rows.size()), features::kDescriptorLength, CV_32F);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    out.keypoints.push_back(f.keypoints[static_cast<std::size_t>(rows[i])]);
    f.descriptors.row(rows[i]).copyTo(out.descriptors.row(static_cast<int>(i)));
  }
  return out;
}

}  // namespace

features::Features extract_features(const cv::Mat& image, const ExtractOptions& options,
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
    features::Features f = features::detect_sift(image, options.sift);
    if (mask.empty()) return f;
    std::vector<int> rows;
    for (int i = 0; i < f.size(); ++i)
      if (inside(mask, f.keypoints[static_cast<std::size_t>(i)].pt)) rows.push_back(i);
    return keep(f, rows);
  }
  // Only the grid points on the mask with some contrast: a small object costs a small fraction
  // of the frame.
  const cv::Mat grey = grey_of(image);
  std::vector<cv::KeyPoint> grid = features::dense_grid(image.size(), options.dense);
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
  features::Features f;
  f.descriptors = cv::Mat(0, features::kDescriptorLength, CV_32F);
  if (grid.empty()) return f;
  cv::Mat desc;
  cv::SIFT::create()->compute(grey, grid, desc);
  f.keypoints = std::move(grid);
  f.descriptors = desc;
  return f;
}

cv::Mat read_image(const fs::path& path) {
  if (!fs::is_regular_file(path)) throw Error::in_file(path, "no such image file");
  cv::Mat image = cv::imread(path.string(), cv::IMREAD_COLOR);
  if (image.empty()) throw Error::in_file(path, "cannot decode the image");
  return image;
}

std::vector<BlobDocument> blob_documents(const features::Features& f, cv::Size image_size,
                                         const features::Vocabulary& vocabulary,
                                         const features::BlobOptions& options) {
  std::vector<BlobDocument> out;
  if (f.empty()) return out;
  const std::vector<int> words = vocabulary.quantize(f.descriptors, 1);
  for (features::Blob& b : features::find_blobs(f.keypoints, image_size, options)) {
    BlobDocument d;
    for (int i : b.features) d.tokens.push_back(words[static_cast<std::size_t>(i)]);
    d.blob = std::move(b);
    out.push_back(std::move(d));
  }
  return out;
}

FrameRegion parse_frame_region(const std::string& name) {
  if (name == "whole") return FrameRegion::kWhole;
  if (name == "target") return FrameRegion::kTarget;
  if (name == "objects") return FrameRegion::kObjects;
  if (name == "blobs") return FrameRegion::kBlobs;
  if (name == "masks") return FrameRegion::kMasks;
  if (name == "each-object") return FrameRegion::kEachObject;
  std::string m = "unknown frame region '";
  m += name;
  m += "' (known: whole, target, objects, blobs, masks, each-object)";
  throw Error(m);
}

std::string to_string(FrameRegion region) {
  switch (region) {
    case FrameRegion::kWhole:
      return "whole";
    case FrameRegion::kTarget:
      return "target";
    case FrameRegion::kObjects:
      return "objects";
    case FrameRegion::kBlobs:
      return "blobs";
    case FrameRegion::kMasks:
      return "masks";
    case FrameRegion::kEachObject:
      return "each-object";
  }
  return "?";
}

void FrameDocumentOptions::validate() const {
  features.validate();
  blobs.validate();
  if (region == FrameRegion::kMasks && masks.empty()) {
    throw Error("the 'masks' region needs a directory of segmentation masks");
  }
}

std::vector<int> selected_object_ids(const episode::Episode& episode,
                                     const std::vector<std::string>& objects) {
  std::vector<int> ids;
  for (const episode::ObjectInfo& o : episode.objects()) {
    if (o.role == episode::ObjectRole::kArm) continue;
    bool match = objects.empty();
    for (const std::string& n : objects) {
      const std::string suffix = "-" + n;
      match = match || o.name == n || (o.name.size() > suffix.size() && o.name.ends_with(suffix));
    }
    if (match) ids.push_back(o.id);
  }
  return ids;
}

std::vector<features::Features> frame_features(const episode::Episode& episode, int frame,
                                               const FrameDocumentOptions& options) {
  options.validate();
  const cv::Mat image = episode.frame(frame);
  cv::Mat mask;
  switch (options.region) {
    case FrameRegion::kWhole:
      return {extract_features(image, options.features)};
    case FrameRegion::kBlobs: {
      const features::Features f = extract_features(image, options.features);
      std::vector<features::Features> docs;
      for (const features::Blob& b : features::find_blobs(f.keypoints, image.size(), options.blobs))
        docs.push_back(keep(f, b.features));
      return docs;
    }
    case FrameRegion::kTarget:
    case FrameRegion::kObjects: {
      if (!episode.info().has_masks) {
        throw Error::in_file(episode.dir(), "the episode has no ground-truth masks");
      }
      std::vector<int> ids;
      if (options.region == FrameRegion::kTarget) {
        for (const auto& o : episode.objects())
          if (o.role == episode::ObjectRole::kTarget) ids.push_back(o.id);
        if (ids.empty()) throw Error::in_file(episode.dir(), "the episode has no target object");
      } else {
        ids = selected_object_ids(episode, options.objects);
      }
      const cv::Mat ids_image = episode.mask(frame);
      mask = cv::Mat::zeros(ids_image.size(), CV_8UC1);
      for (int id : ids) mask.setTo(255, ids_image == id);
      break;
    }
    case FrameRegion::kEachObject: {
      if (!episode.info().has_masks) {
        throw Error::in_file(episode.dir(), "the episode has no ground-truth masks");
      }
      const cv::Mat ids_image = episode.mask(frame);
      const cv::Mat kernel = cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(9, 9));
      std::vector<features::Features> docs;
      for (int id : selected_object_ids(episode, options.objects)) {
        cv::Mat m = ids_image == id;
        if (cv::countNonZero(m) == 0) continue;
        cv::dilate(m, m, kernel);
        docs.push_back(extract_features(image, options.features, m));
      }
      return docs;
    }
    case FrameRegion::kMasks: {
      const fs::path path = options.masks / episode::image_path("", "", frame).filename();
      if (!fs::is_regular_file(path)) throw Error::in_file(path, "no such mask file");
      mask = cv::imread(path.string(), cv::IMREAD_GRAYSCALE);
      if (mask.empty()) throw Error::in_file(path, "cannot decode the mask");
      if (mask.size() != image.size()) throw Error::in_file(path, "mask and frame sizes differ");
      break;
    }
  }
  return {extract_features(image, options.features, mask)};
}

}  // namespace proprio::recognition
