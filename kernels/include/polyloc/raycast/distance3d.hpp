// distance3d backend: rays and clearance from a 3D Euclidean distance field (map/distance_field),
// the representation of likelihood-field weighting, as a RayCaster.
//
// Rays: sphere tracing. From the window start the ray steps by the field's distance (a safe step:
// the field never reads below the true distance far from surfaces, see distance_field.hpp) until
// the distance drops below hit_epsilon (default half a node spacing h); a Newton step on the
// field's slope along the ray then moves the hit onto the zero crossing (exact in front of a
// plane; the cap keeps it within 2 epsilon). Accuracy: the trilinear field reads up to ~h/2 on an
// axis-aligned surface between nodes, so ranges are within about h/2 (worst case near edges and
// corners about h); a wall thinner than h may be missed at grazing angles. Rays that leave the
// grid are misses (the grid spans the mesh plus padding). Normals: the field's gradient; the
// field knows no triangles, so triangle is kNoHit and label 0 for every hit.
//
// Inside solids: the field is unsigned, so at build the nodes inside closed solids are marked by
// the winding number of the mesh along each grid row of nodes (one line per row, nudged off the
// node lattice so it misses edges). A ray starting at an inside node (nearest node) reads range =
// window start (CastOptions::backface_is_solid), and queryFree says not free there. Needs closed,
// outward-facing meshes; on others inside marks are meaningless (set mark_inside = false).
#pragma once

#include <polyloc/map/distance_field.hpp>
#include <polyloc/map/mesh.hpp>
#include <polyloc/raycast/per_ray_caster.hpp>

#include <memory>

namespace polyloc {

struct Distance3dOptions {
  DistanceFieldConfig field{};  // resolution 0.05 m, max_distance 1 m, padding 1 m
  double hit_epsilon = 0;       // m; 0 = half the resolution
  int max_steps = 1000;         // per ray; a ray still marching then is a miss
  bool mark_inside = true;      // mark nodes inside solids (point-in-solid, rays from inside)
  int threads = 0;              // 0 = all cores
};

class Distance3dCaster final : public PerRayCaster {
 public:
  explicit Distance3dCaster(const Mesh& mesh, const Distance3dOptions& options = {});
  ~Distance3dCaster() override;

  const char* name() const override { return "distance3d"; }
  // free = outside solid (node inside mark) and field distance >= clearance (clearance above the
  // field's max_distance reads as max_distance: build with max_distance >= the clearances used).
  void queryFree(std::span<const Eigen::Vector3f> points, float clearance,
                 uint8_t* free) const override;

  const DistanceField3D& field() const;
  bool inside(const Eigen::Vector3f& p) const;  // nearest node is inside a solid
  size_t memoryBytes() const override;                 // field plus inside marks

 protected:
  void traceRay(const HitBuffers& out, size_t i, const Eigen::Vector3f& o, const Eigen::Vector3f& d,
                float t0, float t1, const CastOptions& opt) const override;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace polyloc
