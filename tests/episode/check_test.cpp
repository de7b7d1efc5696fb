// Validation: every kind of bad episode is found and named, by check_episode (all problems) and
// read_episode (the first).
#include <gtest/gtest.h>

#include <fstream>
#include <functional>
#include <opencv2/imgcodecs.hpp>

#include "episode_test_support.hpp"
#include "proprio/core/error.hpp"
#include "proprio/core/json_io.hpp"
#include "proprio/episode/check.hpp"
#include "proprio/episode/episode.hpp"

namespace proprio::episode {
namespace {
using namespace testing;

class CheckTest : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = write_synthetic(tmp_.path() / "ep", spec_); }

  /// check_episode's messages, joined.
  std::string problems(const CheckOptions& options = {}) {
    return joined(check_episode(dir_, options));
  }
  /// read_episode's error, or "no error".
  std::string read_error() {
    try {
      (void)read_episode(dir_);
    } catch (const Error& e) {
      return e.what();
    }
    return "no error";
  }
  std::string file(const std::string& name) { return (dir_ / name).string(); }

  void edit_json(const std::string& name, const std::function<void(core::Json&)>& edit) {
    core::Json j = core::read_json(dir_ / name);
    edit(j);
    core::write_json_atomic(dir_ / name, j);
  }
  /// Replaces line `line` (1-based, counting the header) of arm.csv.
  void replace_arm_line(int line, const std::string& text) {
    std::ifstream in(dir_ / "arm.csv");
    std::string all, l;
    for (int n = 1; std::getline(in, l); ++n) all += (n == line ? text : l) + "\n";
    core::write_file_atomic(dir_ / "arm.csv", all);
  }
  std::string arm_line(int line) {
    std::ifstream in(dir_ / "arm.csv");
    std::string l;
    for (int n = 1; n <= line; ++n) std::getline(in, l);
    return l;
  }

  TempDir tmp_;
  SyntheticSpec spec_;
  fs::path dir_;
};

#define EXPECT_HAS(haystack, needle)                                                              \
  do {                                                                                            \
    const std::string& h_ = (haystack);                                                           \
    EXPECT_NE(h_.find(needle), std::string::npos) << "expected '" << (needle) << "' in:\n" << h_; \
  } while (0)

TEST_F(CheckTest, ValidEpisodeHasNoProblems) {
  EXPECT_EQ(problems(), "");
  EXPECT_EQ(read_error(), "no error");
}

TEST_F(CheckTest, RunCheckGivesTheVerdictAsMessageAndTheProblemsAsBrief) {
  const core::Provenance provenance = core::Provenance::current({"check_test"});
  const CheckResult valid = run_episode_check(dir_, {}, provenance);
  EXPECT_TRUE(valid.valid());
  EXPECT_EQ(valid.message, dir_.string() + ": valid episode");
  EXPECT_EQ(valid.brief(), valid.message + "\n");

  fs::remove(dir_ / "calib.yml");
  const CheckResult one = run_episode_check(dir_, {}, provenance);
  EXPECT_EQ(one.message, dir_.string() + ": not a valid episode (1 problem)");
  EXPECT_EQ(one.brief(), one.problems.at(0).message + "\n");

  fs::remove(image_path(dir_, "masks", 4));
  const CheckResult two = run_episode_check(dir_, {}, provenance);
  EXPECT_EQ(two.message, dir_.string() + ": not a valid episode (2 problems)");
  EXPECT_EQ(two.brief(), two.problems.at(0).message + "\n" + two.problems.at(1).message + "\n");
  EXPECT_EQ(two.document["valid"], false);
}

TEST_F(CheckTest, TruncatedPng) {
  const fs::path f = image_path(dir_, "frames", 2);
  fs::resize_file(f, fs::file_size(f) / 2);
  const std::string expect =
      f.string() + ": truncated PNG (the file does not end with an IEND chunk)";
  EXPECT_HAS(problems(), expect);
  EXPECT_EQ(read_error(), expect);
}

TEST_F(CheckTest, PngCutInsideItsHeader) {
  const fs::path f = image_path(dir_, "frames", 0);
  fs::resize_file(f, 20);
  EXPECT_EQ(read_error(), f.string() + ": truncated or corrupt PNG (no valid IHDR chunk)");
}

TEST_F(CheckTest, NotAPng) {
  core::write_file_atomic(image_path(dir_, "frames", 1), "GIF89a, not a PNG at all");
  EXPECT_EQ(read_error(), image_path(dir_, "frames", 1).string() +
                              ": not an image proprio reads (PNG, JPEG, BMP or PNM)");
}

TEST_F(CheckTest, CorruptPngDataIsFoundByDecoding) {
  // Header and trailer intact, image data garbled: only decoding finds it.
  const fs::path f = image_path(dir_, "frames", 3);
  std::string bytes = core::read_file(f);
  for (size_t k = 60; k < bytes.size() - 40; k += 3) bytes[k] = static_cast<char>(bytes[k] ^ 0x5A);
  core::write_file_atomic(f, bytes);
  EXPECT_EQ(problems({.decode_images = false}), "");
  EXPECT_EQ(read_error(), "no error");
  EXPECT_HAS(problems(), f.string() + ": cannot be decoded (corrupt PNG data)");
  const Episode ep = read_episode(dir_);
  EXPECT_THROW((void)ep.frame(3), Error);
}

TEST_F(CheckTest, FrameOfTheWrongSize) {
  cv::imwrite(image_path(dir_, "frames", 4).string(), cv::Mat(20, 30, CV_8UC3, cv::Scalar(1)));
  const std::string expect = image_path(dir_, "frames", 4).string() +
                             ": is 30x20, expected 64x48 (episode.json's image size)";
  EXPECT_HAS(problems(), expect);
  EXPECT_EQ(read_error(), expect);
}

TEST_F(CheckTest, ArmCsvWithAWrongColumnCount) {
  replace_arm_line(3, "1,0.2,0.1,0.2,0.3");
  const std::string expect = file("arm.csv") +
                             ":3: has 5 columns, expected 10 "
                             "(frame,t,q1,q2,ee_x,ee_y,ee_z,ee_u,ee_v,touching)";
  EXPECT_HAS(problems(), expect);
  EXPECT_EQ(read_error(), expect);
}

TEST_F(CheckTest, ArmCsvWithTheWrongHeader) {
  replace_arm_line(1, "frame,t,q1,ee_x,ee_y,ee_z,ee_u,ee_v,touching");
  EXPECT_EQ(read_error(), file("arm.csv") +
                              ":1: header is 'frame,t,q1,ee_x,ee_y,ee_z,ee_u,ee_v,touching', "
                              "expected 'frame,t,q1,q2,ee_x,ee_y,ee_z,ee_u,ee_v,touching' "
                              "(episode.json says 2 joints)");
}

TEST_F(CheckTest, ArmCsvWithNaNAndInf) {
  std::string l = arm_line(2);
  replace_arm_line(2, l.replace(l.find(",0.05,"), 6, ",nan,"));
  l = arm_line(4);
  replace_arm_line(4, "2,inf" + l.substr(l.find(',', 2)));
  const std::string p = problems();
  EXPECT_HAS(p, file("arm.csv") + ":2: column 'ee_y': 'nan' is not finite");
  EXPECT_HAS(p, file("arm.csv") + ":4: column 't': 'inf' is not finite");
  EXPECT_EQ(read_error(), file("arm.csv") + ":2: column 'ee_y': 'nan' is not finite");
}

TEST_F(CheckTest, ArmCsvWithTextInANumberColumn) {
  std::string l = arm_line(3);
  replace_arm_line(3, l.replace(l.find(",0.05,"), 6, ",abc,"));
  EXPECT_EQ(read_error(), file("arm.csv") + ":3: column 'ee_y': 'abc' is not a number");
}

TEST_F(CheckTest, NonMonotonicTime) {
  std::string l = arm_line(4);  // frame 2
  replace_arm_line(4, "2,0.1" + l.substr(l.find(',', 2)));
  EXPECT_HAS(problems(), file("arm.csv") + ":4: t = 0.1 is not after the previous frame's t = " +
                             "0.13333333333333333 (time must increase)");
}

TEST_F(CheckTest, FrameColumnNotZeroToNMinusOne) {
  std::string l = arm_line(3);  // frame 1
  replace_arm_line(3, "7" + l.substr(1));
  EXPECT_HAS(problems(),
             file("arm.csv") + ":3: frame is 7, expected 1 (frames are numbered 0..N-1 in order)");
}

TEST_F(CheckTest, TouchingNotZeroOrOne) {
  std::string l = arm_line(5);
  replace_arm_line(5, l.substr(0, l.size() - 1) + "2");
  EXPECT_HAS(problems(), file("arm.csv") + ":5: touching is 2, expected 0 or 1");
}

TEST_F(CheckTest, OnlyOneOfEeUAndEeV) {
  std::string l = arm_line(2);
  replace_arm_line(2, l.replace(l.find(",,"), 2, ",5.5,"));
  EXPECT_HAS(problems(), file("arm.csv") + ":2: ee_u and ee_v must both be given or both be empty");
}

TEST_F(CheckTest, MissingCalib) {
  fs::remove(dir_ / "calib.yml");
  const std::string expect = file("calib.yml") + ": missing (the episode's camera calibration)";
  EXPECT_HAS(problems(), expect);
  EXPECT_EQ(read_error(), expect);
}

TEST_F(CheckTest, BrokenCalibIsNamedByGeometry) {
  core::write_file_atomic(dir_ / "calib.yml", "%YAML:1.0\n---\nimage_width: 64\n");
  EXPECT_HAS(read_error(), file("calib.yml") + ": missing 'P'");
}

TEST_F(CheckTest, CalibForAnotherImageSize) {
  auto cam = overhead_camera(640, 480);
  cam.width = 640;
  cam.height = 480;
  geometry::write_calib(dir_ / "calib.yml", cam);
  EXPECT_EQ(read_error(),
            file("calib.yml") + ": is for 640x480 images, episode.json's image size is 64x48");
}

TEST_F(CheckTest, MissingEpisodeJson) {
  fs::remove(dir_ / "episode.json");
  EXPECT_EQ(read_error(), file("episode.json") + ": missing (every episode has one)");
}

TEST_F(CheckTest, EpisodeJsonNotJson) {
  core::write_file_atomic(dir_ / "episode.json", "{\n  \"format\": \"proprio.episode\",\n  oops\n");
  EXPECT_HAS(read_error(), file("episode.json") + ":3: invalid JSON");
}

TEST_F(CheckTest, MissingDirectoryAndNotADirectory) {
  EXPECT_EQ(joined(check_episode(tmp_.path() / "nothing")),
            (tmp_.path() / "nothing").string() + ": no such episode directory\n");
  EXPECT_EQ(joined(check_episode(dir_ / "arm.csv")),
            file("arm.csv") + ": is not a directory (an episode is a directory)\n");
}

TEST_F(CheckTest, FrameMissing) {
  fs::remove(image_path(dir_, "frames", 4));
  EXPECT_EQ(read_error(),
            image_path(dir_, "frames", 4).string() + ": missing (episode.json declares 5 frames)");
}

TEST_F(CheckTest, MoreFramesThanDeclared) {
  fs::copy_file(image_path(dir_, "frames", 4), image_path(dir_, "frames", 5));
  fs::copy_file(image_path(dir_, "frames", 4), image_path(dir_, "frames", 9));
  EXPECT_EQ(problems(), file("frames") +
                            ": holds 2 images beyond episode.json's frame_count 5 (the first is "
                            "000005.png)\n");
}

TEST_F(CheckTest, ArmRowsDifferFromFrameCount) {
  edit_json("episode.json", [](core::Json& j) { j["frame_count"] = 4; });
  const std::string p = problems();
  EXPECT_HAS(p, file("arm.csv") + ": has 5 rows, episode.json says frame_count 4");
  EXPECT_HAS(p, file("frames") + ": holds 1 image beyond episode.json's frame_count 4");
  EXPECT_HAS(p, file("masks") + ": holds 1 image beyond");
}

TEST_F(CheckTest, EmptyEpisode) {
  edit_json("episode.json", [](core::Json& j) { j["frame_count"] = 0; });
  core::write_file_atomic(dir_ / "arm.csv", "frame,t,q1,q2,ee_x,ee_y,ee_z,ee_u,ee_v,touching\n");
  const std::string p = problems();
  EXPECT_HAS(p, file("episode.json") +
                    ": frame_count is 0: an empty episode (an episode has at least one frame)");
  EXPECT_HAS(p, file("arm.csv") + ": no data rows (an episode has at least one frame)");
}

TEST_F(CheckTest, AbsurdSizesInEpisodeJson) {
  edit_json("episode.json", [](core::Json& j) {
    j["image"]["width"] = 100000;
    j["image"]["height"] = -3;
    j["fps"] = -1;
    j["frame_count"] = 1000000000000LL;
    j["arm"]["joints"] = 1000;
  });
  const std::string p = problems();
  const std::string f = file("episode.json");
  EXPECT_HAS(p, f + ": 'image.width' is 100000, out of range [1, 16384]");
  EXPECT_HAS(p, f + ": 'image.height' is -3, out of range [1, 16384]");
  EXPECT_HAS(p, f + ": 'fps' is -1, expected a number in (0.0, 10000.0]");
  EXPECT_HAS(p, f + ": 'frame_count' is 1000000000000, out of range [1, 10000000]");
  EXPECT_HAS(p, f + ": 'arm.joints' is 1000, out of range [0, 64]");
  EXPECT_EQ(read_error(), f + ": 'frame_count' is 1000000000000, out of range [1, 10000000]");
}

TEST_F(CheckTest, WrongTypesInEpisodeJson) {
  edit_json("episode.json", [](core::Json& j) {
    j["fps"] = "thirty";
    j["masks"] = 1;
    j.erase("target");
    j["frames"]["storage"] = "gif";
  });
  const std::string p = problems();
  const std::string f = file("episode.json");
  EXPECT_HAS(p, f + ": 'fps' is \"thirty\", expected a number");
  EXPECT_HAS(p, f + ": 'masks' is 1, expected true or false");
  EXPECT_HAS(p, f + ": missing key 'target'");
  EXPECT_HAS(p, f + ": 'frames.storage' is 'gif', expected 'png' or 'video'");
}

TEST_F(CheckTest, NewerFormatVersion) {
  edit_json("episode.json", [](core::Json& j) { j["format_version"] = kEpisodeFormatVersion + 1; });
  EXPECT_EQ(read_error(), file("episode.json") +
                              ": format_version 2 is newer than this build of "
                              "proprio supports (1); update proprio");
}

TEST_F(CheckTest, AnotherFormat) {
  edit_json("episode.json", [](core::Json& j) { j["format"] = "proprio.calib.dlt"; });
  EXPECT_EQ(read_error(),
            file("episode.json") + ": format is 'proprio.calib.dlt', expected 'proprio.episode'");
}

TEST_F(CheckTest, VideoFileNameMustStayInTheEpisode) {
  edit_json("episode.json", [](core::Json& j) {
    j["frames"] = {{"storage", "video"}, {"file", "../elsewhere.avi"}};
  });
  EXPECT_HAS(read_error(), "'frames.file' must be a file name in the episode directory");
}

TEST_F(CheckTest, MaskOfTheWrongType) {
  const fs::path f = image_path(dir_, "masks", 1);
  cv::imwrite(f.string(), cv::Mat(48, 64, CV_8UC1, cv::Scalar(1)));
  const std::string expect = f.string() + ": is 8-bit grey PNG, masks must be 16-bit grey";
  EXPECT_HAS(problems(), expect);
  EXPECT_EQ(read_error(), expect);
}

TEST_F(CheckTest, MaskOfTheWrongSize) {
  const fs::path f = image_path(dir_, "masks", 2);
  cv::imwrite(f.string(), cv::Mat(48, 32, CV_16UC1, cv::Scalar(1)));
  EXPECT_EQ(read_error(), f.string() + ": is 32x48, expected 64x48 (episode.json's image size)");
}

TEST_F(CheckTest, MaskIdsThatObjectsJsonLacks) {
  const fs::path f = image_path(dir_, "masks", 2);
  cv::Mat m = synthetic_mask(spec_, 2);
  m.at<std::uint16_t>(0, 63) = 9;
  m.at<std::uint16_t>(1, 63) = 7;
  cv::imwrite(f.string(), m);
  EXPECT_EQ(problems(), f.string() + ": holds object ids 7, 9 that objects.json lacks\n");
  const Episode ep = read_episode(dir_);  // ids are only seen when decoding
  try {
    (void)ep.mask(2);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()),
              f.string() + ": holds object ids 7, 9 that objects.json lacks");
  }
}

TEST_F(CheckTest, MissingObjectsJson) {
  fs::remove(dir_ / "objects.json");
  EXPECT_EQ(read_error(), file("objects.json") +
                              ": missing; episode.json declares masks, whose ids objects.json "
                              "defines");
}

TEST_F(CheckTest, TargetNotInObjects) {
  edit_json("episode.json", [](core::Json& j) { j["target"] = 3; });
  EXPECT_EQ(read_error(),
            file("objects.json") + ": object 3 is episode.json's target but has the role 'object'");
  edit_json("episode.json", [](core::Json& j) { j["target"] = 12; });
  EXPECT_EQ(read_error(), file("objects.json") + ": lacks episode.json's target 12");
}

TEST_F(CheckTest, UndeclaredDirectories) {
  edit_json("episode.json", [](core::Json& j) { j["masks"] = false; });
  EXPECT_EQ(problems(), file("masks") + ": exists, but episode.json says masks: false\n");
}

TEST_F(CheckTest, DeclaredDepthMissing) {
  edit_json("episode.json", [](core::Json& j) { j["depth"] = true; });
  EXPECT_EQ(problems(), file("depth") + ": missing directory (episode.json declares 5 frames)\n");
}

TEST_F(CheckTest, EveryProblemIsListedAndReadNamesTheFirst) {
  fs::remove(dir_ / "calib.yml");
  std::string l = arm_line(3);
  replace_arm_line(3, l.replace(l.find(",0.05,"), 6, ",nan,"));
  l = arm_line(5);
  replace_arm_line(5, l.substr(0, l.size() - 1) + "3");
  const fs::path frame = image_path(dir_, "frames", 1);
  fs::resize_file(frame, 100);
  fs::remove(image_path(dir_, "masks", 4));
  const auto list = check_episode(dir_);
  ASSERT_EQ(list.size(), 5u) << joined(list);
  EXPECT_EQ(list[0].file, dir_ / "calib.yml");
  EXPECT_EQ(list[1].message, file("arm.csv") + ":3: column 'ee_y': 'nan' is not finite");
  EXPECT_EQ(list[2].message, file("arm.csv") + ":5: touching is 3, expected 0 or 1");
  EXPECT_EQ(list[3].file, frame);
  EXPECT_EQ(list[4].file, image_path(dir_, "masks", 4));
  EXPECT_EQ(read_error(), list[0].message);
}

TEST(CheckLimits, ManyProblemsOfOneKindAreCounted) {
  TempDir tmp;
  SyntheticSpec spec;
  spec.frames = 30;
  spec.masks = false;
  const auto dir = write_synthetic(tmp.path() / "ep", spec);
  for (int i = 0; i < 30; ++i) fs::remove(image_path(dir, "frames", i));
  const auto list = check_episode(dir, {.decode_images = true, .max_problems_per_file = 20});
  ASSERT_EQ(list.size(), 21u);
  EXPECT_EQ(list.back().message, (dir / "frames").string() + ": 10 more problems not listed");
}

}  // namespace
}  // namespace proprio::episode
