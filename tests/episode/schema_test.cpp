// episode.json and objects.json as written validate against docs/formats/schemas.
#include <gtest/gtest.h>

#include <cstdlib>

#include "episode_test_support.hpp"

namespace proprio::episode {
namespace {
using namespace testing;

bool have_jsonschema() {
  return std::system("python3 -c 'import jsonschema' >/dev/null 2>&1") == 0;
}

int check(const std::string& schema, const fs::path& file) {
  const std::string source = PROPRIO_SOURCE_DIR;
  std::string cmd =
      "python3 " + source + "/tests/schemas/check_schema.py " + source + "/docs/formats/schemas ";
  cmd += schema + " " + file.string();
  return std::system(cmd.c_str());
}

TEST(EpisodeSchema, WrittenFilesValidate) {
  if (!have_jsonschema()) GTEST_SKIP() << "python3-jsonschema not installed";
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
  if (!have_jsonschema()) GTEST_SKIP() << "python3-jsonschema not installed";
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
