#include "proprio/geometry/opencv_runtime.hpp"

#include <opencv2/core/utils/logger.hpp>
#include <opencv2/core/version.hpp>

namespace proprio::geometry {

std::string opencv_version() { return CV_VERSION; }

void set_opencv_log_level(int verbosity) {
  namespace log = cv::utils::logging;
  log::setLogLevel(verbosity >= 2   ? log::LOG_LEVEL_INFO
                   : verbosity == 1 ? log::LOG_LEVEL_WARNING
                                    : log::LOG_LEVEL_SILENT);
}

}  // namespace proprio::geometry
