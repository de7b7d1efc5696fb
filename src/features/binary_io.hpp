#pragma once
// The framing shared by the features and vocabulary files (docs/formats/vocabulary.md), in the
// house style of the LDA model file: 8-byte magic, uint32 version, CRC-32 of what follows,
// uint64 payload size, payload; little-endian.

#include <bit>
#include <boost/crc.hpp>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <string_view>

#include "proprio/core/error.hpp"

namespace proprio::features::detail {

static_assert(std::endian::native == std::endian::little, "the file formats are little-endian");

inline std::uint32_t crc32(std::string_view bytes) {
  boost::crc_32_type crc;
  crc.process_bytes(bytes.data(), bytes.size());
  return crc.checksum();
}

template <typename T>
void put(std::string& out, T v) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  out.append(b, sizeof(T));
}

/// magic + version + crc + size + payload.
inline std::string frame(const char (&magic)[9], std::uint32_t version, std::string_view payload) {
  std::string out(magic, 8);
  put(out, version);
  std::string tail;
  put(tail, static_cast<std::uint64_t>(payload.size()));
  tail += payload;
  put(out, crc32(tail));
  out += tail;
  return out;
}

/// Checks the frame and returns the payload. `kind` names the file type in errors.
inline std::string_view unframe(std::string_view bytes, const char (&magic)[9],
                                std::uint32_t version, const std::filesystem::path& source,
                                const std::string& kind) {
  constexpr std::size_t kHeader = 24;
  if (bytes.size() < kHeader) {
    throw Error::in_file(source, "not a " + kind + " file: truncated header (" +
                                     std::to_string(bytes.size()) + " bytes)");
  }
  if (std::memcmp(bytes.data(), magic, 8) != 0) {
    throw Error::in_file(source, "not a " + kind + " file (wrong magic number)");
  }
  std::uint32_t v = 0;
  std::uint32_t crc = 0;
  std::uint64_t size = 0;
  std::memcpy(&v, bytes.data() + 8, 4);
  std::memcpy(&crc, bytes.data() + 12, 4);
  std::memcpy(&size, bytes.data() + 16, 8);
  if (v != version) {
    throw Error::in_file(source, kind + " format version " + std::to_string(v) +
                                     "; this build reads version " + std::to_string(version));
  }
  const std::size_t have = bytes.size() - kHeader;
  if (size != have) {
    std::string msg = size > have ? "truncated " : "corrupt ";
    msg += kind + " file: " + std::to_string(have);
    msg += " payload bytes where the header says " + std::to_string(size);
    throw Error::in_file(source, msg);
  }
  if (crc32(bytes.substr(16)) != crc) {
    throw Error::in_file(source, "corrupt " + kind + " file: checksum mismatch");
  }
  return bytes.substr(kHeader);
}

/// Sequential reads from a payload; running past its end is an Error naming the file.
class Reader {
 public:
  Reader(std::string_view bytes, const std::filesystem::path& source, std::string kind)
      : bytes_(bytes), source_(source), kind_(std::move(kind)) {}
  template <typename T>
  T get(const char* what) {
    T v;
    std::memcpy(&v, take(sizeof(T), what).data(), sizeof(T));
    return v;
  }
  std::string_view take(std::size_t n, const char* what) {
    if (n > left()) {
      std::string msg = "corrupt " + kind_;
      msg += " file: ";
      msg += what;
      msg += " runs past the end";
      throw Error::in_file(source_, msg);
    }
    const auto s = bytes_.substr(pos_, n);
    pos_ += n;
    return s;
  }
  [[nodiscard]] std::size_t left() const { return bytes_.size() - pos_; }

 private:
  std::string_view bytes_;
  const std::filesystem::path& source_;
  std::string kind_;
  std::size_t pos_ = 0;
};

}  // namespace proprio::features::detail
