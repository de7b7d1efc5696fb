#pragma once
// Logging goes through spdlog to stderr; stdout is kept for a command's results.

#include <spdlog/spdlog.h>

namespace proprio::core {

/// Sends spdlog's default logger to stderr at the given verbosity:
/// 0 = warnings and errors, 1 = info, 2 or more = debug. OpenCV logs on its own: a program that
/// links it sets its level too (geometry::set_opencv_log_level).
void configure_logging(int verbosity);

}  // namespace proprio::core
