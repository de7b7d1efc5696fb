// Writer -> reader round trips, lazy frame access, helpers, and the atomicity of the writer.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <atomic>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <thread>

#include "episode_test_support.hpp"
#include "proprio/core/error.hpp"
#include "proprio/episode/check.hpp"
#include "proprio/episode/episode.hpp"
#include "proprio/episode/summary.hpp"

namespace proprio::episode {
namespace {
using namespace testing;

double max_abs_diff(const cv::Mat& a, const cv::Mat& b) {
  cv::Mat d;
  cv::absdiff(a, b, d);
  double mx = 0;
  cv::minMaxLoc(d.reshape(1), nullptr, &mx);
  return mx;
}

TEST(EpisodeRoundTrip, PngEpisodeReadsBackExactly) {
  TempDir tmp;
  SyntheticSpec spec;
  spec.depth = true;
  const auto dir = write_synthetic(tmp.path() / "ep", spec);
  EXPECT_TRUE(check_episode(dir).empty()) << joined(check_episode(dir));

  const Episode ep = read_episode(dir);
  const EpisodeInfo expect = synthetic_info(spec);
  EXPECT_EQ(ep.frame_count(), spec.frames);
  EXPECT_EQ(ep.info().format_version, kEpisodeFormatVersion);
  EXPECT_EQ(ep.info().fps, expect.fps);
  EXPECT_EQ(ep.info().width, spec.width);
  EXPECT_EQ(ep.info().height, spec.height);
  EXPECT_EQ(ep.info().arm_name, "katana");
  EXPECT_EQ(ep.info().joint_count, spec.joints);
  EXPECT_EQ(ep.info().target, 1);
  EXPECT_TRUE(ep.info().has_masks);
  EXPECT_TRUE(ep.info().has_depth);
  EXPECT_FALSE(ep.info().stereo);
  EXPECT_EQ(ep.info().provenance.source, Source::kSimulated);
  EXPECT_EQ(ep.info().provenance.run.seed, 42u);
  EXPECT_EQ(ep.info().provenance.scenario, "push");
  EXPECT_EQ(ep.info().provenance.switches, expect.provenance.switches);
  EXPECT_NEAR(ep.info().duration(), spec.frames / 30.0, 1e-12);

  ASSERT_EQ(ep.objects().size(), 3u);
  EXPECT_EQ(ep.object(1)->name, "mug");
  EXPECT_EQ(ep.object(1)->role, ObjectRole::kTarget);
  EXPECT_EQ(ep.object(2)->role, ObjectRole::kArm);
  EXPECT_EQ(ep.object(9), nullptr);

  const auto cam = overhead_camera(spec.width, spec.height);
  EXPECT_LT((ep.camera().P() - cam.P()).norm(), 1e-12);
  EXPECT_EQ(ep.camera().width, spec.width);
  EXPECT_FALSE(ep.right_camera());

  ASSERT_EQ(ep.arm().size(), static_cast<size_t>(spec.frames));
  for (int i = 0; i < spec.frames; ++i) {
    const ArmSample s = synthetic_sample(spec, i);
    const ArmSample& r = ep.arm()[static_cast<size_t>(i)];
    EXPECT_EQ(r.t, s.t);  // shortest round-trip formatting: exact
    EXPECT_EQ(r.q, s.q);
    EXPECT_EQ(r.ee, s.ee);
    EXPECT_EQ(r.touching, s.touching);
    EXPECT_FALSE(r.ee_image);
    EXPECT_EQ(max_abs_diff(ep.frame(i), synthetic_frame(spec, i)), 0.0) << "frame " << i;
    EXPECT_EQ(max_abs_diff(ep.mask(i), synthetic_mask(spec, i)), 0.0);
    EXPECT_EQ(ep.mask(i).type(), CV_16UC1);
    EXPECT_EQ(max_abs_diff(ep.depth(i), synthetic_depth(spec, i)), 0.0);
  }
  EXPECT_EQ(ep.first_touch_frame(), 3);
  const auto times = ep.frame_times();
  ASSERT_EQ(times.size(), 5u);
  EXPECT_EQ(times[2], 0.1 + 2 / 30.0);
}

TEST(EpisodeRoundTrip, FramesAreDecodedOnDemandInAnyOrder) {
  TempDir tmp;
  SyntheticSpec spec;
  const auto dir = write_synthetic(tmp.path() / "ep", spec);
  const Episode ep = read_episode(dir);
  // Nothing is decoded at read time: removing a frame afterwards only fails that frame.
  fs::remove(image_path(dir, "frames", 1));
  EXPECT_EQ(max_abs_diff(ep.frame(4), synthetic_frame(spec, 4)), 0.0);
  EXPECT_EQ(max_abs_diff(ep.frame(0), synthetic_frame(spec, 0)), 0.0);
  EXPECT_THROW((void)ep.frame(1), Error);
}

TEST(EpisodeRoundTrip, VideoStorageSupportsRandomAccess) {
  TempDir tmp;
  SyntheticSpec spec;
  spec.storage = FrameStorage::kVideo;
  spec.frames = 8;
  spec.width = 96;
  spec.height = 64;
  const auto dir = write_synthetic(tmp.path() / "ep", spec);
  EXPECT_TRUE(fs::exists(dir / "frames.avi"));
  EXPECT_FALSE(fs::exists(dir / "frames"));
  EXPECT_TRUE(check_episode(dir).empty()) << joined(check_episode(dir));
  const Episode ep = read_episode(dir);
  EXPECT_EQ(ep.info().storage, FrameStorage::kVideo);
  EXPECT_EQ(ep.info().video_file, "frames.avi");
  // MJPEG is lossy: compare means; forwards, backwards and repeated reads agree with each other.
  std::vector<cv::Mat> forward;
  for (int i = 0; i < ep.frame_count(); ++i) {
    forward.push_back(ep.frame(i));
    ASSERT_EQ(forward.back().type(), CV_8UC3);
    const double err = cv::norm(forward.back(), synthetic_frame(spec, i), cv::NORM_L1) /
                       static_cast<double>(spec.width * spec.height * 3);
    EXPECT_LT(err, 6.0) << "frame " << i;
  }
  for (int i : {5, 2, 7, 0, 0, 3}) {
    EXPECT_EQ(max_abs_diff(ep.frame(i), forward[static_cast<size_t>(i)]), 0.0) << "frame " << i;
  }
}

TEST(EpisodeRoundTrip, ConcurrentVideoAccessIsSafe) {
  TempDir tmp;
  SyntheticSpec spec;
  spec.storage = FrameStorage::kVideo;
  spec.frames = 6;
  spec.masks = false;
  const auto dir = write_synthetic(tmp.path() / "ep", spec);
  const Episode ep = read_episode(dir);
  std::vector<cv::Mat> expect;
  for (int i = 0; i < ep.frame_count(); ++i) expect.push_back(ep.frame(i));
  std::vector<std::thread> threads;
  std::atomic<int> wrong{0};
  for (int k = 0; k < 3; ++k) {
    threads.emplace_back([&, k] {
      for (int n = 0; n < 6; ++n) {
        const int i = (n * (k + 2)) % ep.frame_count();
        if (max_abs_diff(ep.frame(i), expect[static_cast<size_t>(i)]) != 0.0) ++wrong;
      }
    });
  }
  for (auto& t : threads) t.join();
  EXPECT_EQ(wrong.load(), 0);
}

TEST(EpisodeRoundTrip, StereoEpisodeHasBothCameras) {
  TempDir tmp;
  SyntheticSpec spec;
  spec.stereo = true;
  const auto dir = write_synthetic(tmp.path() / "ep", spec);
  EXPECT_TRUE(fs::exists(dir / "calib_right.yml"));
  EXPECT_TRUE(fs::exists(image_path(dir, "frames_right", 4)));
  const Episode ep = read_episode(dir);
  ASSERT_TRUE(ep.right_camera());
  EXPECT_NEAR(ep.right_camera()->t.x(), -0.1, 1e-12);
  EXPECT_EQ(max_abs_diff(ep.frame_right(2), synthetic_frame(spec, 2, 7)), 0.0);
  EXPECT_TRUE(check_episode(dir).empty()) << joined(check_episode(dir));
}

TEST(EpisodeHelpers, EeImageIsStoredOrProjected) {
  TempDir tmp;
  SyntheticSpec spec;
  const auto dir = write_synthetic(tmp.path() / "projected", spec);
  const Episode ep = read_episode(dir);
  for (int i = 0; i < ep.frame_count(); ++i) {
    const auto x = ep.ee_image(i);
    ASSERT_TRUE(x);
    const Eigen::Vector3d X = ep.arm()[static_cast<size_t>(i)].ee;
    // Known answer for the overhead camera: u = cx + f x / (1 - z), v = cy - f y / (1 - z).
    const double depth = 1.0 - X.z();
    EXPECT_NEAR(x->x(), (spec.width - 1) / 2.0 + 60.0 * X.x() / depth, 1e-9);
    EXPECT_NEAR(x->y(), (spec.height - 1) / 2.0 - 60.0 * X.y() / depth, 1e-9);
  }
  EXPECT_EQ(ep.ee_image_track().size(), static_cast<size_t>(spec.frames));

  spec.store_ee_image = true;
  const Episode stored = read_episode(write_synthetic(tmp.path() / "stored", spec));
  EXPECT_EQ(*stored.ee_image(3), Eigen::Vector2d(13.5, 20.25));
}

TEST(EpisodeHelpers, EeImageFollowsLensDistortionAndHidesPointsBehindTheCamera) {
  TempDir tmp;
  SyntheticSpec spec;
  spec.masks = false;
  const auto dir = write_synthetic(tmp.path() / "ep", spec);
  // Replace the calibration by a distorted one, and put the last sample behind the camera.
  auto cam = overhead_camera(spec.width, spec.height);
  cam.dist = {-0.3, 0.1, 0.001, -0.002, 0.0};
  geometry::write_calib(dir / "calib.yml", cam);
  std::string csv = core::read_file(dir / "arm.csv");
  const auto pos = csv.rfind("\n4,");
  const auto row = csv.substr(pos + 1);
  std::string moved = row;
  moved.replace(moved.find(",0.1,,,"), 7, ",1.5,,,");  // ee_z = 1.5 m: above the camera
  csv.replace(pos + 1, row.size(), moved);
  core::write_file_atomic(dir / "arm.csv", csv);

  const Episode ep = read_episode(dir);
  const Eigen::Vector3d X = ep.arm()[1].ee;
  cv::Mat K, R, t, rvec;
  cv::eigen2cv(cam.K, K);
  cv::eigen2cv(cam.R, R);
  cv::eigen2cv(cam.t, t);
  cv::Rodrigues(R, rvec);
  std::vector<cv::Point2d> expect;
  cv::projectPoints(std::vector<cv::Point3d>{{X.x(), X.y(), X.z()}}, rvec, t, K, cam.dist, expect);
  const auto x = ep.ee_image(1);
  ASSERT_TRUE(x);
  EXPECT_NEAR(x->x(), expect[0].x, 1e-9);
  EXPECT_NEAR(x->y(), expect[0].y, 1e-9);
  EXPECT_GT((*x - cam.project(X)).norm(), 1e-3);  // distortion does move it
  EXPECT_FALSE(ep.ee_image(4));
}

TEST(EpisodeHelpers, NoTouchMeansNoFirstTouchFrame) {
  TempDir tmp;
  SyntheticSpec spec;
  spec.first_touch = -1;
  const Episode ep = read_episode(write_synthetic(tmp.path() / "ep", spec));
  EXPECT_FALSE(ep.first_touch_frame());
}

TEST(EpisodeHelpers, SummaryReportsWhatTheEpisodeHolds) {
  TempDir tmp;
  SyntheticSpec spec;
  spec.depth = true;
  const Episode ep = read_episode(write_synthetic(tmp.path() / "ep", spec));
  const EpisodeSummary s = summarize(ep);
  EXPECT_EQ(s.frames, 5);
  EXPECT_EQ(s.target_name, "mug");
  EXPECT_EQ(s.first_touch_frame, 3);
  EXPECT_EQ(s.touching_frames, 2);
  EXPECT_TRUE(s.masks);
  EXPECT_TRUE(s.depth);
  EXPECT_FALSE(s.stereo);
  const core::Json j = to_json(s);
  EXPECT_EQ(j["first_touch_frame"], 3);
  EXPECT_EQ(j["objects"].size(), 3u);
  EXPECT_EQ(j["seed"], 42);
  const std::string text = format_summary(s);
  EXPECT_NE(text.find("target: 1 (mug)"), std::string::npos) << text;
  EXPECT_NE(text.find("first touch: frame 3"), std::string::npos) << text;
}

TEST(EpisodeInfoJson, RoundTrips) {
  EpisodeInfo info = synthetic_info({});
  info.frame_count = 17;
  info.storage = FrameStorage::kVideo;
  info.video_file = "v.avi";
  const EpisodeInfo back = episode_info_from_json(to_json(info), "episode.json");
  EXPECT_EQ(back.frame_count, 17);
  EXPECT_EQ(back.storage, FrameStorage::kVideo);
  EXPECT_EQ(back.video_file, "v.avi");
  EXPECT_EQ(back.provenance.run.command_line, info.provenance.run.command_line);
  EXPECT_EQ(to_json(back), to_json(info));
}

TEST(ObjectsJson, RoundTripsAndRejectsBadObjects) {
  const auto objects = synthetic_objects();
  const auto back = objects_from_json(objects_to_json(objects), "objects.json");
  ASSERT_EQ(back.size(), 3u);
  EXPECT_EQ(back[2].name, "book");
  EXPECT_EQ(back[2].role, ObjectRole::kObject);
  const auto error = [](core::Json j) {
    try {
      objects_from_json(j, "objects.json");
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  core::Json j = objects_to_json(objects);
  j["objects"][1]["id"] = 1;
  EXPECT_EQ(error(j), "objects.json: objects[1]: id 1 appears twice");
  j = objects_to_json(objects);
  j["objects"][0]["id"] = 0;
  EXPECT_NE(error(j).find("'id' must be an integer in [1, 65535]"), std::string::npos);
  j = objects_to_json(objects);
  j["objects"][2]["role"] = "furniture";
  EXPECT_NE(error(j).find("'role' must be 'target', 'object', 'arm' or 'distractor'"),
            std::string::npos);
  j = objects_to_json(objects);
  j["objects"][2]["role"] = "target";
  EXPECT_EQ(error(j), "objects.json: more than one object has the role 'target'");
  // Issue 16: repeated object names were accepted (results and classes name objects).
  j = objects_to_json(objects);
  j["objects"][2]["name"] = j["objects"][1]["name"];
  EXPECT_EQ(error(j), "objects.json: objects[2]: name '" + objects[1].name + "' appears twice");
}

// --- the writer -------------------------------------------------------------------------------

std::vector<std::string> entries(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir)) out.push_back(e.path().filename().string());
  std::sort(out.begin(), out.end());
  return out;
}

TEST(EpisodeWriter, DestroyedBeforeFinishLeavesNothing) {
  TempDir tmp;
  SyntheticSpec spec;
  const auto dir = tmp.path() / "ep";
  {
    EpisodeWriter w(dir, synthetic_info(spec), overhead_camera(spec.width, spec.height),
                    synthetic_objects());
    for (int i = 0; i < 3; ++i) {
      w.add_frame(synthetic_frame(spec, i), synthetic_sample(spec, i),
                  {.mask = synthetic_mask(spec, i)});
    }
    EXPECT_TRUE(fs::exists(w.staging_path() / "frames" / "000002.png"));
    EXPECT_FALSE(fs::exists(dir));  // nothing at the final path while writing
  }
  EXPECT_FALSE(fs::exists(dir));
  EXPECT_TRUE(entries(tmp.path()).empty());  // and no staging directory left behind
}

TEST(EpisodeWriter, ErrorMidWayLeavesNothing) {
  TempDir tmp;
  SyntheticSpec spec;
  const auto dir = tmp.path() / "ep";
  try {
    EpisodeWriter w(dir, synthetic_info(spec), overhead_camera(spec.width, spec.height),
                    synthetic_objects());
    w.add_frame(synthetic_frame(spec, 0), synthetic_sample(spec, 0),
                {.mask = synthetic_mask(spec, 0)});
    w.add_frame(synthetic_frame(spec, 1), synthetic_sample(spec, 0),  // time does not increase
                {.mask = synthetic_mask(spec, 1)});
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("is not after the previous frame's"), std::string::npos)
        << e.what();
  }
  EXPECT_TRUE(entries(tmp.path()).empty());
}

TEST(EpisodeWriter, RejectsBadFramesAndSamples) {
  TempDir tmp;
  SyntheticSpec spec;
  spec.masks = false;
  EpisodeWriter w(tmp.path() / "ep", synthetic_info(spec), overhead_camera(spec.width, spec.height),
                  synthetic_objects());
  const auto message = [&](const cv::Mat& image, const ArmSample& s, const FrameExtras& x = {}) {
    try {
      w.add_frame(image, s, x);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const cv::Mat good = synthetic_frame(spec, 0);
  ArmSample s = synthetic_sample(spec, 0);
  EXPECT_NE(message(cv::Mat(10, 10, CV_8UC3), s).find("image of frame 0 is 10x10, expected 64x48"),
            std::string::npos);
  EXPECT_NE(message(cv::Mat(48, 64, CV_32FC1), s).find("must be 8-bit BGR or grey"),
            std::string::npos);
  ArmSample nan = s;
  nan.ee.y() = std::nan("");
  EXPECT_NE(message(good, nan).find("holds NaN or inf"), std::string::npos);
  ArmSample joints = s;
  joints.q = Eigen::VectorXd::Zero(5);
  EXPECT_NE(message(good, joints).find("has 5 joints, expected 2"), std::string::npos);
  EXPECT_NE(message(good, s, {.mask = synthetic_mask(spec, 0)}).find("the episode has none"),
            std::string::npos);
  EXPECT_EQ(w.frames_written(), 0);
  EXPECT_EQ(message(good, s), "no error");
  EXPECT_EQ(w.frames_written(), 1);
}

TEST(EpisodeWriter, RejectsMaskIdsTheObjectsLack) {
  TempDir tmp;
  SyntheticSpec spec;
  EpisodeWriter w(tmp.path() / "ep", synthetic_info(spec), overhead_camera(spec.width, spec.height),
                  synthetic_objects());
  cv::Mat mask = synthetic_mask(spec, 0);
  mask.at<std::uint16_t>(47, 63) = 77;
  try {
    w.add_frame(synthetic_frame(spec, 0), synthetic_sample(spec, 0), {.mask = mask});
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("holds id 77 that the objects lack"), std::string::npos)
        << e.what();
  }
}

TEST(EpisodeWriter, RejectsInconsistentSetup) {
  TempDir tmp;
  SyntheticSpec spec;
  const auto cam = overhead_camera(spec.width, spec.height);
  const auto message = [&](const EpisodeInfo& info, const std::vector<ObjectInfo>& objects,
                           geometry::Camera c) {
    try {
      EpisodeWriter w(tmp.path() / "ep", info, c, objects);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message(synthetic_info(spec), {}, cam).find("needs its objects"), std::string::npos);
  EpisodeInfo info = synthetic_info(spec);
  info.target = 3;  // the book, whose role is 'object'
  EXPECT_NE(message(info, synthetic_objects(), cam).find("must have the role 'target'"),
            std::string::npos);
  info.target = 1;
  info.fps = 0;
  EXPECT_NE(message(info, synthetic_objects(), cam).find("'fps' is 0"), std::string::npos);
  info = synthetic_info(spec);
  info.provenance.run.seed.reset();
  EXPECT_NE(message(info, synthetic_objects(), cam).find("needs its seed"), std::string::npos);
  geometry::Camera wrong = cam;
  wrong.width = 640;
  wrong.height = 480;
  EXPECT_NE(message(synthetic_info(spec), synthetic_objects(), wrong).find("is for 640x480"),
            std::string::npos);
  EXPECT_TRUE(entries(tmp.path()).empty());
}

TEST(EpisodeWriter, FinishWithoutFramesFailsAndLeavesNothing) {
  TempDir tmp;
  SyntheticSpec spec;
  {
    EpisodeWriter w(tmp.path() / "ep", synthetic_info(spec),
                    overhead_camera(spec.width, spec.height), synthetic_objects());
    EXPECT_THROW(w.finish(), Error);
  }
  EXPECT_TRUE(entries(tmp.path()).empty());
}

TEST(EpisodeWriter, RefusesToOverwriteUnlessAsked) {
  TempDir tmp;
  SyntheticSpec spec;
  const auto dir = write_synthetic(tmp.path() / "ep", spec);
  EXPECT_THROW(write_synthetic(dir, spec), Error);
  spec.frames = 2;
  EpisodeWriter w(dir, synthetic_info(spec), overhead_camera(spec.width, spec.height),
                  synthetic_objects(), std::nullopt, {.overwrite = true});
  for (int i = 0; i < 2; ++i) {
    w.add_frame(synthetic_frame(spec, i), synthetic_sample(spec, i),
                {.mask = synthetic_mask(spec, i)});
  }
  EXPECT_EQ(read_episode(dir).frame_count(), 5);  // the old one until finish()
  w.finish();
  EXPECT_EQ(read_episode(dir).frame_count(), 2);
}

}  // namespace
}  // namespace proprio::episode
