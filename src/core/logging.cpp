#include "proprio/core/logging.hpp"

#include <spdlog/sinks/stdout_color_sinks.h>

namespace proprio::core {

void configure_logging(int verbosity) {
  auto logger = spdlog::stderr_color_mt("proprio");
  logger->set_pattern("[%H:%M:%S.%e %^%l%$] %v");
  logger->set_level(verbosity <= 0   ? spdlog::level::warn
                    : verbosity == 1 ? spdlog::level::info
                                     : spdlog::level::debug);
  spdlog::set_default_logger(logger);
}

}  // namespace proprio::core
