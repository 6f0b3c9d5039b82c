// Embree: one scene per map (BVH built once), packets of 16 for the beams of one pose,
// TBB over poses in an arena of the configured size, nothing allocated in the hot path.
#pragma once

#include <polyloc/map/mesh.hpp>
#include <polyloc/raycast/ray_caster.hpp>

#include <memory>
#include <string>

namespace polyloc {

struct EmbreeOptions {
  int threads = 0;               // 0 = all cores; < 0 = no arena of its own: the caller's
                                 // (batch relocalisation runs many recordings in one arena)
  bool robust = true;            // watertight traversal: no rays slip through shared edges
  bool high_quality_bvh = true;  // slower build (SAH with spatial splits), faster rays
  std::string device_config;     // passed to rtcNewDevice, e.g. "verbose=1" or "isa=avx2"
};

class EmbreeCaster final : public RayCaster {
 public:
  explicit EmbreeCaster(const Mesh& mesh, const EmbreeOptions& options = {});
  ~EmbreeCaster() override;
  EmbreeCaster(const EmbreeCaster&) = delete;
  EmbreeCaster& operator=(const EmbreeCaster&) = delete;

  const char* name() const override { return "embree"; }
  void castScans(std::span<const Pose> sensor_poses, const BeamSet& beams, const HitBuffers& out,
                 const ScanWindow& window = {}) const override;
  void castRays(const RayBatch& rays, const HitBuffers& out) const override;
  void queryFree(std::span<const Eigen::Vector3f> points, float clearance,
                 uint8_t* free) const override;
  void setThreads(int threads) override;
  int threads() const override;
  // What Embree's device allocated (BVH, buffers; its memory monitor) plus the mesh copy and
  // normals kept for results.
  size_t memoryBytes() const override;

  // The plain reference: one rtcIntersect1 per ray over the same rays as castScans, same
  // threading and options, no windows, only ranges. Kept for the benchmark that holds the
  // packet path to account.
  void castScansSingle(std::span<const Pose> sensor_poses, const BeamSet& beams, float* range) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace polyloc
