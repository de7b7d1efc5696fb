#pragma once
// Putative objects from feature density (thesis 6.2): the indicator image h of the feature
// points (eq 6.2) is convolved with a Gaussian through the FFT (eq 6.3, cv::dft), and the result
// thresholded into connected blobs; each blob is a document for LDA.

#include <opencv2/core.hpp>
#include <vector>

namespace proprio::features {

struct BlobOptions {
  double sigma = 12.0;  ///< standard deviation of the Gaussian kernel, px
  /// Threshold on the density (h * N)(x) with N scaled to peak 1: roughly the number of
  /// features within sigma of x. One lone feature gives 1 at its location.
  double threshold = 2.5;
  int min_features = 5;  ///< blobs holding fewer features are dropped
  /// Throws Error on a non-positive sigma or threshold or min_features < 1.
  void validate() const;
};

struct Blob {
  cv::Rect box;               ///< bounding box of the mask, image pixels
  cv::Mat1b mask;             ///< box-sized, 255 inside the blob
  std::vector<int> features;  ///< indices into the keypoints whose (rounded) location is in it
};

/// The density image (h * N) of eq 6.3, CV_32F of image_size, N peak-1 Gaussian of options.sigma.
/// Keypoints outside the image are ignored.
cv::Mat1f feature_density(const std::vector<cv::KeyPoint>& keypoints, cv::Size image_size,
                          const BlobOptions& options = {});

/// Blobs where feature_density >= threshold (8-connected), with at least min_features
/// features, sorted by feature count (largest first). Throws Error on an empty image size.
std::vector<Blob> find_blobs(const std::vector<cv::KeyPoint>& keypoints, cv::Size image_size,
                             const BlobOptions& options = {});

}  // namespace proprio::features
