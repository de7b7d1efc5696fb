#pragma once
// Validation of an episode directory: every problem, not only the first.

#include <filesystem>
#include <string>
#include <vector>

namespace proprio::episode {

/// One thing wrong with an episode.
struct Problem {
  std::filesystem::path file;  ///< the file (or directory) at fault
  std::string message;         ///< "FILE:LINE: problem" or "FILE: problem", as proprio::Error
};

struct CheckOptions {
  /// Decode every frame, mask and depth image (finds corrupt image data and mask ids that
  /// objects.json lacks). Off: only the cheap checks that read_episode does (PNG headers and
  /// trailers, video properties). Default: on.
  bool decode_images = true;
  /// At most this many problems are listed per file; the rest are counted in one last entry.
  int max_problems_per_file = 20;
};

/// Checks episode directory `dir`: episode.json, calib.yml (and calib_right.yml), arm.csv,
/// objects.json, frames, masks, depth. Returns every problem found; empty means valid.
/// Never throws proprio::Error for bad content.
std::vector<Problem> check_episode(const std::filesystem::path& dir,
                                   const CheckOptions& options = {});

}  // namespace proprio::episode
