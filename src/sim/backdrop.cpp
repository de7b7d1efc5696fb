#include "proprio/sim/backdrop.hpp"

#include "proprio/sim/object_catalogue.hpp"

namespace proprio::sim {

std::filesystem::path default_background_video() {
  return ObjectCatalogue::default_texture_dir() / "vtest.avi";
}

std::filesystem::path default_background_photo() {
  return ObjectCatalogue::default_texture_dir() / "leuvenA.jpg";
}

BackdropLayout recording_backdrop_layout() { return {}; }

void set_backdrop(SceneDescription& scene, Background background, const BackdropLayout& layout,
                  const std::filesystem::path& photo) {
  scene.backdrop.enabled = background != Background::kPlain;
  scene.backdrop.center = layout.center;
  scene.backdrop.size = layout.size;
  scene.backdrop.texture_width = layout.texture_width;
  scene.backdrop.texture_height = layout.texture_height;
  scene.backdrop.image = background == Background::kPhoto ? photo : std::filesystem::path();
}

}  // namespace proprio::sim
