#pragma once
// The CLI's exit statuses: bad input is 2, a bug is 1, each with one line on stderr. Kept apart
// from main() so that a test can run a library call under the same mapping.

#include <functional>

namespace proprio::app {

/// Runs `body` and returns its result. If it throws, prints one line on stderr and returns:
/// - 2 for proprio::Error (bad input: "proprio: FILE:LINE: problem");
/// - 1 for proprio::InternalError (a broken invariant), an OpenCV exception or any other
///   exception ("proprio: internal error: ...").
int run_with_exit_status(const std::function<int()>& body);

}  // namespace proprio::app
