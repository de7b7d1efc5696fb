// sim::dataset_design and run_sim_dataset: the Chapter 5 set's design (names, seeds, scenarios,
// disturbances) and a tiny recording of its first episodes.
#include "proprio/sim/dataset.hpp"

#include <gtest/gtest.h>

#include <set>

#include "../support/error_of.hpp"
#include "../support/temp_dir.hpp"

namespace proprio::sim {
namespace {

TEST(SimDataset, TheChapter5DesignHas90EpisodesWithConsecutiveSeeds) {
  SimDatasetOptions o;
  o.seed = 100;
  const auto d = dataset_design(o);
  ASSERT_EQ(d.size(), 90U);
  std::set<std::string> names;
  for (std::size_t i = 0; i < d.size(); ++i) {
    EXPECT_EQ(d[i].options.seed, 100 + i);
    EXPECT_EQ(d[i].options.width, 640);
    names.insert(d[i].name);
  }
  EXPECT_EQ(names.size(), 90U);  // every directory name differs
  EXPECT_EQ(d[0].name, "push_rabbit_static_0");
  EXPECT_FALSE(d[0].options.moving_background);
  // Moving pushes cycle over shake, lighting, nudge.
  EXPECT_EQ(d[6].name, "push_rabbit_moving_0");
  EXPECT_TRUE(d[6].options.moving_background && d[6].options.camera_shake);
  EXPECT_TRUE(d[7].options.lighting_change && !d[7].options.camera_shake);
  EXPECT_TRUE(d[8].options.nudge_neighbour);
  EXPECT_TRUE(d[9].options.camera_shake);
  EXPECT_EQ(d[60].name, "homography_push-rotate_bottle_0");
  EXPECT_EQ(d[60].options.scenario, "push-rotate");
  EXPECT_EQ(d[89].name, "homography_hold-3d_spirit-level_9");
  EXPECT_EQ(d[89].options.scenario, "hold-3d");
  o.episodes = 3;
  o.frames = 7;
  const auto cut = dataset_design(o);
  ASSERT_EQ(cut.size(), 3U);
  EXPECT_EQ(cut[2].options.max_frames, 7);
}

TEST(SimDataset, RecordsTheDesignIntoADirectoryThatAppearsWhole) {
  test::TempDir dir("proprio_sim_dataset_");
  SimDatasetOptions o;
  o.out = dir.path() / "ds";
  o.episodes = 2;
  o.frames = 3;
  o.width = 64;
  o.height = 48;
  const SimDatasetResult r = run_sim_dataset(o, core::Provenance::current({"t"}, 1));
  EXPECT_EQ(r.frames, 6);
  EXPECT_TRUE(std::filesystem::exists(o.out / "push_rabbit_static_1" / "episode.json"));
  EXPECT_EQ(r.document.at("episodes").size(), 2U);
  EXPECT_EQ(r.document.at("episodes")[1].at("episode"), "push_rabbit_static_1");
  EXPECT_NE(r.brief().find("episodes: 2"), std::string::npos);
  // Not over an existing directory; bad options name themselves.
  EXPECT_NE(test::error_of([&] { (void)run_sim_dataset(o, {}); }).find("already exists"),
            std::string::npos);
  o.width = 4;
  EXPECT_EQ(test::error_of([&] { (void)run_sim_dataset(o, {}); }),
            "sim dataset: width must be in [16, 8192] (it is 4)");
  o.width = 64;
  o.preset = "thesis-ch9";
  EXPECT_EQ(test::error_of([&] { (void)run_sim_dataset(o, {}); }),
            "sim dataset: unknown preset 'thesis-ch9'");
}

}  // namespace
}  // namespace proprio::sim
