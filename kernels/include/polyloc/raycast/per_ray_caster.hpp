// The batch plumbing of backends that trace one ray at a time (bsp, grid2d, distance3d, octomap):
// poses x beams with the scan windows, explicit rays, the TBB arena of setThreads (cast_arena.hpp:
// < 0 runs in the caller's arena). A backend implements traceRay (one ray, window already
// merged) and queryFree.
#pragma once

#include <polyloc/raycast/cast_arena.hpp>
#include <polyloc/raycast/ray_caster.hpp>

#include <Eigen/Core>

namespace polyloc {

class PerRayCaster : public RayCaster {
 public:
  void castScans(std::span<const Pose> sensor_poses, const BeamSet& beams, const HitBuffers& out,
                 const ScanWindow& window = {}) const final;
  void castRays(const RayBatch& rays, const HitBuffers& out) const final;
  void setThreads(int threads) final { pool_.resize(threads); }
  int threads() const final { return pool_.threads(); }

 protected:
  explicit PerRayCaster(int threads) : pool_(threads) {}

  // One ray o + t d (unit d), t in [t0, t1] (may be empty: t0 > t1); writes entry i of out.
  virtual void traceRay(const HitBuffers& out, size_t i, const Eigen::Vector3f& o,
                        const Eigen::Vector3f& d, float t0, float t1, const CastOptions& opt) const = 0;

  // Writes one result; a miss (range +inf) becomes the window end with miss_is_max_range, and
  // gets triangle kNoHit, label 0, normal 0 whatever was passed.
  static void writeHit(const HitBuffers& out, size_t i, float range, float t1, uint32_t triangle,
                       uint32_t label, const Eigen::Vector3f& normal, const CastOptions& opt);

  // body(begin, end) over [0, n) in chunks of at least `grain`, inside the arena.
  template <class F>
  void parallel(size_t n, size_t grain, F&& body) const {
    pool_.parallel(n, grain, std::forward<F>(body));
  }

 private:
  CastArena pool_;
};

}  // namespace polyloc
