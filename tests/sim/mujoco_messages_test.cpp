// MuJoCo's warnings and errors go through the project's log, not into MUJOCO_LOG.TXT.
#include "proprio/sim/mujoco_messages.hpp"

#include <gtest/gtest.h>
#include <mujoco/mujoco.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>

#include "proprio/core/error.hpp"
#include "proprio/core/logging.hpp"
#include "proprio/sim/world.hpp"
#include "sim_test_util.hpp"

namespace proprio::sim {
namespace {
namespace fs = std::filesystem;

TEST(MujocoMessages, AWarningIsCountedAndWritesNoLogFile) {
  install_mujoco_handlers();
  install_mujoco_handlers();  // twice is harmless
  const fs::path dir = test::temp_dir() / "cwd";
  fs::create_directories(dir);
  const fs::path before = fs::current_path();
  fs::current_path(dir);
  const int n = mujoco_warning_count();
  mju_warning("a test warning");
  mju_warning_i("a test warning with a number %d", 3);
  fs::current_path(before);
  EXPECT_EQ(mujoco_warning_count(), n + 2);
  EXPECT_FALSE(fs::exists(dir / "MUJOCO_LOG.TXT"));
}

TEST(World, MujocoWarningsStopTheSimulation) {
  World w = World::build(test::small_scene(), ObjectCatalogue{});
  const int n = mujoco_warning_count();
  w.data().qpos[0] = std::nan("");
  try {
    w.step();
    FAIL() << "a NaN state should raise mjWARN_BADQPOS";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("mjWARN_BADQPOS"), std::string::npos) << e.what();
  }
  EXPECT_EQ(mujoco_warning_count(), n + 1);
}

TEST(MujocoMessagesDeathTest, AnErrorIsLoggedAndAborts) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  core::configure_logging(0);  // the log to stderr, as in the CLI
  install_mujoco_handlers();
  EXPECT_DEATH(mju_error("a test error"), "MuJoCo error.*a test error");
}

}  // namespace
}  // namespace proprio::sim
