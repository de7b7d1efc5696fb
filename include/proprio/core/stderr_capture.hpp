#pragma once
// Third-party code that prints to stderr by itself (libjpeg's "Premature end of JPEG file",
// libpng's warnings: OpenCV 4.6 installs no message handler for either) would break the CLI's
// promise of one line per error. While a StderrCapture lives, file descriptor 2 goes to an
// anonymous file; when the last one ends, what was written there is logged at debug level
// (visible with -vv) instead of printed. Written here because neither OpenCV nor the codecs offer
// a hook for these messages.
//
// Process-wide (file descriptor 2 is): overlapping captures from several threads share one
// redirection, counted, so that parallel decoders neither serialise nor restore each other's
// descriptors; anything another thread writes to stderr meanwhile is logged the same way, never
// lost.

#include <string>

namespace proprio::core {

class StderrCapture {
 public:
  /// `what` names the caller in the log line ("image decoder").
  explicit StderrCapture(const char* what);
  ~StderrCapture();
  StderrCapture(const StderrCapture&) = delete;
  StderrCapture& operator=(const StderrCapture&) = delete;
  StderrCapture(StderrCapture&&) = delete;
  StderrCapture& operator=(StderrCapture&&) = delete;

  /// Everything captured (by every overlapping capture) and not yet logged, for tests.
  static std::string pending();

 private:
  const char* what_;
};

}  // namespace proprio::core
