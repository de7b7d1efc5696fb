#pragma once
// Synthetic push episodes for the M-L tests: a textured square pushed by a textured "arm" block
// over a static or moving textured background, with exact ground truth.

#include <cstdlib>
#include <filesystem>
#include <opencv2/imgproc.hpp>
#include <string>

#include "../support/synthetic_episode.hpp"
#include "../support/temp_dir.hpp"
#include "proprio/core/random.hpp"
#include "proprio/episode/episode.hpp"
#include "proprio/episode/episode_writer.hpp"

namespace proprio::segmentation::testing {

namespace fs = std::filesystem;

/// Named by `tag`; kept when PROPRIO_SEG_KEEP is set, to look at the episodes.
class TempDir : public proprio::test::TempDir {
 public:
  explicit TempDir(const std::string& tag)
      : proprio::test::TempDir("proprio_seg_ml_", tag, std::getenv("PROPRIO_SEG_KEEP") != nullptr) {
  }
};

struct PushSpec {
  int width = 320;
  int height = 240;
  int frames = 24;
  int still = 2;       ///< frames before the arm moves
  double speed = 4.0;  ///< arm speed, pixels a frame
  bool moving_background = false;
  bool plain_background = false;  ///< a flat grey-blue table instead of the texture
  bool touch = true;              ///< false: the arm stops short of the square
  bool ee_known = true;           ///< false: no end-effector position anywhere (behind the camera)
  int square = 50;                ///< side, pixels
  int arm = 24;                   ///< side of the arm block, pixels
  /// A shaking camera: each frame, all of it (table, square, arm) shifted by a random whole
  /// number of pixels in [-shake, shake] each way; the arm's image track stays as the still
  /// camera would see it.
  int shake = 0;
  /// A second patch (tint unlike the square's) near the top edge, ahead of the arm but far from
  /// it, that stays still until the touch and then moves exactly as the pushed square does
  /// (mask 3).
  bool echo = false;
  /// From frame jolt_frame on, the square stands `jolt` pixels further right (the table bumped
  /// before the touch: the still object moves once, along the arm's approach).
  int jolt_frame = -1;
  int jolt = 0;
  /// The square's texture contrast: 1 = full; below, its grey levels are pulled towards their
  /// mean by this factor (a dark, low-contrast object such as the simulated bottle).
  double square_contrast = 1.0;
  /// Brightness of the square's texture, times its default tint (a darker object below 1).
  double square_brightness = 1.0;
  /// The same for the (textured) table: its grey levels pulled towards their mean.
  double background_contrast = 1.0;
  /// The arm drawn with the square's own texture (another part of it): superpixels of the
  /// touch frame then straddle the arm and the square it touches, as the simulated gripper and
  /// the mug's side do.
  bool arm_like_square = false;
  /// A strip of the arm, this many pixels tall, along the underside of the arm block and the
  /// square, drawn (with the arm's texture) only from the first touching frame on and moving
  /// with the arm: a part of the arm first seen at the touch (as the simulated arm's side and
  /// shade next to a pushed bottle), with no record from before the touch (mask 2).
  int arm_rim = 0;
};

/// Smooth random colour texture (blurred noise), deterministic by seed.
inline cv::Mat3b texture(cv::Size size, std::uint64_t seed, cv::Scalar tint) {
  cv::Mat1f t(size);
  cv::RNG rng(seed);
  rng.fill(t, cv::RNG::UNIFORM, 0.0, 1.0);
  cv::GaussianBlur(t, t, cv::Size(), 2.0);
  cv::normalize(t, t, 0.0, 1.0, cv::NORM_MINMAX);  // full contrast after the blur
  cv::Mat3b out(size);
  for (int y = 0; y < size.height; ++y)
    for (int x = 0; x < size.width; ++x)
      for (int c = 0; c < 3; ++c)
        out(y, x)[c] = cv::saturate_cast<uchar>(tint[c] * (0.3 + 0.9 * t(y, x)));
  return out;
}

struct PushFrame {
  cv::Mat3b image;
  cv::Mat1w mask;  ///< 1 = square (target), 2 = arm, 3 = echo
  Eigen::Vector2d ee;
  bool touching = false;
};

/// The arm's tip moves right from x = square's left - 8 * speed after `still` frames; it
/// touches the square at frame still + 8 and pushes it along.
inline PushFrame push_frame(const PushSpec& s, int i) {
  const double sq_left0 = s.width * 0.45;
  const double y_mid = s.height * 0.5;
  const double tip0 = sq_left0 - 8 * s.speed;
  double tip = tip0 + s.speed * std::max(0, i - s.still);
  if (!s.touch) tip = std::min(tip, sq_left0 - 6);
  const double sq_left = std::max(sq_left0, tip);
  static const cv::Mat3b bg_tex = texture({1024, 1024}, 11, {200, 120, 60});
  static const cv::Mat3b sq_tex = texture({64, 64}, 22, {40, 200, 230});
  static const cv::Mat3b arm_tex = texture({64, 64}, 33, {230, 60, 200});
  PushFrame f;
  const int dy = s.moving_background ? 2 * i : 0;
  const int dx = s.moving_background ? i : 0;
  f.image = s.plain_background ? cv::Mat3b(s.height, s.width, cv::Vec3b(150, 170, 190))
                               : bg_tex(cv::Rect(100 + dx, 100 + dy, s.width, s.height)).clone();
  if (!s.plain_background && s.background_contrast != 1.0) {
    const cv::Scalar mean = cv::mean(f.image);
    cv::Mat3f flat;
    f.image.convertTo(flat, CV_32F);
    flat = (flat - mean) * s.background_contrast + mean;
    flat.convertTo(f.image, CV_8U);
  }
  f.mask = cv::Mat1w(s.height, s.width, ushort{0});
  const int jolted = s.jolt_frame >= 0 && i >= s.jolt_frame ? s.jolt : 0;
  const cv::Rect sq(static_cast<int>(std::lround(sq_left)) + jolted,
                    static_cast<int>(std::lround(y_mid - s.square / 2.0)), s.square, s.square);
  if (s.square_contrast == 1.0 && s.square_brightness == 1.0) {
    sq_tex(cv::Rect(0, 0, s.square, s.square)).copyTo(f.image(sq));
  } else {
    const cv::Mat3b patch = sq_tex(cv::Rect(0, 0, s.square, s.square));
    const cv::Scalar mean = cv::mean(patch);
    cv::Mat3f flat;
    patch.convertTo(flat, CV_32F);
    flat = (flat - mean) * s.square_contrast + mean;
    cv::Mat3b roi = f.image(sq);
    flat.convertTo(roi, CV_8U, s.square_brightness);
  }
  f.mask(sq).setTo(1);
  if (s.echo) {
    static const cv::Mat3b echo_tex = texture({64, 64}, 44, {60, 230, 90});
    const cv::Rect echo(static_cast<int>(std::lround(s.width * 0.65 + sq_left - sq_left0)), 12, 30,
                        30);
    echo_tex(cv::Rect(0, 0, echo.width, echo.height)).copyTo(f.image(echo));
    f.mask(echo).setTo(3);
  }
  const cv::Rect arm(static_cast<int>(std::lround(tip)) - s.arm,
                     static_cast<int>(std::lround(y_mid - s.arm / 2.0)), s.arm, s.arm);
  const cv::Rect arm_in = arm & cv::Rect(0, 0, s.width, s.height);
  const cv::Point arm_from =
      s.arm_like_square ? cv::Point(64 - arm_in.width, 64 - arm_in.height) : cv::Point(0, 0);
  (s.arm_like_square ? sq_tex : arm_tex)(cv::Rect(arm_from, arm_in.size())).copyTo(f.image(arm_in));
  f.mask(arm_in).setTo(2);
  f.ee = {tip, y_mid};
  f.touching = s.touch && tip >= sq_left0;
  if (s.arm_rim > 0 && f.touching) {
    const cv::Rect rim = cv::Rect(arm.x, arm.y + arm.height, arm.width + s.square, s.arm_rim) &
                         cv::Rect(0, 0, s.width, s.height);
    for (int x = rim.x; x < rim.x + rim.width; x += 64) {  // the 64 px texture tiled along it
      const cv::Rect piece(x, rim.y, std::min(64, rim.x + rim.width - x), rim.height);
      arm_tex(cv::Rect(cv::Point(0, 64 - piece.height), piece.size())).copyTo(f.image(piece));
    }
    f.mask(rim).setTo(2);
  }
  if (s.shake > 0) {
    cv::RNG rng(1000 + i);
    const cv::Matx23d shift(1, 0, rng.uniform(-s.shake, s.shake + 1), 0, 1,
                            rng.uniform(-s.shake, s.shake + 1));
    cv::warpAffine(f.image, f.image, shift, f.image.size(), cv::INTER_NEAREST, cv::BORDER_REFLECT);
    cv::warpAffine(f.mask, f.mask, shift, f.mask.size(), cv::INTER_NEAREST, cv::BORDER_CONSTANT);
  }
  return f;
}

/// Writes the episode to `dir` and returns it.
inline fs::path write_push_episode(const fs::path& dir, const PushSpec& s) {
  const auto info = test::synthetic_info(s.width, s.height, "segmentation_ml_test", 1);
  const auto cam = test::overhead_camera(300.0, s.width / 2.0, s.height / 2.0);
  std::vector<episode::ObjectInfo> objects = {{1, "square", episode::ObjectRole::kTarget},
                                              {2, "arm", episode::ObjectRole::kArm}};
  if (s.echo) objects.push_back({3, "echo", episode::ObjectRole::kObject});
  return test::write_synthetic_episode(dir, info, cam, objects, s.frames, [&s](int i) {
    const PushFrame f = push_frame(s, i);
    // Without a known end effector it is above the camera: no image position.
    test::SyntheticFrame out{
        f.image, test::arm_at(i, 25.0, {0.1, 0.0, s.ee_known ? 0.0 : 2.0}), {}};
    if (s.ee_known) out.arm.ee_image = f.ee;
    out.arm.touching = f.touching;
    out.extras.mask = f.mask;
    return out;
  });
}

inline double jaccard(const cv::Mat& a, const cv::Mat& b) {
  const int inter = cv::countNonZero(a & b);
  const int uni = cv::countNonZero(a | b);
  return uni > 0 ? static_cast<double>(inter) / uni : 1.0;
}

}  // namespace proprio::segmentation::testing
