#pragma once
// Finding recorded episodes on disk: an episode is a directory that holds episode.json
// (docs/formats/episode.md); a dataset is a directory of episodes. The one place that decides
// what counts as an episode directory, for the CLI, the evaluation and the tuning tools.

#include <filesystem>
#include <string>
#include <vector>

namespace proprio::episode {

/// Whether `dir` is an episode directory (it holds a regular file episode.json).
bool is_episode_dir(const std::filesystem::path& dir);

/// The episode directories of `dataset` (its subdirectories that are episodes) whose names
/// contain `name_filter` (empty: all), sorted by name. Throws Error naming the directory when it
/// is missing or holds no such episode.
std::vector<std::filesystem::path> list_episode_dirs(const std::filesystem::path& dataset,
                                                     const std::string& name_filter = {});

/// Episode directories named by `paths`, in their order: a path that is an episode stands for
/// itself, a directory of episodes for its episodes sorted by name. Throws Error naming a path
/// that is neither.
std::vector<std::filesystem::path> find_episodes(const std::vector<std::filesystem::path>& paths);

}  // namespace proprio::episode
