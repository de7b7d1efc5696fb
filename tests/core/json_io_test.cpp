#include "proprio/core/json_io.hpp"

#include <gtest/gtest.h>

#include <filesystem>

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

}  // namespace
}  // namespace proprio::core
