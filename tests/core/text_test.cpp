#include "proprio/core/text.hpp"

#include <gtest/gtest.h>

namespace proprio::core {
namespace {

TEST(Text, MarkupEscapeWritesEntities) {
  EXPECT_EQ(markup_escape(R"(<a href="x">Tom & Jerry's</a>)"),
            "&lt;a href=&quot;x&quot;&gt;Tom &amp; Jerry&#39;s&lt;/a&gt;");
  EXPECT_EQ(markup_escape("/data/arm/"), "/data/arm/");
}

TEST(Text, MarkupEscapeKeepsUtf8AndReplacesBadBytes) {
  EXPECT_EQ(markup_escape("caf\xC3\xA9"), "caf\xC3\xA9");
  EXPECT_EQ(markup_escape("a\xFF"
                          "b"),
            "a\xEF\xBF\xBD"
            "b");
  EXPECT_EQ(markup_escape("a\x01\tb\n"), "a\tb\n");
}

}  // namespace
}  // namespace proprio::core
