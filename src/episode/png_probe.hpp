#pragma once
// Internal: the size and pixel format of a PNG file from its first and last bytes, without
// decoding it (OpenCV 4.6 has no header-only reader). Used to check every frame of a long episode
// cheaply.

#include <filesystem>
#include <optional>
#include <string>

namespace proprio::episode::detail {

struct PngHeader {
  int width = 0;
  int height = 0;
  int bit_depth = 0;   ///< bits per sample: 1, 2, 4, 8 or 16
  int color_type = 0;  ///< 0 grey, 2 RGB, 3 palette, 4 grey+alpha, 6 RGBA
};

/// "16-bit grey", "8-bit RGB", ...
std::string describe(const PngHeader& h);

/// The IHDR chunk of a PNG file, after checking the signature and that the file ends with an
/// IEND chunk (a truncated file does not). On failure returns none and sets `why`.
std::optional<PngHeader> probe_png(const std::filesystem::path& path, std::string& why);

}  // namespace proprio::episode::detail
