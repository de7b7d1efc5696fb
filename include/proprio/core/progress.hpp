#pragma once
// A progress bar on stderr for long commands. Draws in place on a terminal; elsewhere (CI logs,
// pipes) prints a line at every 10%, so logs stay short.

#include <chrono>
#include <cstddef>
#include <cstdio>
#include <string>

namespace proprio::core {

class ProgressBar {
 public:
  /// `total` steps labelled `label`; `enabled` = false makes every call a no-op.
  ProgressBar(std::size_t total, std::string label, bool enabled = true,
              std::FILE* out = stderr);
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;
  ~ProgressBar();

  /// Advances by `steps`.
  void tick(std::size_t steps = 1);
  /// Draws 100% and ends the line (also done by the destructor).
  void finish();

  [[nodiscard]] std::size_t done() const { return done_; }

 private:
  void draw();

  std::size_t total_;
  std::size_t done_ = 0;
  std::string label_;
  bool enabled_;
  bool tty_;
  bool finished_ = false;
  int last_decile_ = -1;
  std::FILE* out_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace proprio::core
