// The GPU ray caster ("gpu" in raycast/factory.hpp): the RayCaster contract on compute shaders
// through a headless EGL context, and the beam model's per-pose sums (ScanScorer) computed
// beside the rays, so a weighing round reads back one float a particle. The map's BVH
// (gpu/bvh.hpp) is uploaded once; a batch is uploads, one dispatch (two when scoring) and one
// read-back, in chunks that fit the context's largest storage block.
//
// Any thread may call; calls are serialised and the context is made current for each. Errors
// are GpuError (no display, no compute, out of GPU memory, a lost context). With `fallback`
// set, a construction through makeCaster or a batch that fails warns once and answers from an
// Embree caster from then on: slower, never wrong.
#pragma once

#include <polyloc/gpu/context.hpp>
#include <polyloc/map/mesh.hpp>
#include <polyloc/raycast/ray_caster.hpp>
#include <polyloc/raycast/scan_score.hpp>

#include <functional>
#include <memory>
#include <string>

namespace polyloc {

struct GpuCasterOptions {
  GpuOptions context;             // EGL platforms to try
  size_t batch_rays = size_t(4) << 20;  // rays a dispatch at most (8 bytes each on the GPU)
  int max_leaf_size = 4;          // triangles a BVH leaf
  bool fallback = false;          // after a GPU error: warn, then answer from Embree
  int threads = 0;                // the fallback's threads (0 = all cores)
  std::function<void(const std::string&)> warn;  // null: stderr
  // Tests: the n-th batch (0-based) fails as if the context were lost; -1 never.
  int fail_batch = -1;
};

class GpuCaster final : public RayCaster, public ScanScorer {
 public:
  // Throws GpuError (no EGL display or GLES 3.1, buffers over the GPU's limits or memory) and
  // std::invalid_argument for a mesh without triangles.
  explicit GpuCaster(const Mesh& mesh, const GpuCasterOptions& options = {});
  ~GpuCaster() override;
  GpuCaster(const GpuCaster&) = delete;
  GpuCaster& operator=(const GpuCaster&) = delete;

  const char* name() const override { return "gpu"; }
  void castScans(std::span<const Pose> sensor_poses, const BeamSet& beams, const HitBuffers& out,
                 const ScanWindow& window = {}) const override;
  void castRays(const RayBatch& rays, const HitBuffers& out) const override;
  void queryFree(std::span<const Eigen::Vector3f> points, float clearance, uint8_t* free) const override;
  void scoreScans(std::span<const Pose> sensor_poses, const BeamSet& beams, const ScanWindow& window,
                  const ScanScoring& scoring, double* sums) const override;
  // The GPU takes no thread count; kept for the fallback and reported back.
  void setThreads(int threads) override;
  int threads() const override;
  // The BVH and the batch buffers on the GPU, plus the host copies kept for results.
  size_t memoryBytes() const override;

  const GpuInfo& info() const;
  bool fellBack() const;  // answering from Embree after a GPU error

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace polyloc
