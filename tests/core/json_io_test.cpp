#include "proprio/core/json_io.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>

#include "proprio/core/error.hpp"
#include "proprio/core/files.hpp"

namespace proprio::core {
namespace {
namespace fs = std::filesystem;

TEST(JsonIo, SyntaxErrorNamesFileAndLine) {
  const fs::path p = fs::temp_directory_path() / "proprio_json_io_bad.json";
  write_file_atomic(p, "{\n  \"a\": 1,\n  \"b\": ]\n}\n");
  try {
    read_json(p);
    FAIL();
  } catch (const Error& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.rfind(p.string() + ":3: invalid JSON", 0), 0u) << m;
  }
  fs::remove(p);
}

TEST(JsonIo, RoundTripAndTypedAccess) {
  const fs::path p = fs::temp_directory_path() / "proprio_json_io_ok.json";
  write_json_atomic(p, Json{{"n", 3}, {"s", "x"}});
  const Json j = read_json(p);
  EXPECT_EQ(json_get<int>(j, "n", p), 3);
  EXPECT_THROW(json_get<int>(j, "s", p), Error);
  try {
    json_get<int>(j, "missing", p);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), p.string() + ": missing key 'missing'");
  }
  fs::remove(p);
}

// Issue 16: deeply nested JSON crashed the readers of episode.json and objects.json (SIGSEGV).
TEST(JsonIo, NestingBeyondTheLimitIsRefusedWithItsLine) {
  const fs::path p = fs::temp_directory_path() / "proprio_json_io_deep.json";
  write_file_atomic(p, "{\"a\":\n" + std::string(200000, '[') + std::string(200000, ']') + "}");
  try {
    read_json(p);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), p.string() + ":2: invalid JSON: nested deeper than " +
                                         std::to_string(kMaxJsonDepth) + " levels");
  }
  // Brackets inside strings do not count; the limit itself is accepted.
  const std::string ok = std::string(kMaxJsonDepth, '[') + std::string(kMaxJsonDepth, ']');
  EXPECT_NO_THROW(parse_json(ok, p));
  EXPECT_NO_THROW(parse_json("[\"" + std::string(1000, '[') + "\\\"\"]", p));
  fs::remove(p);
}

// Issue 16: a number beyond a double exited 1 "internal error" instead of 2.
TEST(JsonIo, NumberOutOfRangeIsBadInput) {
  const fs::path p = fs::temp_directory_path() / "proprio_json_io_1e400.json";
  write_file_atomic(p, "{\"x\": 1e400}");
  try {
    read_json(p);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()).rfind(p.string() + ": invalid JSON: number overflow", 0), 0u)
        << e.what();
  }
  fs::remove(p);
}

// Issue 16: a problem message quoting non-UTF-8 bytes made --json exit 1.
TEST(JsonIo, NonUtf8StringsAreWrittenReplaced) {
  const fs::path p = fs::temp_directory_path() / "proprio_json_io_utf8.json";
  write_json_atomic(p, Json{{"problem", std::string("bad \xff\xfe byte")}});
  EXPECT_EQ(read_json(p)["problem"], "bad \xEF\xBF\xBD\xEF\xBF\xBD byte");
  fs::remove(p);
}

TEST(JsonIo, NonFiniteNumbersAreNeverWritten) {
  const fs::path p = fs::temp_directory_path() / "proprio_json_io_nan.json";
  fs::remove(p);
  EXPECT_EQ(first_non_finite(Json{{"a", 1.5}, {"b", {1, 2.5, "x"}}}), std::nullopt);
  const Json nan_deep{{"a", 1}, {"b", {{"c", {0.5, std::nan("")}}}}};
  EXPECT_EQ(first_non_finite(nan_deep), "/b/c/1");
  EXPECT_EQ(first_non_finite(Json(-std::numeric_limits<double>::infinity())), "/");
  try {
    write_json_atomic(p, nan_deep);
    FAIL() << "a NaN was written";
  } catch (const InternalError& e) {
    EXPECT_NE(std::string(e.what()).find("/b/c/1"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(p));  // nothing written, not even null
}

}  // namespace
}  // namespace proprio::core
