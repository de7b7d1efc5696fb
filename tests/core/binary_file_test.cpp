// The binary file framing: the documented layout byte for byte (and the bytes the features and
// topics modules wrote before they shared this code), round trips, and every damaged file is an
// Error naming the file and the problem.
#include "proprio/core/binary_file.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <limits>

#include "../support/hex_bytes.hpp"
#include "proprio/core/error.hpp"
#include "proprio/core/files.hpp"

namespace proprio::core {
namespace {
namespace fs = std::filesystem;

constexpr BinaryFormat kTest{"PRTEST01", 3, "test"};

// Bitwise CRC-32 (IEEE 802.3, reflected, as zlib's crc32): a reference independent of Boost.
std::uint32_t reference_crc32(std::string_view bytes) {
  std::uint32_t crc = 0xFFFFFFFFu;
  for (const char c : bytes) {
    crc ^= static_cast<unsigned char>(c);
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
  }
  return ~crc;
}

template <typename T>
T field(const std::string& bytes, std::size_t offset) {
  T v;
  std::memcpy(&v, bytes.data() + offset, sizeof(T));
  return v;
}

class BinaryFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("proprio_binary_file_test_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // The message of the Error that reading `bytes` as a file of kind `format` throws.
  std::string message(const std::string& bytes, const BinaryFormat& format = kTest) {
    const fs::path path = dir_ / "f.bin";
    write_file_atomic(path, bytes);
    try {
      (void)read_binary_file(path, format);
    } catch (const Error& e) {
      std::string what = e.what();
      EXPECT_EQ(what.rfind(path.string() + ": ", 0), 0u) << "does not name the file: " << what;
      return what;
    }
    ADD_FAILURE() << "no error";
    return {};
  }

  fs::path dir_;
};

TEST(BinaryFrame, LaysOutTheDocumentedHeader) {
  const std::string payload("123456789\0x", 11);
  const std::string bytes = frame_binary(kTest, payload);
  ASSERT_EQ(bytes.size(), kBinaryHeaderBytes + payload.size());
  EXPECT_EQ(bytes.substr(0, 8), "PRTEST01");
  EXPECT_EQ(field<std::uint32_t>(bytes, 8), 3u);
  EXPECT_EQ(field<std::uint32_t>(bytes, 12), reference_crc32(std::string_view(bytes).substr(16)));
  EXPECT_EQ(field<std::uint64_t>(bytes, 16), payload.size());
  EXPECT_EQ(bytes.substr(24), payload);
  // The reference CRC is the standard one: its check value.
  EXPECT_EQ(reference_crc32("123456789"), 0xCBF43926u);
}

TEST(BinaryFrame, MatchesTheBytesOfTheEarlierCode) {
  // Written by features::detail::frame and the LDA model writer before both moved here: files
  // written then must still load, and files written now must read the same in older builds.
  const std::string old_frame = test::bytes_from_hex(
      "505254455354303103000000e858a48509000000000000003132333435363738"
      "39");
  EXPECT_EQ(frame_binary(kTest, "123456789"), old_frame);
  EXPECT_EQ(unframe_binary(old_frame, kTest, "old.bin"), "123456789");
  const std::string old_empty =
      test::bytes_from_hex("50525445535430310100000069df22650000000000000000");
  const BinaryFormat v1{"PRTEST01", 1, "test"};
  EXPECT_EQ(frame_binary(v1, ""), old_empty);
  EXPECT_EQ(unframe_binary(old_empty, v1, "old.bin"), "");
}

// A reader of versions 2-3 (oldest 2) reads both and says which it has; 1 and 4 are refused,
// naming the range.
TEST(BinaryFrame, AReaderOfSeveralVersionsReadsEachAndNamesTheRange) {
  const BinaryFormat v2{"PRTEST01", 2, "test"};
  const BinaryFormat reader{"PRTEST01", 3, "test", 2};
  for (const BinaryFormat& written : {v2, kTest}) {
    const std::string framed = frame_binary(written, "abc");
    EXPECT_EQ(unframe_binary(framed, reader, "x.bin"), "abc");
    EXPECT_EQ(framed_version(framed), written.version);
  }
  for (const std::uint32_t version : {1U, 4U}) {
    const std::string framed = frame_binary({"PRTEST01", version, "test"}, "abc");
    try {
      (void)unframe_binary(framed, reader, "x.bin");
      ADD_FAILURE() << "version " << version << " was read";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("test format version " + std::to_string(version) +
                                           "; this build reads versions 2-3"),
                std::string::npos)
          << e.what();
    }
  }
  // One version only (oldest 0): as before.
  EXPECT_THROW((void)unframe_binary(frame_binary(v2, "abc"), kTest, "x.bin"), Error);
}

TEST_F(BinaryFileTest, RoundTripsAndLeavesNoTemporary) {
  const fs::path path = dir_ / "sub" / "a.bin";
  std::string payload;
  for (int i = 0; i < 1000; ++i) put_binary(payload, static_cast<double>(i) / 7.0);
  payload += std::string("\0\xff", 2);
  write_binary_file(path, kTest, payload);
  EXPECT_EQ(read_binary_file(path, kTest), payload);
  write_binary_file(path, kTest, "");
  EXPECT_EQ(read_binary_file(path, kTest), "");
  int n = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(path.parent_path())) ++n;
  EXPECT_EQ(n, 1);
}

TEST_F(BinaryFileTest, EmptyAndTruncatedFiles) {
  EXPECT_NE(message("").find("not a test file: truncated header (0 bytes)"), std::string::npos);
  const std::string bytes = frame_binary(kTest, "some payload bytes");
  for (std::size_t cut = 1; cut < bytes.size(); ++cut) {
    const std::string m = message(bytes.substr(0, cut));
    EXPECT_NE(m.find(cut < kBinaryHeaderBytes ? "truncated header" : "truncated test file"),
              std::string::npos)
        << "cut at " << cut << ": " << m;
  }
  EXPECT_NE(
      message(bytes + "x").find("corrupt test file: 19 payload bytes where the header says 18"),
      std::string::npos);
}

TEST_F(BinaryFileTest, EveryFlippedByteIsRefused) {
  const std::string bytes = frame_binary(kTest, "some payload bytes");
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    for (const unsigned char mask : {0x01, 0x80}) {
      std::string bad = bytes;
      bad[i] = static_cast<char>(static_cast<unsigned char>(bad[i]) ^ mask);
      const std::string m = message(bad);
      if (i >= 24 || (i >= 12 && i < 16)) {
        EXPECT_NE(m.find("corrupt test file: checksum mismatch"), std::string::npos) << m;
      }
    }
  }
}

TEST_F(BinaryFileTest, WrongMagicOrVersion) {
  const std::string bytes = frame_binary(kTest, "payload");
  std::string other = bytes;
  other[0] = 'X';
  EXPECT_NE(message(other).find("not a test file (wrong magic number)"), std::string::npos);
  EXPECT_NE(message(std::string(30, '\0')).find("wrong magic number"), std::string::npos);
  const BinaryFormat lda{"PRLDAMDL", 1, "LDA model"};
  EXPECT_NE(message(bytes, lda).find("not an LDA model file"), std::string::npos);
  other = bytes;
  other[8] = 9;
  EXPECT_NE(message(other).find("test format version 9; this build reads version 3"),
            std::string::npos);
}

TEST_F(BinaryFileTest, AbsurdLengthFields) {
  std::string bytes = frame_binary(kTest, "payload");
  const auto huge = std::numeric_limits<std::uint64_t>::max();
  std::memcpy(bytes.data() + 16, &huge, sizeof huge);
  EXPECT_NE(message(bytes).find("truncated test file: 7 payload bytes where the header says " +
                                std::to_string(huge)),
            std::string::npos);

  // A length inside the payload that runs past its end.
  std::string payload;
  put_binary(payload, huge);
  put_binary(payload, std::int32_t{7});
  BinaryReader r(payload, dir_ / "p.bin", "test");
  const auto n = r.get<std::uint64_t>("the count");
  EXPECT_EQ(r.left(), 4u);
  try {
    (void)r.take(n, "the items");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()),
              (dir_ / "p.bin").string() + ": corrupt test file: the items runs past the end");
  }
  EXPECT_EQ(r.get<std::int32_t>("seven"), 7);
  EXPECT_THROW((void)r.get<std::uint8_t>("a byte"), Error);
}

TEST_F(BinaryFileTest, MissingFileIsNamed) {
  try {
    (void)read_binary_file(dir_ / "nope.bin", kTest);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("nope.bin"), std::string::npos);
  }
}

// Issue 16: a 5 GB file passed as a model or vocabulary was read whole before its magic number
// was checked. Sparse files: their size costs no disk, reading them would cost the memory.
TEST_F(BinaryFileTest, TheHeaderIsCheckedBeforeTheBodyIsRead) {
  const fs::path big = dir_ / "big.bin";
  write_file_atomic(big, "JUNKJUNK");
  fs::resize_file(big, std::uintmax_t{5} << 30);
  try {
    (void)read_binary_file(big, kTest);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), big.string() + ": not a test file (wrong magic number)");
  }
  // The right magic, but a header that does not match the file's real size.
  std::string head = frame_binary(kTest, "payload");
  write_file_atomic(big, head.substr(0, kBinaryHeaderBytes));
  fs::resize_file(big, std::uintmax_t{5} << 30);
  try {
    (void)check_binary_file_header(big, kTest);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("corrupt test file: 5368709096 payload bytes where the "
                                         "header says 7"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW((void)read_binary_file("/dev/zero", kTest), Error);
}

}  // namespace
}  // namespace proprio::core
