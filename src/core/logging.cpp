#include "proprio/core/logging.hpp"

#include <spdlog/sinks/stdout_color_sinks.h>

#include <opencv2/core/utils/logger.hpp>

namespace proprio::core {

void configure_logging(int verbosity) {
  auto logger = spdlog::stderr_color_mt("proprio");
  logger->set_pattern("[%H:%M:%S.%e %^%l%$] %v");
  logger->set_level(verbosity <= 0   ? spdlog::level::warn
                    : verbosity == 1 ? spdlog::level::info
                                     : spdlog::level::debug);
  spdlog::set_default_logger(logger);
  // OpenCV logs on its own (codec and backend warnings); below -vv they would break the CLI's
  // promise of one stderr line per error, and the caller reports the failure itself.
  cv::utils::logging::setLogLevel(verbosity >= 2 ? cv::utils::logging::LOG_LEVEL_INFO
                                  : verbosity == 1 ? cv::utils::logging::LOG_LEVEL_WARNING
                                                   : cv::utils::logging::LOG_LEVEL_SILENT);
}

}  // namespace proprio::core
