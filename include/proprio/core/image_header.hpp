#pragma once
// The size and pixel format of an image file from its header, before any decoder sees it. Every
// reader of outside images checks this first, so that a 100,000 x 100,000 PNG of 1 KB (a decoder
// would allocate 30 GB for it), a truncated file, a FIFO or a file of another kind are refused
// with one line naming the file instead of reaching OpenCV's codecs. Written here because OpenCV
// 4.6 has no public header-only reader (cv::imread decodes; its ImageDecoder is internal).
// core links no OpenCV: the decoding itself is geometry::read_image (geometry/image_file.hpp).

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

namespace proprio::core {

/// The image formats proprio reads (those of OpenCV's codecs that robot images and photographs
/// come in); anything else is refused by name.
enum class ImageFormat { kPng, kJpeg, kBmp, kPnm };

struct ImageHeader {
  ImageFormat format = ImageFormat::kPng;
  int width = 0;         ///< pixels
  int height = 0;        ///< pixels
  int bit_depth = 0;     ///< bits per sample (PNG 1-16, JPEG 8 or 12, BMP bits per pixel, PNM 8/16)
  int channels = 0;      ///< samples per pixel as stored: 1 grey, 2 grey+alpha, 3 colour, 4 +alpha
  bool palette = false;  ///< indexed colour (PNG colour type 3, BMP of 8 bits or fewer)

  [[nodiscard]] std::int64_t pixels() const { return static_cast<std::int64_t>(width) * height; }
};

/// The most pixels an image may have (100 megapixels: a 12,000 x 8,000 photograph; a camera of
/// proprio's is 640 x 480). Bigger ones are refused from the header, before decoding.
inline constexpr std::int64_t kMaxImagePixels = 100'000'000;

/// How many bytes of a file the header is looked for in (1 MiB: a JPEG's frame header may follow
/// EXIF and other application segments of up to 64 KiB each).
inline constexpr std::size_t kImageHeaderBytes = std::size_t{1} << 20;

/// "8-bit RGB PNG", "16-bit grey PNG", "8-bit colour JPEG", ...
std::string describe(const ImageHeader& header);

/// The header of an image whose first bytes are `head` (up to kImageHeaderBytes of the file).
/// Throws Error naming `source` when the bytes are no PNG, JPEG, BMP or PNM, the header is cut
/// short or corrupt, a dimension is 0 or above 2^31 - 1, or the image has more than
/// kMaxImagePixels pixels. Reads nothing beyond `head`.
ImageHeader parse_image_header(std::string_view head, const std::filesystem::path& source);

/// The header of image file `path` (read_file_head's checks first: a regular file, never a FIFO
/// or device), with parse_image_header's checks; for a PNG also that the file ends with its IEND
/// chunk (a truncated PNG does not). Throws Error naming the file.
ImageHeader read_image_header(const std::filesystem::path& path);

/// read_image_header without throwing: none, with the problem (without the file name) in `why`.
std::optional<ImageHeader> probe_image_header(const std::filesystem::path& path, std::string& why);

}  // namespace proprio::core
