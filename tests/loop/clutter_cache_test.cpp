// The readers of `proprio experiment clutter`'s cache (loop/clutter_cache.hpp): a segmented push's
// views file and a trial's manifest, each bad input the fuzz target's review found refused (views:
// recomputed, nullopt; manifest: proprio::Error naming the file).
#include "proprio/loop/clutter_cache.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <opencv2/core.hpp>
#include <string>

#include "../support/error_of.hpp"
#include "../support/temp_dir.hpp"

namespace proprio::loop {
namespace {

const std::string kKey = R"({"k":1})";

ClutterViews some_views() {
  cv::Mat a(3, 128, CV_32F);
  cv::Mat b(1, 128, CV_32F);
  for (int i = 0; i < a.rows * a.cols; ++i) a.ptr<float>()[i] = static_cast<float>(i) * 0.5F;
  b.setTo(7.0F);
  return {{a, b}, {}};  // two fractions, the second without views
}

void set_u32(std::string& bytes, std::size_t at, std::uint32_t v) {
  std::memcpy(bytes.data() + at, &v, sizeof v);
}

// Offsets in the bytes of some_views(): magic 0, version 4, key size 8, key 12, fractions,
// then the first fraction's count and its first view's rows and cols.
constexpr std::size_t kFractionsAt = 12 + 7;
constexpr std::size_t kCountAt = kFractionsAt + 4;
constexpr std::size_t kRowsAt = kCountAt + 4;
constexpr std::size_t kColsAt = kRowsAt + 4;

TEST(ClutterCache, ViewsRoundTripInTheDocumentedLayout) {
  const ClutterViews views = some_views();
  const std::string bytes = clutter_views_bytes(kKey, views);
  ASSERT_EQ(bytes.substr(0, 4), "PCLV");
  std::uint32_t v = 0;
  std::memcpy(&v, bytes.data() + 4, 4);
  EXPECT_EQ(v, kClutterViewsVersion);
  std::memcpy(&v, bytes.data() + 8, 4);
  EXPECT_EQ(v, kKey.size());
  EXPECT_EQ(bytes.substr(12, kKey.size()), kKey);
  EXPECT_EQ(bytes.size(), kColsAt + 4 + (3 * 128 * 4) + 8 + (128 * 4) + 4);
  const auto back = parse_clutter_views(bytes, kKey, 2);
  ASSERT_TRUE(back.has_value());
  ASSERT_EQ(back->size(), 2U);
  ASSERT_EQ((*back)[0].size(), 2U);
  EXPECT_TRUE((*back)[1].empty());
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(cv::norm((*back)[0][i], views[0][i], cv::NORM_INF), 0.0);
  }
  const test::TempDir dir("proprio_clutter_cache");
  write_clutter_views(dir.path() / "views_dense.bin", kKey, views);
  const auto read = read_clutter_views(dir.path() / "views_dense.bin", kKey, 2);
  ASSERT_TRUE(read.has_value());
  EXPECT_EQ(clutter_views_bytes(kKey, *read), bytes);
  EXPECT_FALSE(read_clutter_views(dir.path() / "missing.bin", kKey, 2).has_value());
}

TEST(ClutterCache, ViewsOfAnotherMagicVersionKeyOrFractionCountAreRecomputed) {
  const std::string good = clutter_views_bytes(kKey, some_views());
  std::string b = good;
  b[0] = 'X';
  EXPECT_FALSE(parse_clutter_views(b, kKey, 2));
  b = good;
  set_u32(b, 4, kClutterViewsVersion + 1);
  EXPECT_FALSE(parse_clutter_views(b, kKey, 2));
  b = good;
  set_u32(b, 8, 0xffffffffU);  // a key of 4 GB: refused before it is read
  EXPECT_FALSE(parse_clutter_views(b, kKey, 2));
  EXPECT_FALSE(parse_clutter_views(good, R"({"k":2})", 2));
  EXPECT_FALSE(parse_clutter_views(good, kKey, 3));
}

TEST(ClutterCache, ViewSizesBeyondTheBytesLeftAreRefusedBeforeAllocating) {
  const std::string good = clutter_views_bytes(kKey, some_views());
  std::string b = good;
  set_u32(b, kCountAt, kClutterViewsMaxViews);  // 100,000 views in a few hundred bytes
  EXPECT_FALSE(parse_clutter_views(b, kKey, 2));
  b = good;
  set_u32(b, kCountAt, 0xffffffffU);
  EXPECT_FALSE(parse_clutter_views(b, kKey, 2));
  b = good;
  set_u32(b, kRowsAt, kClutterViewsMaxRows);  // 512 MB of descriptors in 2 KB
  EXPECT_FALSE(parse_clutter_views(b, kKey, 2));
  b = good;
  set_u32(b, kRowsAt, 0xffffffffU);
  EXPECT_FALSE(parse_clutter_views(b, kKey, 2));
  b = good;
  set_u32(b, kColsAt, 64);
  EXPECT_FALSE(parse_clutter_views(b, kKey, 2));
  // A fraction count the bytes cannot hold (matching the caller's: 1 billion fractions).
  b = good.substr(0, kFractionsAt);
  b.append(4, '\0');
  set_u32(b, kFractionsAt, 1000000000U);
  EXPECT_FALSE(parse_clutter_views(b, kKey, 1000000000U));
}

TEST(ClutterCache, TruncatedOrLongerViewsAreRecomputed) {
  const std::string good = clutter_views_bytes(kKey, some_views());
  for (std::size_t n = 0; n < good.size(); ++n) {
    EXPECT_FALSE(parse_clutter_views(good.substr(0, n), kKey, 2)) << n << " bytes";
  }
  EXPECT_FALSE(parse_clutter_views(good + '\0', kKey, 2));
}

core::Json recording() { return core::Json{{"seed", 1}, {"pushes", 2}}; }

core::Json manifest() {
  return core::Json{
      {"format", kClutterCacheFormat},
      {"format_version", kClutterCacheVersion},
      {"recording", recording()},
      {"pushes", core::Json::array({core::Json{{"index", 0},
                                               {"outcome", "pushed"},
                                               {"episode", "push_00/episode"},
                                               {"moved_intended", true},
                                               {"only_intended", false},
                                               {"replaced", 1},
                                               {"attempts", 3},
                                               {"failed", {"not-planned", "off-table"}}},
                                    core::Json{{"index", 1},
                                               {"outcome", "off-table"},
                                               {"episode", ""},
                                               {"moved_intended", false},
                                               {"only_intended", false}}})}};
}

TEST(ClutterCache, ManifestPushesAsRecorded) {
  EXPECT_EQ(match_clutter_manifest(manifest(), recording()), ClutterManifestMatch::kYes);
  const auto p = clutter_manifest_pushes(manifest(), "m.json", 4, "book", 1, "seed_4/book_t2");
  ASSERT_EQ(p.size(), 2U);
  EXPECT_EQ(p[0].seed, 4U);
  EXPECT_EQ(p[0].object, "book");
  EXPECT_EQ(p[0].trial, 1);
  EXPECT_EQ(p[0].index, 0);
  EXPECT_EQ(p[0].outcome, "pushed");
  EXPECT_TRUE(p[0].moved_intended);
  EXPECT_FALSE(p[0].only_intended);
  EXPECT_EQ(p[0].replaced, 1);
  EXPECT_EQ(p[0].attempts, 3);
  EXPECT_EQ(p[0].failed, (std::vector<std::string>{"not-planned", "off-table"}));
  EXPECT_EQ(p[0].episode, "seed_4/book_t2/push_00/episode");
  EXPECT_EQ(p[1].replaced, 0);  // the session-21 harness's manifests have no replaced,
  EXPECT_EQ(p[1].attempts, 1);  // attempts or failed
  EXPECT_TRUE(p[1].failed.empty());
  EXPECT_TRUE(p[1].episode.empty());
}

TEST(ClutterCache, ManifestOfAnotherFormatOrOptionsIsToldApartWithoutThrowing) {
  // Each of these threw nlohmann's type_error (not proprio::Error) from Json::value.
  EXPECT_EQ(match_clutter_manifest(core::Json::array(), recording()),
            ClutterManifestMatch::kOtherFormat);
  EXPECT_EQ(match_clutter_manifest(core::Json("text"), recording()),
            ClutterManifestMatch::kOtherFormat);
  core::Json m = manifest();
  m["format_version"] = "1";
  EXPECT_EQ(match_clutter_manifest(m, recording()), ClutterManifestMatch::kOtherFormat);
  m = manifest();
  m["format"] = 5;
  EXPECT_EQ(match_clutter_manifest(m, recording()), ClutterManifestMatch::kOtherFormat);
  m = manifest();
  m["format_version"] = 1.0;
  EXPECT_EQ(match_clutter_manifest(m, recording()), ClutterManifestMatch::kOtherFormat);
  m = manifest();
  m.erase("recording");
  EXPECT_EQ(match_clutter_manifest(m, recording()), ClutterManifestMatch::kOtherOptions);
  m = manifest();
  m["recording"]["seed"] = 2;
  EXPECT_EQ(match_clutter_manifest(m, recording()), ClutterManifestMatch::kOtherOptions);
}

TEST(ClutterCache, BadManifestPushesAreOneErrorNamingTheFileAndPush) {
  const auto error = [](auto change) {
    core::Json m = manifest();
    change(m);
    return test::error_of(
        [&] { (void)clutter_manifest_pushes(m, "cache.json", 1, "cd", 0, "seed_1/cd_t1"); });
  };
  // No "pushes": const operator[] on a missing key was undefined behaviour.
  EXPECT_NE(error([](core::Json& m) { m.erase("pushes"); }).find("cache.json"), std::string::npos);
  // An object for the array was walked as its values.
  EXPECT_NE(error([](core::Json& m) {
              m["pushes"] = core::Json{{"a", 1}};
            }).find("pushes"),
            std::string::npos);
  EXPECT_NE(error([](core::Json& m) { m["pushes"][0] = 3; }).find("push 0"), std::string::npos);
  // Missing members and wrong types threw nlohmann's exceptions.
  EXPECT_NE(error([](core::Json& m) { m["pushes"][1].erase("index"); }).find("push 1"),
            std::string::npos);
  EXPECT_NE(
      error([](core::Json& m) { m["pushes"][0]["moved_intended"] = "yes"; }).find("moved_intended"),
      std::string::npos);
  EXPECT_NE(error([](core::Json& m) { m["pushes"][0]["outcome"] = 1; }).find("outcome"),
            std::string::npos);
  // A float index was rounded toward zero; 1e20 overflowed int (undefined behaviour).
  EXPECT_NE(error([](core::Json& m) { m["pushes"][0]["index"] = 2.5; }).find("index"),
            std::string::npos);
  EXPECT_NE(error([](core::Json& m) { m["pushes"][0]["index"] = 1e20; }).find("index"),
            std::string::npos);
  EXPECT_NE(error([](core::Json& m) { m["pushes"][0]["replaced"] = -1; }).find("replaced"),
            std::string::npos);
  EXPECT_NE(error([](core::Json& m) { m["pushes"][0]["attempts"] = 0; }).find("attempts"),
            std::string::npos);
  EXPECT_NE(error([](core::Json& m) {
              m["pushes"][0]["failed"] = {1, 2};
            }).find("failed"),
            std::string::npos);
  // An episode outside the trial's directory was read from wherever it pointed.
  EXPECT_NE(error([](core::Json& m) {
              m["pushes"][0]["episode"] = "../../../elsewhere";
            }).find("not inside"),
            std::string::npos);
  EXPECT_NE(
      error([](core::Json& m) { m["pushes"][0]["episode"] = "/abs/episode"; }).find("not inside"),
      std::string::npos);
  EXPECT_NE(error([](core::Json& m) {
              m["pushes"] = core::Json::array();
              for (std::size_t i = 0; i <= kClutterManifestMaxPushes; ++i) m["pushes"].push_back(0);
            }).find("pushes"),
            std::string::npos);
  EXPECT_NE(error([](core::Json& m) { m = core::Json::array(); }).find("object"),
            std::string::npos);
}

}  // namespace
}  // namespace proprio::loop
