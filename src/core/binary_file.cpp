#include "proprio/core/binary_file.hpp"

#include <algorithm>
#include <boost/crc.hpp>
#include <cassert>
#include <cctype>

#include "proprio/core/error.hpp"
#include "proprio/core/files.hpp"

namespace proprio::core {
namespace fs = std::filesystem;

std::uint32_t crc32(std::string_view bytes) {
  boost::crc_32_type crc;
  crc.process_bytes(bytes.data(), bytes.size());
  return crc.checksum();
}

namespace {

// "a vocabulary", "an LDA model": acronyms read letter by letter.
std::string with_article(std::string_view kind) {
  assert(!kind.empty());
  const char c = kind[0];
  const bool acronym = kind.size() > 1 && std::isupper(static_cast<unsigned char>(kind[1]));
  const std::string_view vowel_sounds = acronym ? "AEFHILMNORSX" : "aeiouAEIOU";
  std::string out = vowel_sounds.find(c) != std::string_view::npos ? "an " : "a ";
  out += kind;
  return out;
}

}  // namespace

std::string frame_binary(const BinaryFormat& format, std::string_view payload) {
  assert(format.magic.size() == 8);
  std::string out;
  out.reserve(kBinaryHeaderBytes + payload.size());
  out += format.magic;
  put_binary(out, format.version);
  put_binary(out, std::uint32_t{0});  // the checksum, filled in below
  put_binary(out, static_cast<std::uint64_t>(payload.size()));
  out += payload;
  const std::uint32_t crc = crc32(std::string_view(out).substr(16));
  std::memcpy(out.data() + 12, &crc, sizeof crc);
  return out;
}

namespace {

// Checks the 24-byte header `head` of a file of `total` bytes (see binary_file.hpp).
void check_header(std::string_view head, std::uintmax_t total, const BinaryFormat& format,
                  const fs::path& source) {
  assert(format.magic.size() == 8);
  const std::string kind(format.kind);
  if (head.size() < kBinaryHeaderBytes) {
    std::string msg = "not " + with_article(kind);
    msg += " file: truncated header (" + std::to_string(head.size()) + " bytes)";
    throw Error::in_file(source, msg);
  }
  if (head.substr(0, 8) != format.magic) {
    throw Error::in_file(source, "not " + with_article(kind) + " file (wrong magic number)");
  }
  BinaryReader fields(head.substr(8, 16), source, kind);
  const auto version = fields.get<std::uint32_t>("the version");
  (void)fields.get<std::uint32_t>("the checksum");
  const auto size = fields.get<std::uint64_t>("the payload size");
  const std::uint32_t oldest = format.oldest == 0 ? format.version : format.oldest;
  if (version < oldest || version > format.version) {
    std::string msg = kind + " format version " + std::to_string(version);
    msg += oldest == format.version ? "; this build reads version " + std::to_string(format.version)
                                    : "; this build reads versions " + std::to_string(oldest) +
                                          "-" + std::to_string(format.version);
    throw Error::in_file(source, msg);
  }
  const std::uintmax_t have = total - kBinaryHeaderBytes;
  if (size != have) {
    std::string msg = size > have ? "truncated " : "corrupt ";
    msg += kind + " file: " + std::to_string(have);
    msg += " payload bytes where the header says " + std::to_string(size);
    throw Error::in_file(source, msg);
  }
}

// A framed file is read whole only after its header agreed with its real size, so the cap is
// the file system's, not read_file's default.
constexpr std::uintmax_t kMaxBinaryBytes = std::uintmax_t{1} << 40;

}  // namespace

std::string_view unframe_binary(std::string_view bytes, const BinaryFormat& format,
                                const fs::path& source) {
  check_header(bytes.substr(0, std::min(bytes.size(), kBinaryHeaderBytes)), bytes.size(), format,
               source);
  std::uint32_t crc = 0;
  std::memcpy(&crc, bytes.data() + 12, sizeof crc);
  if (crc32(bytes.substr(16)) != crc) {
    throw Error::in_file(source,
                         "corrupt " + std::string(format.kind) + " file: checksum mismatch");
  }
  return bytes.substr(kBinaryHeaderBytes);
}

std::uint32_t framed_version(std::string_view bytes) {
  assert(bytes.size() >= kBinaryHeaderBytes);
  std::uint32_t version = 0;
  std::memcpy(&version, bytes.data() + 8, sizeof version);
  return version;
}

std::uintmax_t check_binary_file_header(const fs::path& path, const BinaryFormat& format) {
  const std::string head = read_file_head(path, kBinaryHeaderBytes);
  const std::uintmax_t total =
      head.size() < kBinaryHeaderBytes ? head.size() : regular_file_size(path);
  check_header(head, total, format, path);
  return total;
}

void write_binary_file(const fs::path& path, const BinaryFormat& format, std::string_view payload) {
  write_file_atomic(path, frame_binary(format, payload));
}

std::string read_binary_file(const fs::path& path, const BinaryFormat& format) {
  std::string bytes =
      read_file(path, std::min(check_binary_file_header(path, format), kMaxBinaryBytes));
  (void)unframe_binary(bytes, format, path);
  bytes.erase(0, kBinaryHeaderBytes);
  return bytes;
}

BinaryReader::BinaryReader(std::string_view payload, fs::path source, std::string_view kind)
    : bytes_(payload), source_(std::move(source)), kind_(kind) {}

std::string_view BinaryReader::take(std::uint64_t n, const char* what) {
  if (n > left()) {
    std::string msg = "corrupt " + kind_;
    msg += " file: ";
    msg += what;
    msg += " runs past the end";
    throw Error::in_file(source_, msg);
  }
  const auto s = bytes_.substr(pos_, static_cast<std::size_t>(n));
  pos_ += static_cast<std::size_t>(n);
  return s;
}

}  // namespace proprio::core
