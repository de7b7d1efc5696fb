#include "backdrop_video.hpp"

#include <cmath>

#include "proprio/core/error.hpp"

namespace proprio::sim {

BackdropVideo::BackdropVideo(bool on, const std::filesystem::path& file) : file_(file) {
  if (!on) return;
  if (!std::filesystem::is_regular_file(file)) {
    throw Error::in_file(file, "no such background video");
  }
  video_.open(file.string());
  if (!video_.isOpened()) throw Error::in_file(file, "cannot open the background video");
  const double f = video_.get(cv::CAP_PROP_FPS);
  if (std::isfinite(f) && f >= 1 && f <= 1000) fps_ = f;
}

void BackdropVideo::show_next(World& world, Renderer& renderer) {
  cv::Mat vf;
  read_next(vf, true);
  world.set_texture_image(kBackdropTexture, vf);
  renderer.upload_texture(world, kBackdropTexture);
}

void BackdropVideo::read_next(cv::Mat& frame, bool decode) {
  const bool ok = decode ? video_.read(frame) : video_.grab();
  if (ok && (!decode || !frame.empty())) {
    ++position_;
    return;
  }
  if (position_ == 0) throw Error::in_file(file_, "cannot read a frame");
  length_ = position_;
  position_ = 0;
  video_.set(cv::CAP_PROP_POS_FRAMES, 0);
  if (!(decode ? video_.read(frame) : video_.grab()) || (decode && frame.empty())) {
    throw Error::in_file(file_, "cannot read a frame");
  }
  ++position_;
}

void BackdropVideo::show_at(World& world, Renderer& renderer, double t) {
  if (!on()) return;
  const auto want = static_cast<std::int64_t>(std::floor(std::max(0.0, t) * fps_));
  if (want == shown_) return;
  assert(want > shown_);
  std::int64_t skip = want - shown_ - 1;  // frames to pass over before the one shown
  if (length_ > 0) skip %= length_;
  for (std::int64_t k = 0; k < skip; ++k) {
    cv::Mat unused;
    read_next(unused, false);
  }
  cv::Mat vf;
  read_next(vf, true);
  shown_ = want;
  world.set_texture_image(kBackdropTexture, vf);
  renderer.upload_texture(world, kBackdropTexture);
}

}  // namespace proprio::sim
