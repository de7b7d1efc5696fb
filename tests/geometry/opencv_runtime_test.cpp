#include "proprio/geometry/opencv_runtime.hpp"

#include <gtest/gtest.h>

#include <opencv2/core/utility.hpp>
#include <opencv2/core/utils/logger.hpp>

namespace proprio::geometry {
namespace {

TEST(OpenCvRuntime, VersionIsTheLinkedLibrarys) {
  EXPECT_EQ(opencv_version(), cv::getVersionString());
  EXPECT_EQ(opencv_version().substr(0, 2), "4.");
}

TEST(OpenCvRuntime, LogLevelFollowsVerbosity) {
  namespace log = cv::utils::logging;
  set_opencv_log_level(0);
  EXPECT_EQ(log::getLogLevel(), log::LOG_LEVEL_SILENT);
  set_opencv_log_level(1);
  EXPECT_EQ(log::getLogLevel(), log::LOG_LEVEL_WARNING);
  set_opencv_log_level(3);
  EXPECT_EQ(log::getLogLevel(), log::LOG_LEVEL_INFO);
}

}  // namespace
}  // namespace proprio::geometry
