#pragma once
// The OpenCV that this build links, for provenance and logging. It lives here, in the lowest
// module that uses OpenCV, so that core (and topics above it) stay free of OpenCV.

#include <string>

namespace proprio::geometry {

/// OpenCV's version string, e.g. "4.6.0" (for core::Provenance::opencv_version).
std::string opencv_version();

/// Sets OpenCV's own log level from a proprio verbosity: silent at 0 (codec and backend warnings
/// would break the CLI's promise of one stderr line per error, and the caller reports the failure
/// itself), warnings at 1, information at 2 or more.
void set_opencv_log_level(int verbosity);

}  // namespace proprio::geometry
