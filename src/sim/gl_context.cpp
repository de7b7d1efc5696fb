#include "proprio/sim/gl_context.hpp"

#include <GL/osmesa.h>
#include <dlfcn.h>

#include <cassert>
#include <cstdlib>
#include <map>
#include <mutex>
#include <string_view>
#include <utility>
#include <vector>

#include "proprio/core/error.hpp"

#if __has_include(<EGL/egl.h>)
#include <EGL/egl.h>
#include <EGL/eglext.h>
#define PROPRIO_HAVE_EGL_HEADERS 1
#else
#define PROPRIO_HAVE_EGL_HEADERS 0
#endif

namespace proprio::sim {

namespace {
constexpr GLenum kGlRenderer = 0x1F01;  // GL_RENDERER, without pulling in a GL loader
using GetStringFn = const unsigned char* (*)(GLenum);
}  // namespace

std::string to_string(GlBackend backend) {
  switch (backend) {
    case GlBackend::kAuto:
      return "auto";
    case GlBackend::kEgl:
      return "egl";
    case GlBackend::kOsMesa:
      return "osmesa";
  }
  return "?";
}

GlBackend parse_gl_backend(const std::string& name) {
  if (name == "auto") return GlBackend::kAuto;
  if (name == "egl") return GlBackend::kEgl;
  if (name == "osmesa") return GlBackend::kOsMesa;
  throw Error("unknown OpenGL backend '" + name + "' (expected auto, egl or osmesa)");
}

#if PROPRIO_HAVE_EGL_HEADERS
// EGL displays are per process: eglGetDisplay gives every context in the process the same one, and
// eglTerminate ends every context on it. So that two renderers can live in one process (a Python
// session with a Scene and a SimulatedRobot), a display is terminated only when its last context
// goes, or when a candidate display that no context uses is abandoned.
namespace {
std::mutex& egl_display_mutex() {
  static std::mutex mutex;
  return mutex;
}
std::map<EGLDisplay, int>& egl_display_users() {
  static std::map<EGLDisplay, int> users;
  return users;
}
void acquire_egl_display(EGLDisplay display) {
  const std::lock_guard lock(egl_display_mutex());
  ++egl_display_users()[display];
}
// Drops one user (when `used`) and terminates the display when none is left.
void release_egl_display(EGLDisplay display, PFNEGLTERMINATEPROC terminate, bool used = true) {
  const std::lock_guard lock(egl_display_mutex());
  auto& users = egl_display_users();
  auto it = users.find(display);
  if (used && it != users.end() && --it->second == 0) users.erase(it);
  if (users.find(display) == users.end()) terminate(display);
}
}  // namespace
#endif

struct GlContext::Impl {
  GlBackend backend = GlBackend::kOsMesa;
  // OSMesa
  OSMesaContext osmesa = nullptr;
  std::vector<unsigned char> osmesa_buffer;
  // EGL, loaded with dlopen so that the library needs no EGL at link time.
  void* egl_lib = nullptr;
#if PROPRIO_HAVE_EGL_HEADERS
  EGLDisplay egl_display = EGL_NO_DISPLAY;
  EGLContext egl_context = EGL_NO_CONTEXT;
  PFNEGLMAKECURRENTPROC egl_make_current = nullptr;
  PFNEGLDESTROYCONTEXTPROC egl_destroy_context = nullptr;
  PFNEGLTERMINATEPROC egl_terminate = nullptr;
  PFNEGLGETPROCADDRESSPROC egl_get_proc = nullptr;
#endif

  Impl() = default;
  Impl(const Impl&) = delete;
  Impl& operator=(const Impl&) = delete;
  ~Impl() {
    if (osmesa != nullptr) OSMesaDestroyContext(osmesa);
#if PROPRIO_HAVE_EGL_HEADERS
    if (egl_context != EGL_NO_CONTEXT) {
      egl_make_current(egl_display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
      egl_destroy_context(egl_display, egl_context);
    }
    if (egl_display != EGL_NO_DISPLAY) release_egl_display(egl_display, egl_terminate);
#endif
    if (egl_lib != nullptr) dlclose(egl_lib);
  }
};

namespace {

// The colour buffer OSMesaMakeCurrent insists on; MuJoCo draws into its own framebuffer object.
constexpr int kOsMesaBufferSide = 16;

std::unique_ptr<GlContext::Impl> create_osmesa(std::string& why) {
  auto impl = std::make_unique<GlContext::Impl>();
  impl->backend = GlBackend::kOsMesa;
  impl->osmesa = OSMesaCreateContextExt(OSMESA_RGBA, 24, 8, 8, nullptr);
  if (impl->osmesa == nullptr) {
    why = "OSMesaCreateContextExt failed";
    return nullptr;
  }
  impl->osmesa_buffer.resize(std::size_t{4} * kOsMesaBufferSide * kOsMesaBufferSide);
  if (!OSMesaMakeCurrent(impl->osmesa, impl->osmesa_buffer.data(), GL_UNSIGNED_BYTE,
                         kOsMesaBufferSide, kOsMesaBufferSide)) {
    why = "OSMesaMakeCurrent failed";
    return nullptr;
  }
  return impl;
}

#if PROPRIO_HAVE_EGL_HEADERS
template <typename Fn>
Fn egl_symbol(void* lib, const char* name) {
  return reinterpret_cast<Fn>(dlsym(lib, name));
}

std::unique_ptr<GlContext::Impl> create_egl(std::string& why) {
  auto impl = std::make_unique<GlContext::Impl>();
  impl->backend = GlBackend::kEgl;
  impl->egl_lib = dlopen("libEGL.so.1", RTLD_NOW | RTLD_LOCAL);
  if (impl->egl_lib == nullptr) {
    why = "libEGL.so.1 not found";
    return nullptr;
  }
  void* lib = impl->egl_lib;
  auto get_display = egl_symbol<PFNEGLGETDISPLAYPROC>(lib, "eglGetDisplay");
  auto initialize = egl_symbol<PFNEGLINITIALIZEPROC>(lib, "eglInitialize");
  auto choose_config = egl_symbol<PFNEGLCHOOSECONFIGPROC>(lib, "eglChooseConfig");
  auto bind_api = egl_symbol<PFNEGLBINDAPIPROC>(lib, "eglBindAPI");
  auto create_context = egl_symbol<PFNEGLCREATECONTEXTPROC>(lib, "eglCreateContext");
  impl->egl_make_current = egl_symbol<PFNEGLMAKECURRENTPROC>(lib, "eglMakeCurrent");
  impl->egl_destroy_context = egl_symbol<PFNEGLDESTROYCONTEXTPROC>(lib, "eglDestroyContext");
  impl->egl_terminate = egl_symbol<PFNEGLTERMINATEPROC>(lib, "eglTerminate");
  impl->egl_get_proc = egl_symbol<PFNEGLGETPROCADDRESSPROC>(lib, "eglGetProcAddress");
  if (!get_display || !initialize || !choose_config || !bind_api || !create_context ||
      !impl->egl_make_current || !impl->egl_destroy_context || !impl->egl_terminate ||
      !impl->egl_get_proc) {
    why = "libEGL.so.1 lacks EGL 1.4 entry points";
    return nullptr;
  }
  auto platform_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
      impl->egl_get_proc("eglGetPlatformDisplayEXT"));
  auto query_devices =
      reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(impl->egl_get_proc("eglQueryDevicesEXT"));

  // Candidate displays, best first: a GPU device, Mesa's surfaceless platform, the default.
  std::vector<EGLDisplay> candidates;
  if (platform_display != nullptr && query_devices != nullptr) {
    EGLDeviceEXT devices[8];
    EGLint count = 0;
    if (query_devices(8, devices, &count)) {
      for (EGLint i = 0; i < count; ++i) {
        candidates.push_back(platform_display(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr));
      }
    }
  }
  if (platform_display != nullptr) {
    candidates.push_back(
        platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr));
  }
  candidates.push_back(get_display(EGL_DEFAULT_DISPLAY));

  for (EGLDisplay display : candidates) {
    EGLint major = 0;
    EGLint minor = 0;
    if (display == EGL_NO_DISPLAY || !initialize(display, &major, &minor)) continue;
    const EGLint attributes[] = {EGL_RED_SIZE,
                                 8,
                                 EGL_GREEN_SIZE,
                                 8,
                                 EGL_BLUE_SIZE,
                                 8,
                                 EGL_ALPHA_SIZE,
                                 8,
                                 EGL_DEPTH_SIZE,
                                 24,
                                 EGL_STENCIL_SIZE,
                                 8,
                                 EGL_SURFACE_TYPE,
                                 EGL_PBUFFER_BIT,
                                 EGL_RENDERABLE_TYPE,
                                 EGL_OPENGL_BIT,
                                 EGL_NONE};
    EGLConfig config = nullptr;
    EGLint configs = 0;
    if (!choose_config(display, attributes, &config, 1, &configs) || configs < 1 ||
        !bind_api(EGL_OPENGL_API)) {
      release_egl_display(display, impl->egl_terminate, false);
      continue;
    }
    EGLContext context = create_context(display, config, EGL_NO_CONTEXT, nullptr);
    if (context == EGL_NO_CONTEXT) {
      release_egl_display(display, impl->egl_terminate, false);
      continue;
    }
    if (!impl->egl_make_current(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) {
      impl->egl_destroy_context(display, context);
      release_egl_display(display, impl->egl_terminate, false);
      continue;
    }
    acquire_egl_display(display);
    impl->egl_display = display;
    impl->egl_context = context;
    return impl;
  }
  why = "no EGL display gave an OpenGL context without a surface";
  return nullptr;
}
#else
std::unique_ptr<GlContext::Impl> create_egl(std::string& why) {
  why = "built without EGL headers";
  return nullptr;
}
#endif

}  // namespace

GlContext::GlContext(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
GlContext::GlContext(GlContext&&) noexcept = default;
GlContext& GlContext::operator=(GlContext&&) noexcept = default;
GlContext::~GlContext() = default;

GlContext GlContext::create(GlBackend backend) {
  if (backend == GlBackend::kAuto) {
    // MuJoCo's own convention for choosing a headless backend.
    const char* env = std::getenv("MUJOCO_GL");
    const std::string_view name = env != nullptr ? env : "";
    if (name == "egl") backend = GlBackend::kEgl;
    if (name == "osmesa") backend = GlBackend::kOsMesa;
  }
  std::vector<GlBackend> order;
  if (backend == GlBackend::kAuto) {
    order = {GlBackend::kEgl, GlBackend::kOsMesa};
  } else {
    order = {backend};
  }
  std::string reasons;
  for (GlBackend candidate : order) {
    std::string why;
    auto impl = candidate == GlBackend::kEgl ? create_egl(why) : create_osmesa(why);
    if (impl) return GlContext(std::move(impl));
    if (!reasons.empty()) reasons += "; ";
    reasons += to_string(candidate);
    reasons += ": ";
    reasons += why;
  }
  throw Error("no OpenGL context for rendering (" + reasons + ")");
}

void GlContext::make_current() const {
  assert(impl_);
  bool ok = false;
  if (impl_->backend == GlBackend::kOsMesa) {
    ok = OSMesaMakeCurrent(impl_->osmesa, impl_->osmesa_buffer.data(), GL_UNSIGNED_BYTE,
                           kOsMesaBufferSide, kOsMesaBufferSide);
  } else {
#if PROPRIO_HAVE_EGL_HEADERS
    ok = impl_->egl_make_current(impl_->egl_display, EGL_NO_SURFACE, EGL_NO_SURFACE,
                                 impl_->egl_context);
#endif
  }
  if (!ok) throw Error("cannot make the " + to_string(impl_->backend) + " OpenGL context current");
}

GlBackend GlContext::backend() const { return impl_->backend; }

std::string GlContext::renderer_name() const {
  make_current();
  GetStringFn get_string = nullptr;
  if (impl_->backend == GlBackend::kOsMesa) {
    get_string = reinterpret_cast<GetStringFn>(OSMesaGetProcAddress("glGetString"));
  } else {
#if PROPRIO_HAVE_EGL_HEADERS
    get_string = reinterpret_cast<GetStringFn>(impl_->egl_get_proc("glGetString"));
#endif
  }
  if (get_string == nullptr) return "unknown";
  const unsigned char* name = get_string(kGlRenderer);
  return name != nullptr ? reinterpret_cast<const char*>(name) : "unknown";
}

}  // namespace proprio::sim
