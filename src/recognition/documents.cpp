#include "proprio/recognition/documents.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/features2d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "proprio/core/error.hpp"
#include "proprio/features/mask_morphology.hpp"
#include "proprio/geometry/image_file.hpp"

namespace proprio::recognition {
namespace fs = std::filesystem;

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
  check_mask_change(dilate, erode);
  check_erode_min_features(erode_min_features);
  if (region == FrameRegion::kMasks && masks.empty()) {
    throw Error("the 'masks' region needs a directory of segmentation masks");
  }
}

void check_mask_change(int dilate, int erode) {
  if (dilate < 0 || dilate > 100) throw Error("the mask growth must be in [0, 100] pixels");
  if (erode < 0 || erode > 100) throw Error("the mask shrinking must be in [0, 100] pixels");
  if (dilate > 0 && erode > 0) throw Error("the masks are either grown or shrunk, not both");
}

cv::Mat object_mask(const cv::Mat& ids, int id, int dilate, int erode) {
  check_mask_change(dilate, erode);
  cv::Mat m = ids == id;
  const int r = std::max(dilate, erode);
  if (r == 0 || cv::countNonZero(m) == 0) return m;
  const cv::Mat kernel = features::disc(r);
  // Outside the image counts as off the object: an object cut by the frame's edge shrinks from
  // it too (the patches there are clipped).
  if (dilate > 0) {
    cv::dilate(m, m, kernel);
  } else {
    cv::erode(m, m, kernel, cv::Point(-1, -1), 1, cv::BORDER_CONSTANT, cv::Scalar(0));
  }
  return m;
}

bool on_mask(const cv::Mat& mask, const cv::KeyPoint& k) {
  const int x = static_cast<int>(std::lround(k.pt.x));
  const int y = static_cast<int>(std::lround(k.pt.y));
  return x >= 0 && y >= 0 && x < mask.cols && y < mask.rows && mask.at<uchar>(y, x) != 0;
}

void check_erode_min_features(int min_features) {
  if (min_features < 0 || min_features > 10000) {
    throw Error("the adaptive shrink's least features must be in [0, 10000]");
  }
}

int adaptive_erosion(const cv::Mat& ids, int id, int erode, int min_features,
                     const std::vector<cv::KeyPoint>& points) {
  check_mask_change(0, erode);
  check_erode_min_features(min_features);
  if (min_features == 0) return erode;
  // Only the object's bounding box padded by `erode` pixels (clipped to the image) is shrunk:
  // the pixels around it are off the object, as is the world beyond the image, so object_mask's
  // shrunk mask is the same there and empty elsewhere (the same r as shrinking the whole image).
  const cv::Mat bare = ids == id;
  const cv::Rect box = cv::boundingRect(bare);
  if (box.area() == 0) return 0;
  const cv::Rect roi =
      cv::Rect(box.x - erode, box.y - erode, box.width + 2 * erode, box.height + 2 * erode) &
      cv::Rect(0, 0, ids.cols, ids.rows);
  const cv::Mat crop = bare(roi).clone();
  // The points' pixels (rounded as on_mask rounds) in the box's coordinates; those off it never
  // count.
  std::vector<cv::Point> inside;
  for (const cv::KeyPoint& k : points) {
    const cv::Point p(static_cast<int>(std::lround(k.pt.x)), static_cast<int>(std::lround(k.pt.y)));
    if (roi.contains(p)) inside.push_back(p - roi.tl());
  }
  for (int r = erode; r > 0; --r) {
    const cv::Mat kernel = features::disc(r);
    cv::Mat m;
    cv::erode(crop, m, kernel, cv::Point(-1, -1), 1, cv::BORDER_CONSTANT, cv::Scalar(0));
    int kept = 0;
    for (const cv::Point& p : inside)
      if (m.at<uchar>(p) != 0 && ++kept >= min_features) return r;
  }
  return 0;
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
  return frame_features(episode, frame, episode.frame(frame), options);
}

std::vector<features::Features> frame_features(const episode::Episode& episode, int frame,
                                               const cv::Mat& image,
                                               const FrameDocumentOptions& options) {
  options.validate();
  cv::Mat mask;
  switch (options.region) {
    case FrameRegion::kWhole:
      return {features::extract_features(image, options.features)};
    case FrameRegion::kBlobs: {
      const features::Features f = features::extract_features(image, options.features);
      std::vector<features::Features> docs;
      for (const features::Blob& b : features::find_blobs(f.keypoints, image.size(), options.blobs))
        docs.push_back(features::select_features(f, b.features));
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
      std::vector<features::Features> docs;
      const bool adaptive = options.erode > 0 && options.erode_min_features > 0;
      for (int id : selected_object_ids(episode, options.objects)) {
        if (adaptive) {
          // The features of the bare mask, kept on its adaptively shrunk mask (the grid points
          // and descriptors do not depend on the mask, only which points are kept).
          const cv::Mat bare = object_mask(ids_image, id, 0, 0);
          if (cv::countNonZero(bare) == 0) continue;
          const features::Features all = features::extract_features(image, options.features, bare);
          const int r = adaptive_erosion(ids_image, id, options.erode, options.erode_min_features,
                                         all.keypoints);
          const cv::Mat m = object_mask(ids_image, id, 0, r);
          if (cv::countNonZero(m) == 0) continue;
          std::vector<int> rows;
          for (int k = 0; k < all.size(); ++k)
            if (on_mask(m, all.keypoints[static_cast<std::size_t>(k)])) rows.push_back(k);
          docs.push_back(features::select_features(all, rows));
          continue;
        }
        const cv::Mat m = object_mask(ids_image, id, options.dilate, options.erode);
        if (cv::countNonZero(m) == 0) continue;
        docs.push_back(features::extract_features(image, options.features, m));
      }
      return docs;
    }
    case FrameRegion::kMasks: {
      const fs::path path = options.masks / episode::image_path("", "", frame).filename();
      mask = geometry::read_image(path, cv::IMREAD_GRAYSCALE);
      if (mask.size() != image.size()) throw Error::in_file(path, "mask and frame sizes differ");
      break;
    }
  }
  return {features::extract_features(image, options.features, mask)};
}

}  // namespace proprio::recognition
