// The Fitzpatrick & Metta baseline on synthetic pushes: the object is found at the touch frame,
// the arm is left out, moving backgrounds hurt it, and bad input gives a clear result.
#include "proprio/segmentation/fm_baseline.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgcodecs.hpp>

#include "baseline_test_episode.hpp"
#include "proprio/core/error.hpp"
#include "proprio/episode/episode.hpp"

namespace proprio::segmentation {
namespace {
using namespace testing;

double jaccard(const cv::Mat1b& a, const cv::Mat1b& b) {
  const double inter = cv::countNonZero(a & b);
  const double uni = cv::countNonZero(a | b);
  return uni == 0 ? 1.0 : inter / uni;
}

cv::Mat1b target_mask(const episode::Episode& ep, int frame) { return ep.mask(frame) == 1; }

TEST(FmBaseline, DifferenceMaskThresholdsEveryChannel) {
  cv::Mat3b a(2, 2, cv::Vec3b(10, 10, 10)), b = a.clone();
  b(0, 0) = cv::Vec3b(10, 16, 10);  // one channel by 6
  b(1, 1) = cv::Vec3b(15, 15, 15);  // every channel by 5: not above 5
  const cv::Mat1b m = difference_mask(a, b, 5);
  EXPECT_EQ(m(0, 0), 255);
  EXPECT_EQ(m(1, 1), 0);
  EXPECT_EQ(cv::countNonZero(m), 1);
  EXPECT_THROW(difference_mask(a, cv::Mat3b(3, 2), 5), Error);
}

TEST(FmBaseline, SegmentsThePushedObjectAtTheTouchFrame) {
  ScratchDir tmp;
  PushSpec spec;
  const auto ep = episode::read_episode(write_push_episode(tmp.path() / "ep", spec));
  const FmResult r = segment_fm(ep, FmOptions{});
  ASSERT_TRUE(r.summary.touched) << r.summary.message;
  EXPECT_EQ(r.scored_frame, push_first_touch(spec));
  EXPECT_EQ(r.first_touch_frame, push_first_touch(spec));
  const cv::Mat1b truth = target_mask(ep, r.scored_frame);
  EXPECT_GT(jaccard(r.mask, truth), 0.6) << r.summary.message;
  // The arm is a hard background seed: none of it is object.
  EXPECT_EQ(cv::countNonZero(r.mask & (ep.mask(r.scored_frame) == 2) & r.arm), 0);
  EXPECT_GT(r.summary.arm_pixels, 0);
  EXPECT_GT(r.summary.evidence_pixels, 0);
  EXPECT_GE(r.summary.components, 1);
  EXPECT_GE(r.summary.ee_distance, 0.0);
  EXPECT_EQ(r.mask.size(), truth.size());
}

TEST(FmBaseline, FramesDecodedOnceGiveTheSameResult) {
  ScratchDir tmp;
  const auto ep = episode::read_episode(write_push_episode(tmp.path() / "ep", PushSpec{}));
  FmOptions o;
  const FmFrames frames = load_fm_frames(ep, o);
  const FmResult a = segment_fm(frames, o);
  const FmResult b = segment_fm(ep, o);
  EXPECT_EQ(cv::countNonZero(a.mask != b.mask), 0);
  // A huge threshold sees no motion: no object.
  o.difference_threshold = 250;
  EXPECT_EQ(cv::countNonZero(segment_fm(frames, o).mask), 0);
}

TEST(FmBaseline, DifferencingFindsTheTouchNearTheRobotsFrame) {
  ScratchDir tmp;
  PushSpec spec;
  const auto ep = episode::read_episode(write_push_episode(tmp.path() / "ep", spec));
  FmOptions o;
  o.touch = TouchSource::kDifferencing;
  const FmResult r = segment_fm(ep, o);
  ASSERT_TRUE(r.summary.touched) << r.summary.message;
  EXPECT_LE(std::abs(r.scored_frame - push_first_touch(spec)), 1);
  EXPECT_EQ(r.summary.touch_source, TouchSource::kDifferencing);
}

TEST(FmBaseline, MovingBackgroundHurtsIt) {
  ScratchDir tmp;
  PushSpec still, moving;
  moving.moving_background = true;
  const auto a = episode::read_episode(write_push_episode(tmp.path() / "a", still));
  const auto b = episode::read_episode(write_push_episode(tmp.path() / "b", moving));
  const FmResult ra = segment_fm(a, FmOptions{});
  const FmResult rb = segment_fm(b, FmOptions{});
  EXPECT_GT(rb.summary.evidence_pixels, ra.summary.evidence_pixels);
}

TEST(FmBaseline, NoTouchIsAResultNotAnError) {
  ScratchDir tmp;
  PushSpec spec;
  spec.touch = false;
  const auto ep = episode::read_episode(write_push_episode(tmp.path() / "ep", spec));
  const FmResult r = segment_fm(ep, FmOptions{});
  EXPECT_FALSE(r.summary.touched);
  EXPECT_EQ(r.scored_frame, -1);
  EXPECT_TRUE(r.mask.empty());
  EXPECT_NE(r.summary.message.find("no touch"), std::string::npos) << r.summary.message;
}

TEST(FmBaseline, TouchTooEarlyForAnArmModel) {
  ScratchDir tmp;
  PushSpec spec;
  spec.arm_start = 76;  // touching from frame 1
  const auto ep = episode::read_episode(write_push_episode(tmp.path() / "ep", spec));
  ASSERT_LT(push_first_touch(spec), 2);
  const FmResult r = segment_fm(ep, FmOptions{});
  EXPECT_EQ(r.scored_frame, -1);
  EXPECT_NE(r.summary.message.find("before frame 2"), std::string::npos) << r.summary.message;
}

TEST(FmBaseline, FramesOfDifferentSizesAreAnError) {
  ScratchDir tmp;
  PushSpec spec;
  const auto dir = write_push_episode(tmp.path() / "ep", spec);
  // Replace the frame before the touch with a smaller image.
  const int t = push_first_touch(spec);
  cv::imwrite(episode::image_path(dir, "frames", t - 1).string(), cv::Mat3b(40, 30));
  try {
    const auto ep = episode::read_episode(dir);
    (void)segment_fm(ep, FmOptions{});
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(std::to_string(t - 1)), std::string::npos) << e.what();
  }
}

TEST(FmBaseline, OptionsAreChecked) {
  FmOptions o;
  o.difference_threshold = -1;
  EXPECT_THROW(o.validate(), Error);
  o = {};
  o.difference_threshold = std::nan("");
  EXPECT_THROW(o.validate(), Error);
  o = {};
  o.still_weight = -1;
  EXPECT_THROW(o.validate(), Error);
  o = {};
  o.graph_cut.connectivity = 5;
  EXPECT_THROW(o.validate(), Error);
}

}  // namespace
}  // namespace proprio::segmentation
