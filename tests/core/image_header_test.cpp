#include "proprio/core/image_header.hpp"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <string>

#include "../support/temp_dir.hpp"
#include "proprio/core/error.hpp"
#include "proprio/core/files.hpp"

namespace proprio::core {
namespace {
namespace fs = std::filesystem;

std::string be32(std::uint32_t v) {
  return {static_cast<char>(v >> 24), static_cast<char>(v >> 16), static_cast<char>(v >> 8),
          static_cast<char>(v)};
}
std::string le16(std::uint32_t v) { return {static_cast<char>(v), static_cast<char>(v >> 8)}; }
std::string le32(std::uint32_t v) { return le16(v & 0xFFFF) + le16(v >> 16); }

// A PNG's signature, IHDR chunk (CRC not checked here) and, when `complete`, its IEND chunk.
std::string png(std::uint32_t w, std::uint32_t h, int depth, int colour, bool complete = true) {
  std::string s("\x89PNG\r\n\x1a\n", 8);
  s += be32(13) + "IHDR" + be32(w) + be32(h);
  s += static_cast<char>(depth);
  s += static_cast<char>(colour);
  s += std::string(3, '\0') + be32(0);  // compression, filter, interlace; CRC
  s += be32(0) + "IDAT" + be32(0);
  if (complete) s += std::string("\0\0\0\0IEND\xae\x42\x60\x82", 12);
  return s;
}

// SOI, an APP0 segment of `app_bytes`, then a baseline frame header.
std::string jpeg(int w, int h, int components, std::size_t app_bytes = 14) {
  std::string s = "\xff\xd8";
  s += "\xff\xe0";
  s += static_cast<char>((app_bytes + 2) >> 8);
  s += static_cast<char>((app_bytes + 2) & 0xff);
  s += std::string(app_bytes, 'J');
  s += "\xff\xc0";
  s += std::string("\x00\x11\x08", 3);  // length 17, 8-bit samples
  s += static_cast<char>(h >> 8);
  s += static_cast<char>(h & 0xff);
  s += static_cast<char>(w >> 8);
  s += static_cast<char>(w & 0xff);
  s += static_cast<char>(components);
  s += std::string(9, '\1');
  return s;
}

std::string bmp(std::int32_t w, std::int32_t h, int bits) {
  return "BM" + le32(0) + le32(0) + le32(54) + le32(40) + le32(static_cast<std::uint32_t>(w)) +
         le32(static_cast<std::uint32_t>(h)) + le16(1) + le16(static_cast<std::uint32_t>(bits)) +
         std::string(24, '\0');
}

std::string problem(const std::string& bytes) {
  try {
    (void)parse_image_header(bytes, "x.img");
  } catch (const Error& e) {
    return e.what();
  }
  return "accepted";
}

TEST(ImageHeader, KnownHeadersOfEachFormat) {
  auto h = parse_image_header(png(640, 480, 8, 2), "a.png");
  EXPECT_EQ(h.format, ImageFormat::kPng);
  EXPECT_EQ(h.width, 640);
  EXPECT_EQ(h.height, 480);
  EXPECT_EQ(h.channels, 3);
  EXPECT_EQ(describe(h), "8-bit RGB PNG");
  EXPECT_EQ(describe(parse_image_header(png(4, 4, 16, 0), "m.png")), "16-bit grey PNG");
  EXPECT_TRUE(parse_image_header(png(4, 4, 8, 3), "p.png").palette);

  h = parse_image_header(jpeg(1024, 768, 3, 60000), "a.jpg");  // frame header after 60 KB
  EXPECT_EQ(h.format, ImageFormat::kJpeg);
  EXPECT_EQ(h.width, 1024);
  EXPECT_EQ(h.height, 768);
  EXPECT_EQ(describe(h), "8-bit colour JPEG");

  h = parse_image_header(bmp(320, -240, 24), "a.bmp");  // top-down: negative height
  EXPECT_EQ(h.format, ImageFormat::kBmp);
  EXPECT_EQ(h.width, 320);
  EXPECT_EQ(h.height, 240);

  h = parse_image_header("P5\n# a comment\n  33 17\n65535\n", "a.pgm");
  EXPECT_EQ(h.format, ImageFormat::kPnm);
  EXPECT_EQ(h.width, 33);
  EXPECT_EQ(h.height, 17);
  EXPECT_EQ(h.bit_depth, 16);
  EXPECT_EQ(h.channels, 1);
  EXPECT_EQ(parse_image_header("P4 8 2\n", "a.pbm").bit_depth, 1);
}

TEST(ImageHeader, HostileHeadersAreRefusedNamingTheFile) {
  // 100,000 x 100,000 pixels in a few bytes: refused before any decoder would allocate 30 GB.
  EXPECT_EQ(problem(png(100000, 100000, 8, 2)),
            "x.img: PNG of 100000x100000 pixels, more than proprio reads (100 megapixels)");
  EXPECT_EQ(problem(jpeg(65535, 65535, 3)),
            "x.img: JPEG of 65535x65535 pixels, more than proprio reads (100 megapixels)");
  EXPECT_EQ(problem(bmp(0x7fffffff, 2, 24)).rfind("x.img: BMP of 2147483647x2", 0), 0u);
  EXPECT_EQ(problem("P6 99999999999 1 255\n"), "x.img: corrupt PNM (width too large)");
  EXPECT_EQ(problem(png(0, 5, 8, 2)), "x.img: corrupt PNG (image size 0x5)");
  EXPECT_EQ(problem(png(0x80000000u, 1, 8, 2)), "x.img: corrupt PNG (image size 2147483648x1)");
  EXPECT_EQ(problem(png(4, 4, 3, 2)), "x.img: corrupt PNG (bit depth 3)");
  EXPECT_EQ(problem(png(4, 4, 8, 5)), "x.img: corrupt PNG (colour type 5)");
  EXPECT_EQ(problem(png(4, 4, 8, 2).substr(0, 20)),
            "x.img: truncated or corrupt PNG (no valid IHDR chunk)");
  EXPECT_EQ(problem(jpeg(8, 8, 3).substr(0, 22)), "x.img: truncated JPEG (a segment is cut short)");
  EXPECT_EQ(problem(jpeg(8, 8, 2)), "x.img: corrupt JPEG (2 components)");
  EXPECT_EQ(problem(std::string("\xff\xd8\xff\xda\x00\x02", 6)),
            "x.img: corrupt JPEG (image data before a frame header)");
  EXPECT_EQ(problem(std::string("\xff\xd8\xff\xe0\x00\x01", 6)),
            "x.img: corrupt JPEG (a segment of length 1)");
  EXPECT_EQ(problem(bmp(5, 5, 7)), "x.img: corrupt BMP (7 bits per pixel)");
  EXPECT_EQ(problem("P2 5"), "x.img: corrupt or truncated PNM (no height)");
  EXPECT_EQ(problem("GIF89a"), "x.img: not an image proprio reads (PNG, JPEG, BMP or PNM)");
  EXPECT_EQ(problem(""), "x.img: not an image proprio reads (PNG, JPEG, BMP or PNM)");
}

TEST(ImageHeader, FilesAreCheckedForTruncationAndTypeWithoutBlocking) {
  test::TempDir dir("proprio_image_header_");
  const fs::path ok = dir.path() / "ok.png";
  write_file_atomic(ok, png(7, 9, 8, 6));
  EXPECT_EQ(read_image_header(ok).height, 9);

  const fs::path cut = dir.path() / "cut.png";
  write_file_atomic(cut, png(7, 9, 8, 6, false) + std::string(40, 'x'));
  std::string why;
  EXPECT_FALSE(probe_image_header(cut, why));
  EXPECT_EQ(why, "truncated PNG (the file does not end with an IEND chunk)");

  EXPECT_FALSE(probe_image_header(dir.path() / "missing.png", why));
  EXPECT_EQ(why, "no such file");

  const fs::path fifo = dir.path() / "fifo.png";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_THROW((void)read_image_header(fifo), Error);  // refused at once, never blocks
}

}  // namespace
}  // namespace proprio::core
