#pragma once
// Local image features (thesis 6.1.1): keypoints with their 128-D SIFT descriptors, and the
// binary file that stores them (docs/formats/vocabulary.md, "features file").

#include <cstdint>
#include <filesystem>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace proprio::features {

/// Keypoints (image pixels, origin at the top-left pixel's centre, as OpenCV has them) and one
/// descriptor row per keypoint.
struct Features {
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;  ///< N x 128 CV_32F, row i describes keypoints[i]

  [[nodiscard]] int size() const { return static_cast<int>(keypoints.size()); }
  [[nodiscard]] bool empty() const { return keypoints.empty(); }
};

/// The length of a SIFT descriptor.
inline constexpr int kDescriptorLength = 128;

/// The version of the features file format this build writes (and the only one it reads).
inline constexpr std::uint32_t kFeaturesFormatVersion = 1;

/// Writes keypoints and descriptors atomically in a versioned, checksummed binary format.
void write_features(const std::filesystem::path& path, const Features& features);
/// Reads a file written by write_features. Throws Error naming the file when it is missing,
/// truncated, corrupt (checksum), of another version, or holds non-finite values.
Features read_features(const std::filesystem::path& path);

/// Throws Error (prefixed by `what`) unless `descriptors` is an N x 128 CV_32F matrix of finite
/// values with N >= 1.
void check_descriptors(const cv::Mat& descriptors, const std::string& what);

}  // namespace proprio::features
