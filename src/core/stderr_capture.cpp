#include "proprio/core/stderr_capture.hpp"

#include <sys/mman.h>
#include <unistd.h>

#include <cstdio>
#include <mutex>

#include "proprio/core/logging.hpp"

namespace proprio::core {
namespace {

// The shared redirection: how many captures are open, the saved descriptor 2 and the anonymous
// file that stands in for it.
struct Redirection {
  std::mutex mutex;
  int depth = 0;
  int saved = -1;
  int file = -1;
};

Redirection& redirection() {
  static Redirection r;  // a function-local static: no global constructor order to depend on
  return r;
}

std::string read_all(int fd) {
  std::string text;
  if (::lseek(fd, 0, SEEK_SET) < 0) return text;
  char buf[4096];
  ssize_t n = 0;
  while ((n = ::read(fd, buf, sizeof buf)) > 0) text.append(buf, static_cast<std::size_t>(n));
  return text;
}

}  // namespace

StderrCapture::StderrCapture(const char* what) : what_(what) {
  Redirection& r = redirection();
  const std::lock_guard<std::mutex> lock(r.mutex);
  if (r.depth++ > 0) return;
  std::fflush(stderr);
  r.file = ::memfd_create("proprio-stderr", MFD_CLOEXEC);
  r.saved = r.file >= 0 ? ::dup(STDERR_FILENO) : -1;
  if (r.saved < 0 || ::dup2(r.file, STDERR_FILENO) < 0) {
    // Could not redirect: leave stderr as it is (the messages show, nothing is lost).
    if (r.saved >= 0) ::close(r.saved);
    if (r.file >= 0) ::close(r.file);
    r.saved = r.file = -1;
  }
}

StderrCapture::~StderrCapture() {
  Redirection& r = redirection();
  std::string text;
  {
    const std::lock_guard<std::mutex> lock(r.mutex);
    if (--r.depth > 0 || r.file < 0) return;
    std::fflush(stderr);
    ::dup2(r.saved, STDERR_FILENO);
    ::close(r.saved);
    text = read_all(r.file);
    ::close(r.file);
    r.saved = r.file = -1;
  }
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    if (end > start) spdlog::debug("{}: {}", what_, text.substr(start, end - start));
    start = end + 1;
  }
}

std::string StderrCapture::pending() {
  Redirection& r = redirection();
  const std::lock_guard<std::mutex> lock(r.mutex);
  if (r.file < 0) return {};
  std::fflush(stderr);
  std::string text = read_all(r.file);
  ::lseek(r.file, 0, SEEK_END);
  return text;
}

}  // namespace proprio::core
