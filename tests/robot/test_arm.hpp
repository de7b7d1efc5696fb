#pragma once
// Shared fixtures of the robot tests: the standalone arm model, loaded once per process.

#include <gtest/gtest.h>

#include <string>

#include "../support/error_of.hpp"
#include "../support/paths.hpp"
#include "proprio/core/error.hpp"
#include "proprio/robot/arm.hpp"

namespace proprio::robot::testing {

inline std::string arm_model_path() {
  return (test::data_dir() / "models" / "arm_standalone.xml").string();
}

inline const Arm& standard_arm() {
  static const Arm arm = Arm::load(arm_model_path());
  return arm;
}

using test::error_of;  // tests/support/error_of.hpp

/// Fails the test when MuJoCo counted a warning in `data`.
inline void expect_no_warnings(const mjData& data) {
  const auto w = warnings(data);
  EXPECT_TRUE(w.empty()) << "MuJoCo warning: " << w.front();
}

}  // namespace proprio::robot::testing
