// The headless GPU context and compute shaders, on whatever EGL offers (Mesa llvmpipe in CI):
// a shader computes known values, bad shaders, uniforms and oversized buffers are GpuErrors.
#ifdef POLYLOC_HAVE_GPU
#include <polyloc/gpu/compute.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <vector>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_gpu_compute {

using namespace polyloc;


GpuContext& gpu() {
  static GpuContext context;  // one per process: creating EGL contexts is slow on llvmpipe
  context.makeCurrent();
  return context;
}

const char* kAffine = R"(#version 310 es
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer In { float x[]; };
layout(std430, binding = 1) writeonly buffer Out { float y[]; };
uniform float scale;
uniform uint count;
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i < count) y[i] = scale * x[i] * x[i] + 1.0;
}
)";


TEST(GpuContext, HeadlessContextReportsGles31AndLimits) {
  const GpuInfo& i = gpu().info();
  EXPECT_FALSE(i.platform.empty());
  EXPECT_FALSE(i.renderer.empty());
  EXPECT_NE(i.version.find("OpenGL ES 3."), std::string::npos) << i.version;
  EXPECT_GE(i.max_ssbo_bindings, 4);  // GLES 3.1 minimum: 4 per compute stage
  EXPECT_GE(i.max_ssbo_bytes, int64_t{1} << 24);
  EXPECT_GE(i.max_work_group_invocations, 128);
  EXPECT_GE(i.max_work_group_count[0], 65535);
}

TEST(GpuCompute, ShaderComputesKnownValues) {
  ComputeProgram p(gpu(), "affine", kAffine);
  const uint32_t n = 1000;  // not a multiple of the work group: the tail is guarded
  std::vector<float> x(n), y(n + 8, -7.f);
  std::iota(x.begin(), x.end(), -500.f);
  StorageBuffer in(gpu(), n * sizeof(float)), out(gpu(), (n + 8) * sizeof(float));
  in.upload(x.data(), n * sizeof(float));
  out.upload(y.data(), y.size() * sizeof(float));
  in.bind(0), out.bind(1);
  p.use();
  p.set("scale", 0.5f);
  p.set("count", n);
  p.dispatch((n + 63) / 64);
  out.download(y.data(), y.size() * sizeof(float));
  for (uint32_t i = 0; i < n; ++i) ASSERT_FLOAT_EQ(y[i], 0.5f * x[i] * x[i] + 1.f) << i;
  for (uint32_t i = n; i < n + 8; ++i) EXPECT_EQ(y[i], -7.f) << "written past count at " << i;
}

TEST(GpuCompute, ErrorsNameWhatWentWrong) {
  try {
    ComputeProgram bad(gpu(), "broken", "#version 310 es\nlayout(local_size_x = 1) in;\nvoid main() { nope(); }\n");
    FAIL() << "a shader that does not compile was accepted";
  } catch (const GpuError& e) {
    EXPECT_NE(std::string(e.what()).find("'broken' does not compile"), std::string::npos) << e.what();
  }
  ComputeProgram p(gpu(), "affine", kAffine);
  p.use();
  EXPECT_THROW(p.set("no_such_uniform", 1.f), GpuError);
  EXPECT_THROW(StorageBuffer(gpu(), size_t(gpu().info().max_ssbo_bytes) + 1), GpuError);
  StorageBuffer small(gpu(), 16);
  float v[8] = {};
  EXPECT_THROW(small.upload(v, sizeof(v)), GpuError);
  EXPECT_THROW(small.download(v, sizeof(v)), GpuError);
  EXPECT_THROW(GpuContext(GpuOptions{"nonsense"}), GpuError);
}
#endif

}  // namespace polyloc::t_gpu_compute
