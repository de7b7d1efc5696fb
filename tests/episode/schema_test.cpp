// episode.json and objects.json as written validate against docs/formats/schemas.
#include <gtest/gtest.h>

#include <cstdlib>

#include "episode_test_support.hpp"
#include "../support/schema_check.hpp"

namespace proprio::episode {
namespace {
using namespace testing;

int check(const std::string& schema, const fs::path& file) {
  return test::check_schema(schema, file);
}

TEST(EpisodeSchema, WrittenFilesValidate) {
  TempDir tmp;
  SyntheticSpec spec;
  spec.stereo = true;
  spec.storage = FrameStorage::kVideo;
  const auto video = write_synthetic(tmp.path() / "video", spec);
  EXPECT_EQ(check("episode.schema.json", video / "episode.json"), 0);
  EXPECT_EQ(check("objects.schema.json", video / "objects.json"), 0);
  spec = {};
  const auto png = write_synthetic(tmp.path() / "png", spec);
  EXPECT_EQ(check("episode.schema.json", png / "episode.json"), 0);
}

TEST(EpisodeSchema, RejectsWhatTheReaderRejects) {
  TempDir tmp;
  const auto dir = write_synthetic(tmp.path() / "ep", {});
  core::Json j = core::read_json(dir / "episode.json");
  j["image"]["width"] = 100000;
  core::write_json_atomic(tmp.path() / "bad.json", j);
  EXPECT_NE(check("episode.schema.json", tmp.path() / "bad.json"), 0);
  j = core::read_json(dir / "objects.json");
  j["objects"][0]["role"] = "furniture";
  core::write_json_atomic(tmp.path() / "bad_objects.json", j);
  EXPECT_NE(check("objects.schema.json", tmp.path() / "bad_objects.json"), 0);
}

}  // namespace
}  // namespace proprio::episode
