#include <polyloc/gpu/context.hpp>

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GLES3/gl31.h>

#include <fmt/core.h>

#include <cstring>
#include <map>
#include <mutex>
#include <sstream>
#include <utility>
#include <vector>

namespace polyloc {
namespace {

std::string eglErrorName(EGLint e) {
  switch (e) {
    case EGL_SUCCESS: return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS: return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT: return "EGL_BAD_CONTEXT";
    case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
    case EGL_BAD_PARAMETER: return "EGL_BAD_PARAMETER";
    case EGL_CONTEXT_LOST: return "EGL_CONTEXT_LOST";
  }
  return fmt::format("EGL error 0x{:x}", e);
}

bool hasExtension(const char* list, const char* name) {
  if (!list) return false;
  std::istringstream in(list);
  for (std::string w; in >> w;)
    if (w == name) return true;
  return false;
}

std::string glString(GLenum e) {
  const auto* s = reinterpret_cast<const char*>(glGetString(e));
  return s ? s : "";
}

// The display of one platform, or EGL_NO_DISPLAY when that platform is not there.
EGLDisplay openDisplay(const std::string& platform, const char* client_ext) {
  if (platform == "surfaceless") {
    if (!hasExtension(client_ext, "EGL_MESA_platform_surfaceless")) return EGL_NO_DISPLAY;
    return eglGetPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
  }
  if (platform == "device") {
    if (!hasExtension(client_ext, "EGL_EXT_platform_device")) return EGL_NO_DISPLAY;
    auto query = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
    if (!query) return EGL_NO_DISPLAY;
    EGLDeviceEXT devices[8];
    EGLint n = 0;
    if (!query(8, devices, &n) || n < 1) return EGL_NO_DISPLAY;
    return eglGetPlatformDisplay(EGL_PLATFORM_DEVICE_EXT, devices[0], nullptr);
  }
  if (platform == "default") return eglGetDisplay(EGL_DEFAULT_DISPLAY);
  throw GpuError("gpu: unknown EGL platform '" + platform + "' (surfaceless, device or default)");
}

// EGL hands every context of a platform the same display, and eglTerminate ends it for all of
// them: a display is terminated when its last context goes (casters of parallel relocalisation
// jobs come and go independently).
std::mutex display_mutex;
std::map<EGLDisplay, int> display_users;

bool initializeDisplay(EGLDisplay d, EGLint* major, EGLint* minor) {
  std::lock_guard<std::mutex> lock(display_mutex);
  if (!eglInitialize(d, major, minor)) return false;
  ++display_users[d];
  return true;
}

void releaseDisplay(EGLDisplay d) {
  std::lock_guard<std::mutex> lock(display_mutex);
  if (--display_users[d] > 0) return;
  display_users.erase(d);
  eglTerminate(d);
}

}  // namespace

// Cleanup here, not in ~GpuContext: it must also run when the constructor throws after
// eglInitialize.
struct GpuContext::Impl {
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLContext context = EGL_NO_CONTEXT;
  // What was current on the thread before makeCurrent(): release() puts it back.
  struct Previous {
    EGLDisplay display = EGL_NO_DISPLAY;
    EGLContext context = EGL_NO_CONTEXT;
    EGLSurface draw = EGL_NO_SURFACE, read = EGL_NO_SURFACE;
  } previous;

  void remember() {
    const EGLContext c = eglGetCurrentContext();
    if (c == context) return;  // already ours: keep what was before
    previous = {eglGetCurrentDisplay(), c, eglGetCurrentSurface(EGL_DRAW), eglGetCurrentSurface(EGL_READ)};
  }
  bool restore() {
    const Previous p = std::exchange(previous, {});
    if (p.context != EGL_NO_CONTEXT && p.display != EGL_NO_DISPLAY) return eglMakeCurrent(p.display, p.draw, p.read, p.context);
    return eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  }
  ~Impl() {
    if (display == EGL_NO_DISPLAY) return;
    if (context != EGL_NO_CONTEXT && eglGetCurrentContext() == context) restore();  // a caller's context stays
    if (context != EGL_NO_CONTEXT) eglDestroyContext(display, context);
    releaseDisplay(display);
  }
};

GpuContext::GpuContext(const GpuOptions& options) : impl_(std::make_unique<Impl>()) {
  const char* client_ext = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  std::vector<std::string> tried;
  std::istringstream list(options.platforms);
  for (std::string p; std::getline(list, p, ',');) {
    const EGLDisplay d = openDisplay(p, client_ext);
    EGLint major = 0, minor = 0;
    if (d == EGL_NO_DISPLAY) {
      tried.push_back(p + ": not offered by this EGL");
      continue;
    }
    if (!initializeDisplay(d, &major, &minor)) {
      tried.push_back(p + ": eglInitialize failed (" + eglErrorName(eglGetError()) + ")");
      continue;
    }
    impl_->display = d;
    info_.platform = p;
    break;
  }
  std::string why;
  for (const auto& t : tried) why += (why.empty() ? "" : "; ") + t;
  if (impl_->display == EGL_NO_DISPLAY)
    throw GpuError("gpu: no EGL display (" + (why.empty() ? std::string("no platform tried") : why) +
                   "); install Mesa's EGL (libegl-mesa0, libgl1-mesa-dri) or the GPU vendor's EGL");
  const EGLDisplay d = impl_->display;
  info_.egl_vendor = eglQueryString(d, EGL_VENDOR) ? eglQueryString(d, EGL_VENDOR) : "";
  info_.egl_version = eglQueryString(d, EGL_VERSION) ? eglQueryString(d, EGL_VERSION) : "";
  if (!eglBindAPI(EGL_OPENGL_ES_API)) throw GpuError("gpu: EGL cannot bind OpenGL ES (" + eglErrorName(eglGetError()) + ")");
  // No surface: a context without a default framebuffer (EGL_KHR_surfaceless_context).
  if (!hasExtension(eglQueryString(d, EGL_EXTENSIONS), "EGL_KHR_surfaceless_context"))
    throw GpuError("gpu: the EGL display has no EGL_KHR_surfaceless_context");
  const EGLint config_attribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_ES3_BIT, EGL_NONE};
  EGLConfig config = nullptr;
  EGLint configs = 0;
  const bool have_config = eglChooseConfig(d, config_attribs, &config, 1, &configs) && configs > 0;
  const EGLint ctx_attribs[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 1, EGL_NONE};
  impl_->context = eglCreateContext(d, have_config ? config : EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, ctx_attribs);
  if (impl_->context == EGL_NO_CONTEXT)
    throw GpuError("gpu: no OpenGL ES 3.1 context on " + info_.platform + " (" + eglErrorName(eglGetError()) +
                   "): compute shaders need GLES 3.1");
  makeCurrent();
  info_.vendor = glString(GL_VENDOR);
  info_.renderer = glString(GL_RENDERER);
  info_.version = glString(GL_VERSION);
  info_.glsl_version = glString(GL_SHADING_LANGUAGE_VERSION);
  for (const char* sw : {"llvmpipe", "softpipe", "swrast", "SwiftShader"})
    info_.software = info_.software || info_.renderer.find(sw) != std::string::npos;
  GLint64 ssbo = 0;
  glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &ssbo);
  info_.max_ssbo_bytes = ssbo;
  glGetIntegerv(GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS, &info_.max_ssbo_bindings);
  glGetIntegerv(GL_MAX_COMPUTE_WORK_GROUP_INVOCATIONS, &info_.max_work_group_invocations);
  for (GLuint k = 0; k < 3; ++k) {
    glGetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_SIZE, k, &info_.max_work_group_size[k]);
    glGetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_COUNT, k, &info_.max_work_group_count[k]);
  }
  check("reading the context's limits");
}

GpuContext::~GpuContext() = default;

void GpuContext::makeCurrent() const {
  impl_->remember();
  if (!eglMakeCurrent(impl_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, impl_->context))
    throw GpuError("gpu: cannot make the context current (" + eglErrorName(eglGetError()) + ")");
}

void GpuContext::release() const {
  if (!impl_->restore()) throw GpuError("gpu: cannot release the context (" + eglErrorName(eglGetError()) + ")");
}

bool GpuContext::current() const { return impl_->context != EGL_NO_CONTEXT && eglGetCurrentContext() == impl_->context; }

void GpuContext::check(const char* what) const {
  const GLenum e = glGetError();
  if (e == GL_NO_ERROR) return;
  constexpr GLenum kContextLost = 0x0507;  // GL_CONTEXT_LOST (GLES 3.2, KHR_robustness)
  const char* name = e == GL_OUT_OF_MEMORY ? "GL_OUT_OF_MEMORY (GPU memory exhausted)"
                     : e == kContextLost ? "GL_CONTEXT_LOST (the GPU was reset; make a new context)"
                     : e == GL_INVALID_OPERATION ? "GL_INVALID_OPERATION"
                     : e == GL_INVALID_VALUE ? "GL_INVALID_VALUE"
                     : e == GL_INVALID_ENUM ? "GL_INVALID_ENUM" : "GL error";
  throw GpuError(fmt::format("gpu: {} failed: {} (0x{:x})", what, name, e));
}

}  // namespace polyloc
