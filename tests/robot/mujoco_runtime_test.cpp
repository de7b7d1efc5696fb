#include "proprio/robot/mujoco_runtime.hpp"

#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <string>

namespace proprio::robot {
namespace {

TEST(MujocoRuntime, VersionIsTheLinkedLibrarys) {
  const std::string v = mujoco_version();
  EXPECT_EQ(v, mj_versionString());
  // "MAJOR.MINOR.PATCH" of the library loaded, agreeing with the header compiled against.
  EXPECT_EQ(v.substr(0, v.find('.')), std::to_string(mjVERSION_HEADER / 100));
}

}  // namespace
}  // namespace proprio::robot
