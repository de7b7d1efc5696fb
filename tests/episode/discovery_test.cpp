// Finding episodes: what counts as an episode directory, sorting, filters, and the errors.
#include "proprio/episode/discovery.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "../support/error_of.hpp"
#include "../support/temp_dir.hpp"
#include "proprio/core/error.hpp"

namespace proprio::episode {
namespace {
namespace fs = std::filesystem;

// An "episode" for discovery's purpose: a directory with an episode.json (not read).
void make_episode(const fs::path& dir) {
  fs::create_directories(dir);
  std::ofstream(dir / "episode.json") << "{}";
}

using test::error_of;

TEST(Discovery, ListsADatasetsEpisodesSortedAndFiltered) {
  const test::TempDir tmp("proprio_discovery_");
  make_episode(tmp.path() / "push_mug_static_1");
  make_episode(tmp.path() / "push_book_moving_0");
  make_episode(tmp.path() / "push_mug_moving_0");
  fs::create_directories(tmp.path() / "not_an_episode");
  std::ofstream(tmp.path() / "episode.json") << "{}";  // a file, not a subdirectory
  const auto all = list_episode_dirs(tmp.path());
  ASSERT_EQ(all.size(), 3u);
  EXPECT_EQ(all[0].filename(), "push_book_moving_0");
  EXPECT_EQ(all[1].filename(), "push_mug_moving_0");
  EXPECT_EQ(all[2].filename(), "push_mug_static_1");
  const auto mug = list_episode_dirs(tmp.path(), "mug");
  ASSERT_EQ(mug.size(), 2u);
  EXPECT_EQ(mug[0].filename(), "push_mug_moving_0");
  EXPECT_NE(error_of([&] { (void)list_episode_dirs(tmp.path(), "rabbit"); }).find("'rabbit'"),
            std::string::npos);
}

TEST(Discovery, ADatasetMustExistAndHoldEpisodes) {
  const test::TempDir tmp("proprio_discovery_");
  EXPECT_NE(error_of([&] {
              (void)list_episode_dirs(tmp.path() / "missing");
            }).find("no such dataset directory"),
            std::string::npos);
  EXPECT_NE(error_of([&] { (void)list_episode_dirs(tmp.path()); }).find("no episodes"),
            std::string::npos);
}

TEST(Discovery, FindsEpisodesAndDirectoriesOfEpisodesInArgumentOrder) {
  const test::TempDir tmp("proprio_discovery_");
  make_episode(tmp.path() / "single");
  make_episode(tmp.path() / "set" / "b");
  make_episode(tmp.path() / "set" / "a");
  const auto found = find_episodes({tmp.path() / "single", tmp.path() / "set"});
  ASSERT_EQ(found.size(), 3u);
  EXPECT_EQ(found[0].filename(), "single");
  EXPECT_EQ(found[1].filename(), "a");
  EXPECT_EQ(found[2].filename(), "b");
  EXPECT_TRUE(is_episode_dir(tmp.path() / "single"));
  EXPECT_FALSE(is_episode_dir(tmp.path() / "set"));
  fs::create_directories(tmp.path() / "empty");
  EXPECT_NE(error_of([&] { (void)find_episodes({tmp.path() / "empty"}); }).find("holds no episode"),
            std::string::npos);
  EXPECT_NE(error_of([&] { (void)find_episodes({tmp.path() / "nowhere"}); }).find("nowhere"),
            std::string::npos);
}

}  // namespace
}  // namespace proprio::episode
