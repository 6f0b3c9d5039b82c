// octomap backend: an OctoMap OcTree (Debian's liboctomap) built from the mesh, with octomap's own
// castRay, as a RayCaster.
//
// Build: every triangle is sampled on a barycentric lattice at half the resolution and the voxels
// hit are set occupied (clamping maximum); everything else stays unknown, interiors of solids
// included (octomap models surfaces seen by sensors). Each occupied voxel remembers the first
// triangle that marked it, for triangle/label results.
//
// Rays: octomap's castRay (3D DDA) from the window start with ignoreUnknown = true, limited to the
// window and to the tree's bounding box. The range is where the ray enters the hit voxel (slab
// test against the voxel cube; the voxel centre's projection if the ray only touches it), so it
// is within one voxel diagonal of the surface, typically half a voxel early. An origin in an
// occupied voxel gives the window start. Normals: the face of the voxel the ray entered.
//
// queryFree: the point's voxel and every voxel whose cube comes closer than `clearance` are not
// occupied. Limitation: interiors are unknown, so a point deep inside a thick solid reads free,
// and a ray from inside one returns the distance to the solid's far surface.
#pragma once

#include <polyloc/map/mesh.hpp>
#include <polyloc/raycast/per_ray_caster.hpp>

#include <memory>

namespace polyloc {

struct OctomapOptions {
  double resolution = 0.05;  // m, leaf voxel size
  int threads = 0;           // 0 = all cores
};

class OctomapCaster final : public PerRayCaster {
 public:
  explicit OctomapCaster(const Mesh& mesh, const OctomapOptions& options = {});
  ~OctomapCaster() override;

  const char* name() const override { return "octomap"; }
  void queryFree(std::span<const Eigen::Vector3f> points, float clearance,
                 uint8_t* free) const override;

  size_t occupiedVoxels() const;
  bool occupied(const Eigen::Vector3f& p) const;
  size_t memoryBytes() const override;  // octomap's memoryUsage() plus the voxel -> triangle table

 protected:
  void traceRay(const HitBuffers& out, size_t i, const Eigen::Vector3f& o, const Eigen::Vector3f& d,
                float t0, float t1, const CastOptions& opt) const override;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace polyloc
