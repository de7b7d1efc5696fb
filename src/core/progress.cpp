#include "proprio/core/progress.hpp"

#include <unistd.h>

#include <algorithm>

namespace proprio::core {

ProgressBar::ProgressBar(std::size_t total, std::string label, bool enabled, std::FILE* out)
    : total_(std::max<std::size_t>(total, 1)),
      label_(std::move(label)),
      enabled_(enabled),
      tty_(enabled && ::isatty(::fileno(out)) != 0),
      out_(out),
      start_(std::chrono::steady_clock::now()) {}

ProgressBar::~ProgressBar() { finish(); }

void ProgressBar::tick(std::size_t steps) {
  done_ = std::min(total_, done_ + steps);
  draw();
}

void ProgressBar::finish() {
  if (finished_) return;
  finished_ = true;
  if (!enabled_) return;
  done_ = total_;
  last_decile_ = -1;
  draw();
  if (tty_) std::fputc('\n', out_);
}

void ProgressBar::draw() {
  if (!enabled_) return;
  const double frac = static_cast<double>(done_) / static_cast<double>(total_);
  const double secs =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double eta = done_ > 0 ? secs * (1.0 - frac) / frac : 0.0;
  if (tty_) {
    constexpr int kWidth = 30;
    const int filled = static_cast<int>(frac * kWidth);
    std::fprintf(out_, "\r%s [%.*s%*s] %zu/%zu %5.1fs eta %5.1fs", label_.c_str(), filled,
                 "##############################", kWidth - filled, "", done_, total_, secs, eta);
  } else {
    const int decile = static_cast<int>(frac * 10.0);
    if (decile == last_decile_) return;
    last_decile_ = decile;
    std::fprintf(out_, "%s: %zu/%zu (%d%%) %.1fs\n", label_.c_str(), done_, total_, decile * 10,
                 secs);
  }
  std::fflush(out_);
}

}  // namespace proprio::core
