#include "png_probe.hpp"

#include <array>
#include <cstdint>
#include <cstring>
#include <fstream>

namespace proprio::episode::detail {
namespace {

std::uint32_t be32(const unsigned char* p) {
  return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) |
         std::uint32_t{p[3]};
}

}  // namespace

std::string describe(const PngHeader& h) {
  std::string kind;
  switch (h.color_type) {
    case 0:
      kind = "grey";
      break;
    case 2:
      kind = "RGB";
      break;
    case 3:
      kind = "palette";
      break;
    case 4:
      kind = "grey+alpha";
      break;
    case 6:
      kind = "RGBA";
      break;
    default:
      kind = "colour type " + std::to_string(h.color_type);
  }
  return std::to_string(h.bit_depth) + "-bit " + kind;
}

std::optional<PngHeader> probe_png(const std::filesystem::path& path, std::string& why) {
  // Signature (8), IHDR length (4) and type (4), width, height (4 + 4), bit depth, colour type.
  static constexpr std::array<unsigned char, 8> kSignature = {0x89, 'P',  'N',  'G',
                                                              '\r', '\n', 0x1A, '\n'};
  // The IEND chunk: length 0, type, CRC. Every complete PNG ends with these 12 bytes.
  static constexpr std::array<unsigned char, 12> kIend = {0,   0,   0,    0,    'I',  'E',
                                                          'N', 'D', 0xAE, 0x42, 0x60, 0x82};
  // A FIFO would block the open below, a device never end: only regular files are read.
  std::error_code ec;
  const auto type = std::filesystem::status(path, ec).type();
  if (!ec && type != std::filesystem::file_type::regular) {
    why = "is not a regular file (a FIFO, device or socket)";
    return std::nullopt;
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    why = "cannot open";
    return std::nullopt;
  }
  std::array<unsigned char, 26> head{};
  in.read(reinterpret_cast<char*>(head.data()), head.size());
  if (in.gcount() < 8 || std::memcmp(head.data(), kSignature.data(), 8) != 0) {
    why = "not a PNG file";
    return std::nullopt;
  }
  if (in.gcount() < static_cast<std::streamsize>(head.size()) || be32(head.data() + 8) != 13 ||
      std::memcmp(head.data() + 12, "IHDR", 4) != 0) {
    why = "truncated or corrupt PNG (no valid IHDR chunk)";
    return std::nullopt;
  }
  PngHeader h;
  const std::uint32_t w = be32(head.data() + 16);
  const std::uint32_t ht = be32(head.data() + 20);
  if (w == 0 || ht == 0 || w > 0x7fffffffu || ht > 0x7fffffffu) {
    why = "corrupt PNG (image size " + std::to_string(w) + "x" + std::to_string(ht) + ")";
    return std::nullopt;
  }
  h.width = static_cast<int>(w);
  h.height = static_cast<int>(ht);
  h.bit_depth = head[24];
  h.color_type = head[25];
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  std::array<unsigned char, 12> tail{};
  if (size < 8 + 25 + 12) {
    why = "truncated PNG (" + std::to_string(size) + " bytes)";
    return std::nullopt;
  }
  in.seekg(size - 12);
  in.read(reinterpret_cast<char*>(tail.data()), tail.size());
  if (!in || tail != kIend) {
    why = "truncated PNG (the file does not end with an IEND chunk)";
    return std::nullopt;
  }
  return h;
}

}  // namespace proprio::episode::detail
