#pragma once
// Headless rendering of a World's cameras with MuJoCo's OpenGL renderer: colour images, object-id
// masks (exact ground truth: segmentation colours decoded back to object ids) and depth.

#include <memory>
#include <opencv2/core.hpp>
#include <string>

#include "proprio/sim/gl_context.hpp"
#include "proprio/sim/world.hpp"

namespace proprio::sim {

struct RenderOptions {
  bool shadows = true;      ///< shadow mapping (about half the frame rate in software GL)
  bool reflections = true;  ///< mirror reflections of reflective materials (the table top)
  GlBackend backend = GlBackend::kAuto;
};

/// Which images render() produces.
enum RenderPass : unsigned {
  kPassRgb = 1U,
  kPassMask = 2U,
  kPassDepth = 4U,
};

/// What one camera saw; images are top row first, width x height of the camera.
struct Frame {
  cv::Mat rgb;    ///< CV_8UC3, BGR (OpenCV order)
  cv::Mat mask;   ///< CV_16UC1 object ids: 0 background, objects 1..N, kArmId for the arm
  cv::Mat depth;  ///< CV_32FC1 metres along the optical axis (the camera frame's z); 0 = nothing
};

/// Renders a World. Owns the GL context, MuJoCo's GPU-side copy of the model (mjrContext) and the
/// abstract scene (mjvScene); one renderer serves one World (the one it was made with; calls with
/// another world's model are a programming error) and one thread.
class Renderer {
 public:
  /// Creates the GL context (throws Error when none can be had) and uploads the model.
  explicit Renderer(const World& world, RenderOptions options = {});
  Renderer(Renderer&&) noexcept;
  Renderer& operator=(Renderer&&) noexcept;
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;
  ~Renderer();

  /// Renders camera `camera` in the world's current state. RGB and depth come from one pass, the
  /// mask from a second (flat id colours, no lighting). Throws Error for an unknown camera.
  Frame render(const World& world, const std::string& camera,
               unsigned passes = kPassRgb | kPassMask);
  cv::Mat rgb(const World& world, const std::string& camera);
  cv::Mat mask(const World& world, const std::string& camera);
  cv::Mat depth(const World& world, const std::string& camera);

  /// Sends a texture's texels (after World::set_texture_image) to the GPU.
  void upload_texture(const World& world, const std::string& texture);

  void set_shadows(bool on);
  void set_reflections(bool on);
  [[nodiscard]] const RenderOptions& options() const;
  [[nodiscard]] GlBackend backend() const;
  /// GL_RENDERER of the context, e.g. "llvmpipe (LLVM 15.0.7, 256 bits)".
  [[nodiscard]] std::string gl_renderer() const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace proprio::sim
