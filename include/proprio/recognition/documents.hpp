#pragma once
// Documents for LDA from pictures (thesis 6.1, 6.2): an image, a blob of dense features (a
// putative object, 6.2) or a region of an episode's frame becomes a bag of visual words.
#include <cstdint>
#include <filesystem>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "proprio/episode/episode.hpp"
#include "proprio/features/blobs.hpp"
#include "proprio/features/extraction.hpp"
#include "proprio/features/features.hpp"
#include "proprio/features/sift.hpp"
#include "proprio/features/vocabulary.hpp"

namespace proprio::recognition {

/// A blob (a putative object from feature density, 6.2) and its document.
struct BlobDocument {
  features::Blob blob;
  std::vector<std::int32_t> tokens;
};

/// One document per blob of `f`'s keypoints (features::find_blobs, eq 6.2-6.3): the words of the
/// features inside it. Use interest-point SIFT: dense features have a uniform density.
std::vector<BlobDocument> blob_documents(const features::Features& f, cv::Size image_size,
                                         const features::Vocabulary& vocabulary,
                                         const features::BlobOptions& options = {});

/// Which part of an episode's frame makes its document(s).
enum class FrameRegion {
  kWhole,    ///< the whole frame, one document
  kTarget,   ///< the features on the target object (ground-truth mask)
  kObjects,  ///< the features on the named objects (ground-truth mask), one document
  kBlobs,    ///< one document per feature-density blob (6.2)
  kMasks,    ///< the features inside a segmentation mask read from a directory
  /// One document per named object in view (ground-truth masks, each grown by
  /// FrameDocumentOptions::dilate px, 4 by default, so that the patches on its outline count, as
  /// in object_view_corpus): the thesis's blob documents (6.2) with a perfect segmenter. No
  /// labels: which object a document is stays unknown.
  kEachObject,
};

/// "whole", "target", "objects", "blobs", "masks", "each-object"; throws Error otherwise.
FrameRegion parse_frame_region(const std::string& name);
std::string to_string(FrameRegion region);

/// Where a view was cut from: which of the episodes and frame, and its object's bare mask (its
/// area in pixels and whether it touches the image's border: an object partly out of view).
struct ViewOrigin {
  int episode = 0;
  int frame = 0;
  int mask_pixels = 0;
  bool at_border = false;
};

/// Which mask's features decide whether a view is kept (object_view_features).
enum class ViewSelection {
  kMask,      ///< the mask the view is cut by (grown or shrunk)
  kBareMask,  ///< the object's bare mask, whatever the growth or shrinking
};

struct FrameDocumentOptions {
  FrameRegion region = FrameRegion::kWhole;
  /// kObjects, kEachObject: catalogue names; an episode object counts when its name is one of them
  /// or ends in
  /// "-" + one of them (the simulator names sliding objects "scatter-<type>"). Empty: every
  /// object that is not the arm.
  std::vector<std::string> objects;
  /// kMasks: a directory of 8-bit masks named as the frames (000000.png ...), non-zero inside.
  std::filesystem::path masks;
  features::ExtractOptions features;
  features::BlobOptions blobs;
  /// kEachObject: each object's mask is grown by this many pixels (an ellipse of side
  /// 2 dilate + 1) before its features are taken; 0 keeps the grid points on the object only.
  /// In [0, 100].
  int dilate = 4;
  /// kEachObject: each object's mask is shrunk by this many pixels instead (the same ellipse),
  /// so that the grid points whose 16 px SIFT patch lies mostly off the object, on the table or
  /// a neighbour, are left out; an object with no pixel left gives no document. In [0, 100], and
  /// 0 unless dilate is 0.
  int erode = 0;
  /// kEachObject with erode > 0: the adaptive shrink (adaptive_erosion). Each object's mask is
  /// shrunk only as far as it keeps at least this many of its bare mask's features (by the
  /// largest r <= erode that does; not at all when none does). 0 (the default): every mask by
  /// erode. In [0, 10000].
  int erode_min_features = 0;
  void validate() const;
};

/// The mask of object `id` in a frame's object-id image `ids` (non-zero on the object), grown
/// by `dilate` pixels or shrunk by `erode` pixels (an ellipse of side 2 n + 1; at most one of
/// them non-zero, both in [0, 100]; Error otherwise).
cv::Mat object_mask(const cv::Mat& ids, int id, int dilate, int erode);
/// object_mask's checks of dilate and erode alone (Error naming the problem).
void check_mask_change(int dilate, int erode);

/// Whether key point `k` (rounded to the nearest pixel) lies on the non-zero pixels of `mask`.
bool on_mask(const cv::Mat& mask, const cv::KeyPoint& k);

/// The adaptive shrink: how many pixels (in [0, erode]) object `id`'s mask in the object-id
/// image `ids` is shrunk by (object_mask) so that it keeps at least `min_features` of `points`
/// (the grid points found on its bare mask): the largest r <= erode whose shrunk mask holds at
/// least min_features of them (on_mask), 0 (the bare mask) when none does. min_features 0: erode
/// (the fixed shrink). Error when erode is not in [0, 100] or min_features not in [0, 10000].
int adaptive_erosion(const cv::Mat& ids, int id, int erode, int min_features,
                     const std::vector<cv::KeyPoint>& points);
/// adaptive_erosion's check of min_features alone.
void check_erode_min_features(int min_features);

/// The features of the document(s) of frame i: one, or one per blob (kBlobs) or per object in view
/// (kEachObject, in the order of the episode's objects). Throws Error when the episode lacks
/// masks (kTarget, kObjects, kEachObject) or a target (kTarget), or a mask file is missing or of
/// the wrong size (kMasks).
std::vector<features::Features> frame_features(const episode::Episode& episode, int frame,
                                               const FrameDocumentOptions& options);
/// The same from frame i's image already read (episode.frame(frame)): a caller that needs the
/// image too (colour words) reads it once.
std::vector<features::Features> frame_features(const episode::Episode& episode, int frame,
                                               const cv::Mat& image,
                                               const FrameDocumentOptions& options);

/// The ids of the episode's objects that kObjects keeps.
std::vector<int> selected_object_ids(const episode::Episode& episode,
                                     const std::vector<std::string>& objects);

}  // namespace proprio::recognition
