// The checks run on YAML text before a third-party parser sees it (issue 16).
#include "proprio/core/yaml_depth.hpp"

#include <gtest/gtest.h>

#include <string>

#include "proprio/core/error.hpp"

namespace proprio::core {
namespace {

std::string error_of(void (*check)(std::string_view, const std::filesystem::path&),
                     const std::string& text) {
  try {
    check(text, "f.yml");
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

void depth(std::string_view text, const std::filesystem::path& source) {
  check_yaml_depth(text, source);
}

TEST(YamlDepth, CountsFlowBracketsIndentationAndDashes) {
  EXPECT_EQ(error_of(depth, "a: 1\nb:\n  c: [1, [2, {d: 3}]]\n  e: '[[[['\n# [[[[[\n"), "no error");
  // The key's level and 63 brackets make 64: the limit itself is accepted.
  EXPECT_EQ(error_of(depth, "x: " + std::string(63, '[') + std::string(63, ']') + "\n"),
            "no error");
  EXPECT_EQ(error_of(depth, "x:\n  " + std::string(64, '[') + "\n"),
            "f.yml:2: nested deeper than 64 levels");
  std::string block;
  for (int i = 0; i < 70; ++i) block += std::string(static_cast<std::size_t>(i), ' ') + "a:\n";
  EXPECT_EQ(error_of(depth, block), "f.yml:65: nested deeper than 64 levels");
  std::string dashes;
  for (int i = 0; i < 70; ++i) dashes += "- ";
  EXPECT_EQ(error_of(depth, dashes + "x\n"), "f.yml:1: nested deeper than 64 levels");
}

TEST(YamlDepth, Utf8IsCheckedWithItsLine) {
  EXPECT_EQ(error_of(check_utf8, "name: caf\xc3\xa9 \xe2\x82\xac \xf0\x9f\x98\x80\n"), "no error");
  EXPECT_EQ(error_of(check_utf8, "a: 1\nb: \xff\n"), "f.yml:2: not UTF-8 text (byte 255)");
  EXPECT_NE(error_of(check_utf8, "\xc0\xaf").find("invalid sequence"), std::string::npos);
  EXPECT_NE(error_of(check_utf8, "\xed\xa0\x80").find("invalid sequence"), std::string::npos);
  EXPECT_NE(error_of(check_utf8, "x\xe2\x82").find("truncated sequence"), std::string::npos);
}

}  // namespace
}  // namespace proprio::core
