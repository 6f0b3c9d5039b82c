// A headless OpenGL ES 3.1 context through EGL, for compute shaders: no display server, no
// window. It tries EGL_MESA_platform_surfaceless (Mesa: llvmpipe on a CPU, or the GPU's Mesa
// driver), then EGL_EXT_platform_device (vendor drivers, e.g. NVIDIA), then the default display.
// Made once per process part that computes; current on the thread that made it (makeCurrent()
// to move it). Errors are GpuError naming what is missing.
//
//   GpuContext gpu;                         // throws GpuError: no EGL, no GLES 3.1, ...
//   GpuInfo info = gpu.info();              // vendor, renderer, version, limits
#pragma once

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>

namespace polyloc {

class GpuError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct GpuInfo {
  std::string platform;   // "surfaceless", "device" or "default"
  std::string egl_vendor, egl_version;
  std::string vendor, renderer, version, glsl_version;  // GL_VENDOR, GL_RENDERER, ...
  bool software = false;  // llvmpipe / softpipe / swrast: a CPU, not a GPU
  int64_t max_ssbo_bytes = 0;          // GL_MAX_SHADER_STORAGE_BLOCK_SIZE
  int max_ssbo_bindings = 0;           // GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS
  int max_work_group_invocations = 0;  // GL_MAX_COMPUTE_WORK_GROUP_INVOCATIONS
  int max_work_group_size[3] = {0, 0, 0};
  int max_work_group_count[3] = {0, 0, 0};
};

struct GpuOptions {
  // Which EGL platforms to try, in order: "surfaceless", "device", "default".
  std::string platforms = "surfaceless,device,default";
};

class GpuContext {
 public:
  explicit GpuContext(const GpuOptions& options = {});
  ~GpuContext();
  GpuContext(const GpuContext&) = delete;
  GpuContext& operator=(const GpuContext&) = delete;

  const GpuInfo& info() const { return info_; }
  // makeCurrent() remembers the context that was current on this thread (a caller's own GL
  // work); release() makes that one current again (or none), so that polyloc never unbinds it.
  void makeCurrent() const;  // throws GpuError when the context is lost
  void release() const;      // then current on no thread of ours (another thread may make it current)
  bool current() const;      // current on the calling thread
  // Throws GpuError naming `what` and the GL error, if one is pending.
  void check(const char* what) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  GpuInfo info_;
};

}  // namespace polyloc
