#pragma once
// The framing of the project's binary files (LDA models, vocabularies, features; see
// docs/formats/lda-model.md and docs/formats/vocabulary.md). Little-endian throughout:
//
//   offset  size  content
//        0     8  magic: eight ASCII bytes naming the kind of file, e.g. "PRLDAMDL"
//        8     4  format version, uint32
//       12     4  CRC-32 (IEEE 802.3, as zlib's crc32) of every byte from offset 16 to the end
//       16     8  payload size P in bytes, uint64: the file is 24 + P bytes
//       24     P  payload, laid out by each kind of file
//
// A reader checks, in this order, and throws proprio::Error naming the file on the first failure:
// the header is complete ("truncated header"), the magic ("wrong magic number"), the version
// ("format version N; this build reads version M", or "versions L-M"), the payload size against
// the bytes there ("truncated" when fewer, "corrupt" when more), and the checksum ("checksum
// mismatch"). The payload is then read with BinaryReader, which refuses to run past its end.

#include <bit>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <string_view>
#include <type_traits>

namespace proprio::core {

static_assert(std::endian::native == std::endian::little, "the binary files are little-endian");

/// What the 24-byte header takes before the payload.
inline constexpr std::size_t kBinaryHeaderBytes = 24;

/// One kind of framed file.
struct BinaryFormat {
  std::string_view magic;  ///< exactly 8 bytes
  std::uint32_t version;   ///< the version this build writes (and the newest it reads)
  std::string_view kind;   ///< names the kind in errors: "not a <kind> file", e.g. "vocabulary"
  /// The oldest version this build reads (0: `version` only); a reader of several versions asks
  /// framed_version which one it has.
  std::uint32_t oldest = 0;
};

/// The format version in the header of framed `bytes` (call after unframe_binary checked them).
std::uint32_t framed_version(std::string_view bytes);

/// CRC-32 (IEEE 802.3, as zlib's crc32) of `bytes`: the checksum of the header above.
std::uint32_t crc32(std::string_view bytes);

/// The whole file: header for `format`, then `payload`.
std::string frame_binary(const BinaryFormat& format, std::string_view payload);

/// Checks the frame of `bytes` (see above) and returns the payload, a view into `bytes`.
/// `source` names the file in errors.
std::string_view unframe_binary(std::string_view bytes, const BinaryFormat& format,
                                const std::filesystem::path& source);

/// Frames `payload` and writes it atomically (core::write_file_atomic).
void write_binary_file(const std::filesystem::path& path, const BinaryFormat& format,
                       std::string_view payload);

/// Checks the header of the file at `path` (magic, version, then the payload size against the
/// file's real size), reading only its first 24 bytes, and returns the file's size: a file of
/// another kind, or one whose size disagrees with its header, is refused before its body is read.
std::uintmax_t check_binary_file_header(const std::filesystem::path& path,
                                        const BinaryFormat& format);

/// Reads `path` and checks its frame; returns the payload. The header is checked first
/// (check_binary_file_header). Throws Error naming the file when it is missing, unreadable, not a
/// regular file or fails a check.
std::string read_binary_file(const std::filesystem::path& path, const BinaryFormat& format);

/// Appends the bytes of `value` (little-endian, as in memory) to `out`.
template <typename T>
void put_binary(std::string& out, T value) {
  static_assert(std::is_arithmetic_v<T>, "put_binary writes numbers");
  char b[sizeof(T)];
  std::memcpy(b, &value, sizeof(T));
  out.append(b, sizeof(T));
}

/// Sequential reads from a payload; running past its end throws Error naming the file:
/// "corrupt <kind> file: <what> runs past the end".
class BinaryReader {
 public:
  BinaryReader(std::string_view payload, std::filesystem::path source, std::string_view kind);

  /// The next sizeof(T) bytes as a T; `what` names the field in errors.
  template <typename T>
  T get(const char* what) {
    static_assert(std::is_arithmetic_v<T>, "BinaryReader::get reads numbers");
    T v;
    std::memcpy(&v, take(sizeof(T), what).data(), sizeof(T));
    return v;
  }
  /// The next `n` bytes.
  std::string_view take(std::uint64_t n, const char* what);
  /// Bytes not read yet.
  [[nodiscard]] std::size_t left() const { return bytes_.size() - pos_; }

 private:
  std::string_view bytes_;
  std::filesystem::path source_;
  std::string kind_;
  std::size_t pos_ = 0;
};

}  // namespace proprio::core
