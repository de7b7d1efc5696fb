// Import of a real recording: arm-log resampling (known answers) and a real video from opencv-doc.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <cstdio>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <opencv2/videoio.hpp>

#include "episode_test_support.hpp"
#include "proprio/core/error.hpp"
#include "proprio/episode/check.hpp"
#include "proprio/episode/episode.hpp"
#include "proprio/episode/import.hpp"

namespace proprio::episode {
namespace {
using namespace testing;

const fs::path kVideo = fs::path(PROPRIO_OPENCV_SAMPLES) / "vtest.avi";  // 768x576, 10 fps

ArmLog log_of(std::vector<double> t, std::vector<bool> touching) {
  ArmLog log;
  log.t = std::move(t);
  log.touching = std::move(touching);
  log.joint_count = 1;
  log.has_touching = true;
  for (double x : log.t) {
    log.ee.emplace_back(x, 2 * x, 0.5);
    log.q.push_back(Eigen::VectorXd::Constant(1, -x));
  }
  return log;
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

TEST(SampleArmLog, InterpolatesLinearly) {
  const ArmLog log = log_of({0.0, 1.0, 3.0}, {false, false, false});
  const ArmSample s = sample_arm_log(log, 2.0, 0.1);  // halfway between samples 1 and 2
  EXPECT_NEAR(s.ee.x(), 2.0, 1e-12);
  EXPECT_NEAR(s.ee.y(), 4.0, 1e-12);
  EXPECT_NEAR(s.q[0], -2.0, 1e-12);
  EXPECT_EQ(s.t, 2.0);
  EXPECT_EQ(sample_arm_log(log, 0.0, 0.1).ee.x(), 0.0);  // both ends exactly
  EXPECT_EQ(sample_arm_log(log, 3.0, 0.1).ee.x(), 3.0);
  EXPECT_NEAR(sample_arm_log(log, 0.25, 0.1).q[0], -0.25, 1e-12);
  EXPECT_FALSE(s.ee_image);
}

TEST(SampleArmLog, TouchingWhenAnySampleInTheFrameIntervalTouches) {
  // A 100 Hz log with one touching sample at t = 1.03; frames every 0.1 s.
  std::vector<double> t;
  std::vector<bool> touching;
  for (int k = 0; k <= 200; ++k) {
    t.push_back(k * 0.01);
    touching.push_back(k == 103);
  }
  const ArmLog log = log_of(t, touching);
  EXPECT_FALSE(sample_arm_log(log, 1.0, 0.1).touching);
  EXPECT_TRUE(sample_arm_log(log, 1.1, 0.1).touching);  // interval (1.0, 1.1] holds 1.03
  EXPECT_FALSE(sample_arm_log(log, 1.2, 0.1).touching);
  EXPECT_TRUE(sample_arm_log(log, 1.03, 0.1).touching);    // a sample at the frame time counts
  EXPECT_FALSE(sample_arm_log(log, 1.135, 0.1).touching);  // (1.035, 1.135] excludes it
}

TEST(SampleArmLog, ASlowLogHoldsItsLastSample) {
  // 1 Hz log, 10 Hz video: frames between samples take the last sample before them.
  const ArmLog log = log_of({0.0, 1.0, 2.0}, {false, true, false});
  EXPECT_FALSE(sample_arm_log(log, 0.9, 0.1).touching);
  EXPECT_TRUE(sample_arm_log(log, 1.0, 0.1).touching);
  EXPECT_TRUE(sample_arm_log(log, 1.5, 0.1).touching);
  EXPECT_FALSE(sample_arm_log(log, 2.0, 0.1).touching);
}

class ImportTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(kVideo)) GTEST_SKIP() << "opencv-doc sample " << kVideo << " not installed";
    camera_.K << 700.0, 0.0, 383.5, 0.0, 700.0, 287.5, 0.0, 0.0, 1.0;
    camera_.R << 1, 0, 0, 0, -1, 0, 0, 0, -1;
    camera_.t = Eigen::Vector3d(0.0, 0.0, 1.2);
    camera_.dist = {-0.2, 0.05, 0.0, 0.0, 0.0};
    calib_ = tmp_.path() / "calib.yml";
    geometry::write_calib(calib_, camera_);
    log_ = tmp_.path() / "arm_log.csv";
    write_log(0.25, 140);
  }

  /// A 50 Hz log from `start` (s), `n` samples, the end-effector on a circle 0.1 m above the
  /// table, touching from t = 1.45 s on. Extra column `gripper` is ignored by the importer.
  void write_log(double start, int n) {
    std::string csv = "t,q1,q2,ee_x,ee_y,ee_z,touching,gripper\n";
    char buf[256];
    for (int k = 0; k < n; ++k) {
      const double t = start + 0.02 * k;
      std::snprintf(buf, sizeof buf, "%.2f,%.4f,%.4f,%.6f,%.6f,0.1,%d,0\n", t, 0.1 * t, -0.2 * t,
                    0.1 * std::cos(t), 0.1 * std::sin(t), t >= 1.449 ? 1 : 0);
      csv += buf;
    }
    core::write_file_atomic(log_, csv);
  }

  ImportResult run(ImportOptions options = {}) {
    if (!options.max_frames) options.max_frames = 20;
    return import_recording(kVideo, log_, calib_, out_, options,
                            core::Provenance::current({"import_test"}));
  }

  TempDir tmp_;
  geometry::Camera camera_;
  fs::path calib_;
  fs::path log_;
  fs::path out_ = tmp_.path() / "ep";
};

TEST_F(ImportTest, RealVideoBecomesAValidEpisode) {
  const ImportResult r = run();
  EXPECT_EQ(r.message, out_.string() + ": 20 frames imported");
  EXPECT_EQ(r.brief(), "episode: " + out_.string() + "\n" + format_import_summary(r.summary));
  EXPECT_EQ(r.brief().substr(0, r.brief().find('\n')), "episode: " + out_.string());
  const ImportSummary s = r.summary;
  // Frames at i / 10 s; the log starts at 0.25 s: frames 0-2 are dropped, frame 3 is the first.
  EXPECT_EQ(s.dropped_before_log, 3);
  EXPECT_EQ(s.first_video_frame, 3);
  EXPECT_EQ(s.frames_written, 20);
  EXPECT_EQ(s.video_frames_read, 23);
  EXPECT_EQ(s.stop_reason, "max_frames reached");
  EXPECT_EQ(s.fps, 10.0);
  EXPECT_TRUE(s.undistorted);
  EXPECT_EQ(s.log_samples, 140);
  // Touching from 1.45 s: frame at 1.5 s (video 15, episode 12) is the first whose interval
  // (1.4, 1.5] holds a touching sample.
  EXPECT_EQ(s.first_touch_frame, 12);
  EXPECT_EQ(s.touching_frames, 8);

  EXPECT_TRUE(check_episode(out_).empty()) << joined(check_episode(out_));
  const Episode ep = read_episode(out_);
  EXPECT_EQ(ep.frame_count(), 20);
  EXPECT_EQ(ep.info().width, 768);
  EXPECT_EQ(ep.info().height, 576);
  EXPECT_EQ(ep.info().provenance.source, Source::kReal);
  EXPECT_EQ(ep.info().joint_count, 2);
  EXPECT_FALSE(ep.info().target);
  EXPECT_EQ(ep.first_touch_frame(), 12);
  EXPECT_FALSE(ep.camera().has_distortion());  // removed from the frames, so not in calib.yml
  EXPECT_LT((ep.camera().K - camera_.K).norm(), 1e-12);
  EXPECT_NEAR(ep.arm()[0].t, 0.3, 1e-12);
  EXPECT_NEAR(ep.arm()[19].t, 2.2, 1e-12);

  // Frame 0 is video frame 3 with the lens distortion removed by cv::undistort.
  cv::VideoCapture cap(kVideo.string());
  cv::Mat raw;
  for (int i = 0; i <= 3; ++i) cap.read(raw);
  cv::Mat K, expect;
  cv::eigen2cv(camera_.K, K);
  cv::undistort(raw, expect, K, camera_.dist);
  cv::Mat diff;
  cv::absdiff(ep.frame(0), expect, diff);
  EXPECT_LT(cv::mean(diff)[0], 0.5);
  EXPECT_GT(cv::norm(ep.frame(0), raw, cv::NORM_L1) / raw.total(), 5.0);  // it did change

  // ee_u, ee_v are stored and are the projection through P of the interpolated position.
  for (int i : {0, 7, 19}) {
    const ArmSample& a = ep.arm()[static_cast<size_t>(i)];
    ASSERT_TRUE(a.ee_image);
    EXPECT_LT((*a.ee_image - camera_.project(a.ee)).norm(), 1e-9);
    const double t = a.t;
    EXPECT_NEAR(a.ee.x(), 0.1 * std::cos(t), 2e-5);  // interpolation of a smooth curve
    EXPECT_NEAR(a.q[1], -0.2 * t, 1e-4);
  }
}

TEST_F(ImportTest, StopsAtTheEndOfTheLogAndHonoursTheTimeOffset) {
  write_log(0.25, 40);  // 0.25 .. 1.03 s
  ImportOptions options;
  options.time_offset = 0.5;  // video frame i at 0.5 + i / 10 s
  options.max_frames = 100;
  const ImportSummary s = run(options).summary;
  EXPECT_EQ(s.dropped_before_log, 0);
  EXPECT_EQ(s.frames_written, 6);  // 0.5, 0.6, ..., 1.0
  EXPECT_EQ(s.stop_reason, "end of arm log");
  const Episode ep = read_episode(out_);
  EXPECT_NEAR(ep.arm().back().t, 1.0, 1e-12);
}

TEST_F(ImportTest, ExplicitFpsAndVideoStorage) {
  ImportOptions options;
  options.fps = 25.0;
  options.max_frames = 10;
  options.storage = FrameStorage::kVideo;
  options.scenario = "push mug";
  const ImportSummary s = run(options).summary;
  EXPECT_EQ(s.fps, 25.0);
  EXPECT_EQ(s.dropped_before_log, 7);  // 0, 0.04, ..., 0.24 < 0.25
  EXPECT_TRUE(check_episode(out_).empty()) << joined(check_episode(out_));
  const Episode ep = read_episode(out_);
  EXPECT_EQ(ep.info().storage, FrameStorage::kVideo);
  EXPECT_EQ(ep.info().provenance.scenario, "push mug");
  EXPECT_NEAR(ep.arm()[1].t - ep.arm()[0].t, 0.04, 1e-12);
  EXPECT_EQ(ep.frame(9).size(), cv::Size(768, 576));
}

TEST_F(ImportTest, NoOverlapIsAnErrorAndLeavesNothing) {
  ImportOptions options;
  options.time_offset = 500.0;
  options.max_frames = 5;
  const std::string e = error_of([&] { run(options); });
  EXPECT_NE(e.find(kVideo.string() + ": no frame falls within the arm log's time span"),
            std::string::npos)
      << e;
  EXPECT_FALSE(fs::exists(out_));
}

TEST_F(ImportTest, CalibrationForAnotherImageSize) {
  camera_.width = 640;
  camera_.height = 480;
  geometry::write_calib(calib_, camera_);
  EXPECT_EQ(error_of([&] { run(); }),
            calib_.string() + ": is for 640x480 images, the video's are 768x576");
  EXPECT_FALSE(fs::exists(out_));
}

TEST_F(ImportTest, MissingOrUnreadableVideo) {
  EXPECT_EQ(error_of([&] {
              import_recording(tmp_.path() / "none.avi", log_, calib_, out_, {},
                               core::Provenance::current({"t"}));
            }),
            (tmp_.path() / "none.avi").string() + ": no such video file");
  const fs::path junk = tmp_.path() / "junk.avi";
  core::write_file_atomic(junk, "not a video");
  EXPECT_NE(error_of([&] {
              import_recording(junk, log_, calib_, out_, {}, core::Provenance::current({"t"}));
            }).find(junk.string() + ": "),
            std::string::npos);
  EXPECT_FALSE(fs::exists(out_));
}

TEST_F(ImportTest, BadArmLogs) {
  core::write_file_atomic(log_, "t,ee_x,ee_y\n0,1,2\n");
  EXPECT_EQ(error_of([&] { run(); }), log_.string() + ":1: header lacks column 'ee_z'");
  core::write_file_atomic(log_, "t,ee_x,ee_y,ee_z\n0,1,2,3\n0.5,1,2,3\n0.5,1,2,3\n");
  EXPECT_EQ(error_of([&] { run(); }),
            log_.string() +
                ":4: t = 0.500000 is not after the previous sample's 0.500000 (time "
                "must increase)");
  core::write_file_atomic(log_, "t,ee_x,ee_y,ee_z,touching\n0,1,2,3,0\n1,1,2,3,0.5\n");
  EXPECT_EQ(error_of([&] { run(); }), log_.string() + ":3: touching is 0.500000, expected 0 or 1");
  core::write_file_atomic(log_, "t,ee_x,ee_y,ee_z\n0,1,nan,3\n");
  EXPECT_EQ(error_of([&] { run(); }), log_.string() + ":2: column 'ee_y': 'nan' is not finite");
  core::write_file_atomic(log_, "t,ee_x,ee_y,ee_z\n");
  EXPECT_EQ(error_of([&] { run(); }), log_.string() + ": no data rows");
  EXPECT_FALSE(fs::exists(out_));
}

TEST_F(ImportTest, ReadArmLogFindsJointsAndTouching) {
  const ArmLog log = read_arm_log(log_);
  EXPECT_EQ(log.joint_count, 2);
  EXPECT_TRUE(log.has_touching);
  EXPECT_EQ(log.t.size(), 140u);
  EXPECT_NEAR(log.q[10][1], -0.2 * 0.45, 1e-4);
}

TEST(ImportOptions, Validate) {
  ImportOptions o;
  o.fps = -2;
  EXPECT_THROW(o.validate(), Error);
  o.fps.reset();
  o.max_frames = 0;
  EXPECT_THROW(o.validate(), Error);
  o.max_frames = 1;
  o.time_offset = std::nan("");
  EXPECT_THROW(o.validate(), Error);
}

}  // namespace
}  // namespace proprio::episode
