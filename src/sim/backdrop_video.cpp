#include "backdrop_video.hpp"

#include "proprio/core/error.hpp"

namespace proprio::sim {

BackdropVideo::BackdropVideo(bool on, const std::filesystem::path& file) : file_(file) {
  if (!on) return;
  if (!std::filesystem::is_regular_file(file)) {
    throw Error::in_file(file, "no such background video");
  }
  video_.open(file.string());
  if (!video_.isOpened()) throw Error::in_file(file, "cannot open the background video");
}

void BackdropVideo::show_next(World& world, Renderer& renderer) {
  cv::Mat vf;
  if (!video_.read(vf) || vf.empty()) {
    video_.set(cv::CAP_PROP_POS_FRAMES, 0);
    video_.read(vf);
  }
  if (vf.empty()) throw Error::in_file(file_, "cannot read a frame");
  world.set_texture_image(kBackdropTexture, vf);
  renderer.upload_texture(world, kBackdropTexture);
}

}  // namespace proprio::sim
