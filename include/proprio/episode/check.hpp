#pragma once
// Validation of an episode directory: every problem, not only the first.

#include <filesystem>
#include <string>
#include <vector>

#include "proprio/core/fields.hpp"
#include "proprio/core/json_io.hpp"
#include "proprio/core/provenance.hpp"

namespace proprio::episode {

/// One thing wrong with an episode.
struct Problem {
  std::filesystem::path file;  ///< the file (or directory) at fault
  std::string message;         ///< "FILE:LINE: problem" or "FILE: problem", as proprio::Error

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.file, {"file", "The file (or directory) at fault"});
    v(self.message, {"message", "The problem"});
  }
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

/// What run_episode_check found.
// NOLINTNEXTLINE(bugprone-exception-escape)
struct CheckResult {
  std::filesystem::path dir;      ///< the episode directory checked
  bool decoded_images = true;     ///< whether every image was decoded (CheckOptions)
  std::vector<Problem> problems;  ///< every problem; empty means valid
  /// The record (format "proprio.episode.check"): the fields described below.
  core::Json document;
  /// One line, the verdict: "DIR: valid episode" or "DIR: not a valid episode (N problems)".
  std::string message;

  [[nodiscard]] bool valid() const { return problems.empty(); }
  /// Every problem, one a line; when there is none, the verdict (`message`). An invalid
  /// episode's verdict is not repeated here: `proprio episode check` reports it as its error.
  [[nodiscard]] std::string brief() const;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.dir, {"dir", "The episode directory"});
    v(self.decoded_images, {"decoded_images", "Whether every image was decoded"});
    v(self.valid(), {"valid", "No problem found"});
    v(self.problems, {"problems", "Every problem found"});
  }
};

/// check_episode(dir, options) with its record (`proprio episode check`). Never throws
/// proprio::Error for bad content.
CheckResult run_episode_check(const std::filesystem::path& dir, const CheckOptions& options,
                              const core::Provenance& provenance);

}  // namespace proprio::episode
