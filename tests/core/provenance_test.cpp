#include "proprio/core/provenance.hpp"

#include <gtest/gtest.h>

#include "proprio/core/error.hpp"
#include "proprio/core/version.hpp"

namespace proprio::core {
namespace {

TEST(Provenance, CarriesBuildAndCommandAndLeavesLibraryVersionsToTheirModules) {
  const char* argv[] = {"proprio", "calib", "dlt", "--points", "p.csv"};
  const auto p = Provenance::current(5, argv, 7);
  EXPECT_EQ(p.proprio_version, kVersion);
  EXPECT_EQ(p.command_line, "proprio calib dlt --points p.csv");
  EXPECT_EQ(p.seed, 7u);
  // core links neither OpenCV nor MuJoCo: geometry and robot say which ones a program links.
  EXPECT_EQ(p.opencv_version, "");
  EXPECT_EQ(p.mujoco_version, "");
  EXPECT_EQ(p.created_utc.size(), 20u);
}

TEST(Provenance, JsonRoundTrip) {
  const auto p = Provenance::current(std::vector<std::string>{"a", "b"}, std::nullopt);
  const Json j = to_json(p);
  EXPECT_TRUE(j["seed"].is_null());
  const auto q = provenance_from_json(j, "f.json");
  EXPECT_EQ(q.command_line, p.command_line);
  EXPECT_EQ(q.git_commit, p.git_commit);
  EXPECT_FALSE(q.seed.has_value());
  Json bad = j;
  bad.erase("opencv_version");
  EXPECT_THROW(provenance_from_json(bad, "f.json"), Error);
}

}  // namespace
}  // namespace proprio::core
