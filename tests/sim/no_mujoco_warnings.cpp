// Linked into every simulator test program: a test fails when MuJoCo warned while it ran (MuJoCo
// reports physics trouble, such as a full contact buffer or bad accelerations, only as warnings).
#include <gtest/gtest.h>

#include "proprio/sim/mujoco_messages.hpp"

namespace proprio::sim::test {
namespace {

class NoMujocoWarnings : public ::testing::EmptyTestEventListener {
  void OnTestStart(const ::testing::TestInfo& /*info*/) override {
    install_mujoco_handlers();
    at_start_ = mujoco_warning_count();
  }
  void OnTestEnd(const ::testing::TestInfo& info) override {
    const int warned = mujoco_warning_count() - at_start_;
    EXPECT_EQ(warned, 0) << info.test_suite_name() << "." << info.name() << ": MuJoCo warned "
                         << warned << " time(s) (see the log above)";
  }
  int at_start_ = 0;
};

const bool kInstalled = [] {
  ::testing::UnitTest::GetInstance()->listeners().Append(new NoMujocoWarnings);
  return true;
}();

}  // namespace
}  // namespace proprio::sim::test
