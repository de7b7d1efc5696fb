#pragma once
// What the recognition library calls share (private): episodes from command-line style
// arguments, and a progress bar for a ProgressFn.
#include <filesystem>
#include <memory>
#include <vector>

#include "proprio/core/progress.hpp"
#include "proprio/episode/discovery.hpp"
#include "proprio/episode/episode.hpp"
#include "proprio/recognition/image_corpus.hpp"

namespace proprio::recognition::detail {

/// Each argument is an episode or a directory of episodes (episode::find_episodes).
inline std::vector<episode::Episode> read_episodes(const std::vector<std::filesystem::path>& args) {
  std::vector<episode::Episode> out;
  for (const auto& d : episode::find_episodes(args)) out.push_back(episode::read_episode(d));
  return out;
}

/// A progress bar made on the first call of each pass (a pass counts from 1 again); nothing
/// when !show. `bar` must outlive the calls.
inline ProgressFn progress_bar(std::shared_ptr<core::ProgressBar>& bar, const char* label,
                               bool show) {
  return [&bar, label, show](std::size_t done, std::size_t total) {
    if (!show) return;
    if (!bar || done == 1) bar = std::make_shared<core::ProgressBar>(total, label);
    bar->tick();
    if (done == total) bar->finish();
  };
}

}  // namespace proprio::recognition::detail
