#include "proprio/core/image_header.hpp"

#include <array>
#include <climits>
#include <cstring>
#include <fstream>

#include "proprio/core/error.hpp"
#include "proprio/core/files.hpp"

namespace proprio::core {
namespace {

using Bytes = std::string_view;

std::uint32_t be16(Bytes b, std::size_t at) {
  return (std::uint32_t{static_cast<unsigned char>(b[at])} << 8) |
         std::uint32_t{static_cast<unsigned char>(b[at + 1])};
}
std::uint32_t be32(Bytes b, std::size_t at) { return (be16(b, at) << 16) | be16(b, at + 2); }
std::uint32_t le16(Bytes b, std::size_t at) {
  return std::uint32_t{static_cast<unsigned char>(b[at])} |
         (std::uint32_t{static_cast<unsigned char>(b[at + 1])} << 8);
}
std::uint32_t le32(Bytes b, std::size_t at) { return le16(b, at) | (le16(b, at + 2) << 16); }

constexpr std::array<unsigned char, 8> kPngSignature = {0x89, 'P',  'N',  'G',
                                                        '\r', '\n', 0x1A, '\n'};
// The IEND chunk: length 0, type, CRC. Every complete PNG ends with these 12 bytes.
constexpr std::array<unsigned char, 12> kPngEnd = {0,   0,   0,    0,    'I',  'E',
                                                   'N', 'D', 0xAE, 0x42, 0x60, 0x82};

bool starts_with(Bytes b, const void* prefix, std::size_t n) {
  return b.size() >= n && std::memcmp(b.data(), prefix, n) == 0;
}

// A failed parse: the problem, without the file's name.
struct Problem {
  std::string why;
};

ImageHeader sized(ImageHeader h, std::uint64_t width, std::uint64_t height, const char* kind) {
  if (width == 0 || height == 0 || width > INT_MAX || height > INT_MAX) {
    throw Problem{std::string("corrupt ") + kind + " (image size " + std::to_string(width) + "x" +
                  std::to_string(height) + ")"};
  }
  h.width = static_cast<int>(width);
  h.height = static_cast<int>(height);
  if (h.pixels() > kMaxImagePixels) {
    throw Problem{std::string(kind) + " of " + std::to_string(width) + "x" +
                  std::to_string(height) + " pixels, more than proprio reads (" +
                  std::to_string(kMaxImagePixels / 1'000'000) + " megapixels)"};
  }
  return h;
}

ImageHeader parse_png(Bytes b) {
  // Signature (8), IHDR length (4) and type (4), width, height (4 + 4), bit depth, colour type.
  if (b.size() < 26 || be32(b, 8) != 13 || b.substr(12, 4) != "IHDR") {
    throw Problem{"truncated or corrupt PNG (no valid IHDR chunk)"};
  }
  ImageHeader h;
  h.format = ImageFormat::kPng;
  h.bit_depth = static_cast<unsigned char>(b[24]);
  const int colour = static_cast<unsigned char>(b[25]);
  switch (colour) {
    case 0:
      h.channels = 1;
      break;
    case 2:
      h.channels = 3;
      break;
    case 3:
      h.channels = 3;
      h.palette = true;
      break;
    case 4:
      h.channels = 2;
      break;
    case 6:
      h.channels = 4;
      break;
    default:
      throw Problem{"corrupt PNG (colour type " + std::to_string(colour) + ")"};
  }
  const int d = h.bit_depth;
  if (d != 1 && d != 2 && d != 4 && d != 8 && d != 16) {
    throw Problem{"corrupt PNG (bit depth " + std::to_string(d) + ")"};
  }
  return sized(h, be32(b, 16), be32(b, 20), "PNG");
}

ImageHeader parse_jpeg(Bytes b) {
  // Markers from SOI on: each is 0xFF (fill bytes 0xFF allowed), a code, and, except for the
  // standalone ones, a 2-byte length that counts itself. The frame header (SOFn) holds the size.
  std::size_t at = 2;
  while (true) {
    if (at >= b.size() || static_cast<unsigned char>(b[at]) != 0xFF) {
      throw Problem{at >= b.size() ? "truncated JPEG (no frame header in its first bytes)"
                                   : "corrupt JPEG (no marker where one should be)"};
    }
    while (at < b.size() && static_cast<unsigned char>(b[at]) == 0xFF) ++at;
    if (at >= b.size()) throw Problem{"truncated JPEG (no frame header in its first bytes)"};
    const int m = static_cast<unsigned char>(b[at]);
    ++at;  // now at the length of the segment, if it has one
    if (m == 0x01 || m == 0xD8 || (m >= 0xD0 && m <= 0xD7)) continue;  // standalone markers
    if (m == 0xD9 || m == 0xDA) throw Problem{"corrupt JPEG (image data before a frame header)"};
    if (at + 2 > b.size()) throw Problem{"truncated JPEG (a segment is cut short)"};
    const std::uint32_t length = be16(b, at);
    if (length < 2)
      throw Problem{"corrupt JPEG (a segment of length " + std::to_string(length) + ")"};
    const bool frame = m >= 0xC0 && m <= 0xCF && m != 0xC4 && m != 0xC8 && m != 0xCC;
    if (frame) {
      if (length < 8 || at + 8 > b.size()) throw Problem{"truncated JPEG (frame header cut short)"};
      ImageHeader h;
      h.format = ImageFormat::kJpeg;
      h.bit_depth = static_cast<unsigned char>(b[at + 2]);
      h.channels = static_cast<unsigned char>(b[at + 7]);
      if (h.channels != 1 && h.channels != 3 && h.channels != 4) {
        throw Problem{"corrupt JPEG (" + std::to_string(h.channels) + " components)"};
      }
      if (be16(b, at + 3) == 0) {
        throw Problem{"JPEG whose height is given after the image data (DNL): not supported"};
      }
      return sized(h, be16(b, at + 5), be16(b, at + 3), "JPEG");
    }
    at += length;
  }
}

ImageHeader parse_bmp(Bytes b) {
  if (b.size() < 26) throw Problem{"truncated BMP (header cut short)"};
  const std::uint32_t info = le32(b, 14);
  ImageHeader h;
  h.format = ImageFormat::kBmp;
  std::uint64_t width = 0;
  std::uint64_t height = 0;
  if (info == 12) {  // BITMAPCOREHEADER: 16-bit sizes
    width = le16(b, 18);
    height = le16(b, 20);
    h.bit_depth = static_cast<int>(le16(b, 24));
  } else if (info >= 40 && info <= 124) {  // BITMAPINFOHEADER and its successors
    if (b.size() < 30) throw Problem{"truncated BMP (header cut short)"};
    const auto w = static_cast<std::int32_t>(le32(b, 18));
    const auto hh = static_cast<std::int32_t>(le32(b, 22));  // negative: stored top-down
    if (w <= 0 || hh == INT32_MIN) throw Problem{"corrupt BMP (image size)"};
    width = static_cast<std::uint64_t>(w);
    height = static_cast<std::uint64_t>(hh < 0 ? -static_cast<std::int64_t>(hh) : hh);
    h.bit_depth = static_cast<int>(le16(b, 28));
  } else {
    throw Problem{"corrupt BMP (information header of " + std::to_string(info) + " bytes)"};
  }
  switch (h.bit_depth) {
    case 1:
    case 4:
    case 8:
      h.channels = 3;
      h.palette = true;
      break;
    case 16:
    case 24:
      h.channels = 3;
      break;
    case 32:
      h.channels = 4;
      break;
    default:
      throw Problem{"corrupt BMP (" + std::to_string(h.bit_depth) + " bits per pixel)"};
  }
  return sized(h, width, height, "BMP");
}

ImageHeader parse_pnm(Bytes b) {
  // "P1".."P6", then width, height and (except for bitmaps) the largest value, as decimal
  // numbers separated by white space and '#' comments.
  const char kind = b[1];
  std::size_t at = 2;
  auto number = [&](const char* what) -> std::uint64_t {
    while (at < b.size()) {
      const char c = b[at];
      if (c == '#') {
        while (at < b.size() && b[at] != '\n' && b[at] != '\r') ++at;
      } else if (c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f') {
        ++at;
      } else {
        break;
      }
    }
    std::uint64_t v = 0;
    int digits = 0;
    while (at < b.size() && b[at] >= '0' && b[at] <= '9') {
      if (++digits > 10) throw Problem{std::string("corrupt PNM (") + what + " too large)"};
      v = v * 10 + static_cast<std::uint64_t>(b[at] - '0');
      ++at;
    }
    if (digits == 0) throw Problem{std::string("corrupt or truncated PNM (no ") + what + ")"};
    return v;
  };
  ImageHeader h;
  h.format = ImageFormat::kPnm;
  const std::uint64_t width = number("width");
  const std::uint64_t height = number("height");
  std::uint64_t largest = 1;
  if (kind != '1' && kind != '4') largest = number("largest value");
  if (largest == 0 || largest > 65535) {
    throw Problem{"corrupt PNM (largest value " + std::to_string(largest) + ")"};
  }
  h.bit_depth = kind == '1' || kind == '4' ? 1 : (largest < 256 ? 8 : 16);
  h.channels = kind == '3' || kind == '6' ? 3 : 1;
  return sized(h, width, height, "PNM");
}

ImageHeader parse(Bytes b) {
  if (starts_with(b, kPngSignature.data(), kPngSignature.size())) return parse_png(b);
  if (b.size() >= 3 && static_cast<unsigned char>(b[0]) == 0xFF &&
      static_cast<unsigned char>(b[1]) == 0xD8 && static_cast<unsigned char>(b[2]) == 0xFF) {
    return parse_jpeg(b);
  }
  if (starts_with(b, "BM", 2)) return parse_bmp(b);
  if (b.size() >= 2 && b[0] == 'P' && b[1] >= '1' && b[1] <= '6') return parse_pnm(b);
  throw Problem{"not an image proprio reads (PNG, JPEG, BMP or PNM)"};
}

// The PNG's last 12 bytes must be its IEND chunk.
void check_png_end(const std::filesystem::path& path) {
  const std::uintmax_t size = regular_file_size(path);
  if (size < 8 + 25 + 12) throw Problem{"truncated PNG (" + std::to_string(size) + " bytes)"};
  std::ifstream in(path, std::ios::binary);
  std::array<unsigned char, 12> tail{};
  in.seekg(static_cast<std::streamoff>(size - 12));
  in.read(reinterpret_cast<char*>(tail.data()), tail.size());
  if (!in || tail != kPngEnd)
    throw Problem{"truncated PNG (the file does not end with an IEND chunk)"};
}

}  // namespace

std::string describe(const ImageHeader& h) {
  std::string kind;
  if (h.palette) {
    kind = "palette";
  } else if (h.channels == 1) {
    kind = "grey";
  } else if (h.channels == 2) {
    kind = "grey+alpha";
  } else if (h.channels == 3) {
    kind = h.format == ImageFormat::kPng ? "RGB" : "colour";
  } else {
    kind = h.format == ImageFormat::kPng ? "RGBA" : "colour+alpha";
  }
  static constexpr std::array<const char*, 4> kNames = {"PNG", "JPEG", "BMP", "PNM"};
  return std::to_string(h.bit_depth) + "-bit " + kind + " " +
         kNames[static_cast<std::size_t>(h.format)];
}

ImageHeader parse_image_header(std::string_view head, const std::filesystem::path& source) {
  try {
    return parse(head);
  } catch (const Problem& p) {
    throw Error::in_file(source, p.why);
  }
}

std::optional<ImageHeader> probe_image_header(const std::filesystem::path& path, std::string& why) {
  std::string head;
  try {
    head = read_file_head(path, kImageHeaderBytes);
  } catch (const Error& e) {
    // read_file_head's message names the file first; `why` is the problem alone.
    std::string what = e.what();
    const std::string prefix = path.string() + ": ";
    if (what.rfind(prefix, 0) == 0) what.erase(0, prefix.size());
    why = what;
    return std::nullopt;
  }
  try {
    ImageHeader h = parse(head);
    if (h.format == ImageFormat::kPng) check_png_end(path);
    return h;
  } catch (const Problem& p) {
    why = p.why;
    return std::nullopt;
  }
}

ImageHeader read_image_header(const std::filesystem::path& path) {
  std::string why;
  auto h = probe_image_header(path, why);
  if (!h) throw Error::in_file(path, why);
  return *h;
}

}  // namespace proprio::core
