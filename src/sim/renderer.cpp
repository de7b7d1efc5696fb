#include "proprio/sim/renderer.hpp"

#include <mujoco/mujoco.h>

#include <cassert>
#include <cstddef>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <utility>
#include <vector>

#include "proprio/core/error.hpp"
#include "proprio/sim/mujoco_messages.hpp"

namespace proprio::sim {

namespace {

struct SceneDeleter {
  void operator()(mjvScene* s) const noexcept {
    mjv_freeScene(s);
    delete s;
  }
};
struct ContextDeleter {
  void operator()(mjrContext* c) const noexcept {
    mjr_freeContext(c);
    delete c;
  }
};

// Room in the abstract scene for geoms beyond the model's (decorations such as contact markers).
constexpr int kExtraSceneGeoms = 500;
// Hidden geom group: the table's collision plane.
constexpr int kHiddenGroup = 3;

}  // namespace

struct Renderer::Impl {
  // Declaration order matters: the GL context must outlive MuJoCo's GPU resources.
  GlContext gl;
  const mjModel* model = nullptr;
  RenderOptions options;
  std::unique_ptr<mjrContext, ContextDeleter> context;
  std::unique_ptr<mjvScene, SceneDeleter> scene;
  mjvOption option{};
  mjvCamera camera{};
  std::vector<unsigned char> rgb_buffer;
  std::vector<float> depth_buffer;
  std::vector<ObjectId> segid_to_object;

  explicit Impl(GlContext context_in) : gl(std::move(context_in)) {}
  Impl(const Impl&) = delete;
  Impl& operator=(const Impl&) = delete;
  ~Impl() {
    // MuJoCo frees GPU objects of the current context.
    if (context) gl.make_current();
  }

  // Renders `camera_id` into the off-screen buffer and reads back colour (and depth).
  void draw(const World& world, int camera_id, int width, int height, bool segment,
            bool want_depth) {
    assert(&world.model() == model && "a Renderer serves the World it was made with");
    gl.make_current();
    camera.type = mjCAMERA_FIXED;
    camera.fixedcamid = camera_id;
    // mjv_updateScene does not modify the data; MuJoCo's API just is not const-correct.
    mjv_updateScene(model, const_cast<mjData*>(&world.data()), &option, nullptr, &camera, mjCAT_ALL,
                    scene.get());
    scene->flags[mjRND_SHADOW] = !segment && options.shadows;
    scene->flags[mjRND_REFLECTION] = !segment && options.reflections;
    scene->flags[mjRND_SKYBOX] = 0;
    scene->flags[mjRND_SEGMENT] = segment;
    scene->flags[mjRND_IDCOLOR] = segment;
    const mjrRect viewport{0, 0, width, height};
    mjr_render(viewport, scene.get(), context.get());
    rgb_buffer.resize(static_cast<std::size_t>(width) * height * 3);
    depth_buffer.resize(want_depth ? static_cast<std::size_t>(width) * height : 0);
    mjr_readPixels(rgb_buffer.data(), want_depth ? depth_buffer.data() : nullptr, viewport,
                   context.get());
  }

  cv::Mat read_rgb(int width, int height) const {
    // OpenGL rows run bottom-up.
    const cv::Mat gl_rgb(height, width, CV_8UC3, const_cast<unsigned char*>(rgb_buffer.data()));
    cv::Mat bgr;
    cv::flip(gl_rgb, bgr, 0);
    cv::cvtColor(bgr, bgr, cv::COLOR_RGB2BGR);  // in place: no second image
    return bgr;
  }

  cv::Mat read_mask(const World& world, int width, int height) {
    // With mjRND_IDCOLOR every pixel holds segid + 1 of its scene geom (0 = nothing drawn).
    segid_to_object.assign(static_cast<std::size_t>(scene->ngeom) + 1, kBackgroundId);
    for (int i = 0; i < scene->ngeom; ++i) {
      const mjvGeom& g = scene->geoms[i];
      if (g.objtype == mjOBJ_GEOM && g.segid >= 0 && g.segid < scene->ngeom) {
        segid_to_object[static_cast<std::size_t>(g.segid) + 1] = world.geom_object_id(g.objid);
      }
    }
    cv::Mat mask(height, width, CV_16UC1);
    for (int r = 0; r < height; ++r) {
      const unsigned char* src =
          rgb_buffer.data() + static_cast<std::size_t>(height - 1 - r) * width * 3;
      auto* dst = mask.ptr<std::uint16_t>(r);
      for (int c = 0; c < width; ++c) {
        const unsigned char* rgb = src + std::ptrdiff_t{3} * c;
        const std::size_t id = rgb[0] | (static_cast<std::size_t>(rgb[1]) << 8) |
                               (static_cast<std::size_t>(rgb[2]) << 16);
        dst[c] = id < segid_to_object.size() ? segid_to_object[id] : kBackgroundId;
      }
    }
    return mask;
  }

  cv::Mat read_depth(int width, int height) const {
    // Undo the perspective depth mapping d = (1/near - 1/z) / (1/near - 1/far) of OpenGL's
    // standard projection: z = near far / (far - d (far - near)).
    const double extent = model->stat.extent;
    const double znear = model->vis.map.znear * extent;
    const double zfar = model->vis.map.zfar * extent;
    cv::Mat depth(height, width, CV_32FC1);
    for (int r = 0; r < height; ++r) {
      const float* src = depth_buffer.data() + static_cast<std::size_t>(height - 1 - r) * width;
      auto* dst = depth.ptr<float>(r);
      for (int c = 0; c < width; ++c) {
        const double d = src[c];
        dst[c] = d >= 1.0 ? 0.0F : static_cast<float>(znear * zfar / (zfar - d * (zfar - znear)));
      }
    }
    return depth;
  }
};

Renderer::Renderer(const World& world, RenderOptions options)
    : impl_(std::make_unique<Impl>(GlContext::create(options.backend))) {
  install_mujoco_handlers();
  Impl& r = *impl_;
  r.model = &world.model();
  r.options = options;
  r.scene.reset(new mjvScene);
  mjv_defaultScene(r.scene.get());
  mjv_makeScene(r.model, r.scene.get(), r.model->ngeom + kExtraSceneGeoms);
  r.context.reset(new mjrContext);
  mjr_defaultContext(r.context.get());
  mjr_makeContext(r.model, r.context.get(), mjFONTSCALE_100);
  mjr_setBuffer(mjFB_OFFSCREEN, r.context.get());
  if (r.context->currentBuffer != mjFB_OFFSCREEN) {
    throw Error("OpenGL: MuJoCo could not make its off-screen framebuffer");
  }
  mjv_defaultOption(&r.option);
  r.option.geomgroup[kHiddenGroup] = 0;
  // Sites (the ee point) are references, not things a camera sees.
  for (int g = 0; g < mjNGROUP; ++g) r.option.sitegroup[g] = 0;
  mjv_defaultCamera(&r.camera);
}

Renderer::Renderer(Renderer&&) noexcept = default;
Renderer& Renderer::operator=(Renderer&&) noexcept = default;
Renderer::~Renderer() = default;

Frame Renderer::render(const World& world, const std::string& camera, unsigned passes) {
  const int id = world.camera_id(camera);
  const auto [width, height] = world.camera_size(camera);
  Frame f;
  if ((passes & (kPassRgb | kPassDepth)) != 0U) {
    impl_->draw(world, id, width, height, false, (passes & kPassDepth) != 0U);
    if ((passes & kPassRgb) != 0U) f.rgb = impl_->read_rgb(width, height);
    if ((passes & kPassDepth) != 0U) f.depth = impl_->read_depth(width, height);
  }
  if ((passes & kPassMask) != 0U) {
    impl_->draw(world, id, width, height, true, false);
    f.mask = impl_->read_mask(world, width, height);
  }
  return f;
}

cv::Mat Renderer::rgb(const World& world, const std::string& camera) {
  return render(world, camera, kPassRgb).rgb;
}

cv::Mat Renderer::mask(const World& world, const std::string& camera) {
  return render(world, camera, kPassMask).mask;
}

cv::Mat Renderer::depth(const World& world, const std::string& camera) {
  return render(world, camera, kPassDepth).depth;
}

void Renderer::upload_texture(const World& world, const std::string& texture) {
  assert(&world.model() == impl_->model);
  const int id = world.texture_id(texture);
  impl_->gl.make_current();
  mjr_uploadTexture(impl_->model, impl_->context.get(), id);
}

void Renderer::set_shadows(bool on) { impl_->options.shadows = on; }
void Renderer::set_reflections(bool on) { impl_->options.reflections = on; }
const RenderOptions& Renderer::options() const { return impl_->options; }
GlBackend Renderer::backend() const { return impl_->gl.backend(); }
std::string Renderer::gl_renderer() const { return impl_->gl.renderer_name(); }

}  // namespace proprio::sim
