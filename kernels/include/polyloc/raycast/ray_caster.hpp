// The RayCaster interface: batch ray casting against a polygon map. Backends (embree, and later
// bsp, grid2d, ...) stand side by side in raycast/. All calls take caller-owned plain buffers and
// allocate nothing per call; a call may run on several threads (see setThreads).
//
// Conventions, shared by every backend:
// - Ranges are metres along unit directions. A miss is +inf (or the window end when
//   CastOptions::miss_is_max_range), triangle kNoHit, label 0, normal (0,0,0).
// - Each ray only looks at [tmin, tmax]: a hit before tmin or after tmax is not seen. Scans use
//   the sensor's [range_min, range_max], optionally narrowed per beam by a ScanWindow (the beam
//   model asks only about an interval around the measured range, so traversal ends early).
// - Solids are closed and their triangles face outward. When the first surface a ray meets is a
//   back face, the ray started inside solid: with CastOptions::backface_is_solid (default) the
//   range is the window start (0 for an origin inside a wall), the triangle is the back face.
#pragma once

#include <polyloc/geometry/pose.hpp>
#include <polyloc/sensors/beams.hpp>

#include <cstdint>
#include <limits>
#include <span>

namespace polyloc {

inline constexpr uint32_t kNoHit = 0xFFFFFFFFu;

// Results, one entry per ray. Only `range` is required; null fields are not written.
struct HitBuffers {
  float* range = nullptr;
  uint32_t* triangle = nullptr;  // triangle index in the Mesh
  uint32_t* label = nullptr;     // Mesh::triangle_label of the hit
  float* nx = nullptr;           // unit geometric normal of the hit triangle, map frame
  float* ny = nullptr;
  float* nz = nullptr;
};

// Explicit rays in structure-of-arrays form. Directions must be unit length.
struct RayBatch {
  const float *ox = nullptr, *oy = nullptr, *oz = nullptr;
  const float *dx = nullptr, *dy = nullptr, *dz = nullptr;
  const float *tmin = nullptr, *tmax = nullptr;  // per ray; null means [0, +inf)
  size_t count = 0;
};

// Per-beam window for scans, shared by all poses (e.g. measured range +- k sigma).
struct ScanWindow {
  const float* tmin = nullptr;  // beams.size() entries each; null means the sensor's limits
  const float* tmax = nullptr;
};

struct CastOptions {
  bool backface_is_solid = true;    // first hit on a back face => ray starts inside solid
  bool miss_is_max_range = false;   // misses return the window end instead of +inf
};

class RayCaster {
 public:
  virtual ~RayCaster() = default;
  virtual const char* name() const = 0;

  // (a) poses.size() x beams.size() rays from map_T_sensor poses; result p * beams.size() + b.
  virtual void castScans(std::span<const Pose> sensor_poses, const BeamSet& beams,
                         const HitBuffers& out, const ScanWindow& window = {}) const = 0;
  // (b) explicit rays.
  virtual void castRays(const RayBatch& rays, const HitBuffers& out) const = 0;
  // (c) free[i] = 1 when point i is outside every solid and at least `clearance` metres from
  //     every surface, else 0.
  virtual void queryFree(std::span<const Eigen::Vector3f> points, float clearance,
                         uint8_t* free) const = 0;

  // Worker threads for the batch calls; 0 = all cores.
  virtual void setThreads(int threads) = 0;
  virtual int threads() const = 0;

  // Bytes this representation of the map holds (structure, tables, the copies it keeps): what a
  // backend costs in memory, as `bench maps` reports it.
  virtual size_t memoryBytes() const = 0;

  CastOptions options;
};

}  // namespace polyloc
