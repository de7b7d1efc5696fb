#pragma once
// The message of the proprio::Error (bad input) or proprio::InternalError (a broken invariant) a
// call throws, for tests that check what an error says and which kind it is.

#include <gtest/gtest.h>

#include <string>

#include "proprio/core/error.hpp"

namespace proprio::test {

/// The message of the Error that `f` throws; fails the test when it throws nothing.
template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  ADD_FAILURE() << "no Error thrown";
  return {};
}

/// The message of the InternalError that `f` throws; fails the test when it throws nothing or
/// throws proprio::Error (which the CLI would report as bad input, exit 2, not as a bug).
template <class F>
std::string internal_error_of(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    ADD_FAILURE() << "bad input (proprio::Error) where an internal error was expected: "
                  << e.what();
    return {};
  } catch (const InternalError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InternalError thrown";
  return {};
}

}  // namespace proprio::test
