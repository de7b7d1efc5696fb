#include "proprio/core/error.hpp"

#include <gtest/gtest.h>

#include <string>
#include <type_traits>

namespace proprio {
namespace {

TEST(Errors, BadInputNamesTheFileAndLine) {
  EXPECT_STREQ(Error::at_line("a.csv", 3, "not a number").what(), "a.csv:3: not a number");
  EXPECT_STREQ(Error::in_file("m.lda", "truncated").what(), "m.lda: truncated");
  EXPECT_THROW(require(false, "x"), Error);
  EXPECT_NO_THROW(require(true, "x"));
}

TEST(Errors, AnInternalErrorIsNeverBadInput) {
  // The CLI maps Error to exit 2 and everything else to exit 1: a broken invariant must not be
  // catchable as Error.
  static_assert(!std::is_base_of_v<Error, InternalError>);
  static_assert(std::is_base_of_v<std::exception, InternalError>);
  EXPECT_NO_THROW(ensure(true, "fine"));
  try {
    ensure(false, "a plan must start after it is made");
    FAIL() << "no exception";
  } catch (const Error&) {
    FAIL() << "an internal error was thrown as proprio::Error";
  } catch (const InternalError& e) {
    EXPECT_EQ(std::string(e.what()), "a plan must start after it is made");
  }
}

}  // namespace
}  // namespace proprio
