#include "proprio/sim/mujoco_messages.hpp"

#include <mujoco/mujoco.h>
#include <spdlog/spdlog.h>

#include <atomic>
#include <cstdlib>
#include <mutex>

namespace proprio::sim {

namespace {

std::atomic<int> warning_count{0};

void on_warning(const char* message) {
  warning_count.fetch_add(1, std::memory_order_relaxed);
  spdlog::warn("MuJoCo: {}", message != nullptr ? message : "(no message)");
}

[[noreturn]] void on_error(const char* message) {
  spdlog::critical("MuJoCo error (aborting): {}", message != nullptr ? message : "(no message)");
  spdlog::default_logger()->flush();
  std::abort();
}

}  // namespace

void install_mujoco_handlers() {
  static std::once_flag once;
  std::call_once(once, [] {
    mju_user_warning = on_warning;
    mju_user_error = on_error;
  });
}

int mujoco_warning_count() { return warning_count.load(std::memory_order_relaxed); }

}  // namespace proprio::sim
