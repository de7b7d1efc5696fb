#pragma once
// A headless OpenGL context for MuJoCo's renderer: EGL (a GPU, or Mesa's surfaceless platform)
// or OSMesa (software), chosen at run time.

#include <memory>
#include <string>

namespace proprio::sim {

enum class GlBackend {
  kAuto,    ///< MUJOCO_GL=egl|osmesa when set, else EGL, falling back to OSMesa
  kEgl,     ///< EGL without a window: device platform (GPU) or Mesa's surfaceless platform
  kOsMesa,  ///< Mesa's off-screen software renderer
};

/// "auto", "egl", "osmesa" (for command lines and logs).
std::string to_string(GlBackend backend);
/// Parses "auto", "egl", "osmesa"; throws Error otherwise.
GlBackend parse_gl_backend(const std::string& name);

/// An OpenGL context that is current on the calling thread after create() and make_current().
/// MuJoCo renders into its own off-screen framebuffer, so the context needs no window; the
/// OSMesa variant owns a small colour buffer only because OSMesaMakeCurrent requires one.
/// Move-only; destroying it releases the context.
class GlContext {
 public:
  /// Creates a context and makes it current. Throws Error naming every backend tried and why it
  /// failed when no context can be had.
  static GlContext create(GlBackend backend = GlBackend::kAuto);

  GlContext(GlContext&&) noexcept;
  GlContext& operator=(GlContext&&) noexcept;
  GlContext(const GlContext&) = delete;
  GlContext& operator=(const GlContext&) = delete;
  ~GlContext();

  /// Makes this context current on the calling thread (contexts are per thread in OpenGL).
  void make_current() const;
  /// The backend actually in use (never kAuto).
  [[nodiscard]] GlBackend backend() const;
  /// GL_RENDERER of the context, e.g. "llvmpipe (LLVM 15.0.7, 256 bits)".
  [[nodiscard]] std::string renderer_name() const;

  struct Impl;

 private:
  explicit GlContext(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace proprio::sim
