#include "proprio/episode/discovery.hpp"

#include <algorithm>
#include <system_error>

#include "proprio/core/error.hpp"

namespace proprio::episode {
namespace fs = std::filesystem;

bool is_episode_dir(const fs::path& dir) {
  std::error_code ec;
  return fs::is_regular_file(dir / "episode.json", ec);
}

namespace {

// The episodes directly inside `dir` whose names contain `filter`, sorted by name.
std::vector<fs::path> episodes_in(const fs::path& dir, const std::string& filter) {
  std::vector<fs::path> out;
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const fs::path& p = it->path();
    if (!it->is_directory(ec) || !is_episode_dir(p)) continue;
    if (!filter.empty() && p.filename().string().find(filter) == std::string::npos) continue;
    out.push_back(p);
  }
  if (ec) throw Error::in_file(dir, "cannot list the directory: " + ec.message());
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

std::vector<fs::path> list_episode_dirs(const fs::path& dataset, const std::string& name_filter) {
  std::error_code ec;
  if (!fs::is_directory(dataset, ec)) throw Error::in_file(dataset, "no such dataset directory");
  std::vector<fs::path> out = episodes_in(dataset, name_filter);
  if (out.empty()) {
    throw Error::in_file(dataset, name_filter.empty()
                                      ? "no episodes (directories with episode.json)"
                                      : "no episodes (directories with episode.json) whose name "
                                        "contains '" +
                                            name_filter + "'");
  }
  return out;
}

std::vector<fs::path> find_episodes(const std::vector<fs::path>& paths) {
  std::vector<fs::path> out;
  for (const fs::path& p : paths) {
    if (is_episode_dir(p)) {
      out.push_back(p);
      continue;
    }
    std::error_code ec;
    if (!fs::is_directory(p, ec))
      throw Error::in_file(p, "no such episode or directory of episodes");
    const std::vector<fs::path> inside = episodes_in(p, {});
    if (inside.empty()) throw Error::in_file(p, "holds no episode (no episode.json)");
    out.insert(out.end(), inside.begin(), inside.end());
  }
  return out;
}

}  // namespace proprio::episode
