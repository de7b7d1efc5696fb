#pragma once
// The one reader of outside image files (photographs, frames, masks, backdrops): the header is
// checked before OpenCV decodes anything (core/image_header.hpp: a regular file, a format proprio
// reads, at most core::kMaxImagePixels pixels), so that a hostile image costs no more than its
// header. It lives in geometry, the lowest module that links OpenCV.

#include <filesystem>
#include <opencv2/imgcodecs.hpp>

namespace proprio::geometry {

/// Image file `path` decoded by OpenCV with cv::imread `flags` (cv::IMREAD_COLOR: 8-bit BGR;
/// cv::IMREAD_GRAYSCALE; cv::IMREAD_UNCHANGED: as stored). Throws Error naming the file when it
/// is missing, not a regular file, not a PNG, JPEG, BMP or PNM, cut short or corrupt in its
/// header, larger than core::kMaxImagePixels, or when the codec cannot decode its data. What the
/// codecs print themselves goes to the debug log (core::StderrCapture), never to stderr.
cv::Mat read_image(const std::filesystem::path& path, int flags = cv::IMREAD_COLOR);

}  // namespace proprio::geometry
