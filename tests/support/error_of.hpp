#pragma once
// The message of the proprio::Error a call throws, for tests that check what an error says.

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

}  // namespace proprio::test
