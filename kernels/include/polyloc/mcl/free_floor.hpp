// Where a robot can stand: the floor under a point (a ray cast down), free space around the body
// (queryFree with the robot radius at body height), and uniform sampling of such poses for
// global localisation. Where the map labels triangles "floor" (or "ramp"), only those count as
// floor, so table tops and shelf boards are not taken for floor. Sampled poses must also be
// enclosed (a wall in each of 8 horizontal directions), so a floor slab reaching beyond the outer
// walls does not put particles outside the building.
#pragma once

#include <polyloc/geometry/random.hpp>
#include <polyloc/map/mesh.hpp>
#include <polyloc/mcl/config.hpp>
#include <polyloc/mcl/localizer.hpp>
#include <polyloc/raycast/ray_caster.hpp>

#include <vector>

namespace polyloc {

struct BlockedResult {
  size_t zeroed = 0, ignored = 0;
};

class FreeFloor {
 public:
  FreeFloor(const RayCaster& caster, const Mesh& map, const MclConfig& config);

  // dof 3: puts each particle on the floor under it (z, roll, pitch from the floor, yaw kept),
  // looking from `step_up` above its base down to `max_drop` below. No floor found: unchanged.
  void snapToFloor(ParticleSet& s, double step_up = 0.3, double max_drop = 1.0) const;
  // Sets logw = -inf for particles whose body is in solid or closer than the clearance to a
  // surface, unless they hold more than max_mass of the weight: then the robot evidently stands
  // where the map says it cannot (a tight spot, furniture moved), and zeroing would leave only the
  // particles elsewhere. Returns how many were zeroed, or ignored.
  BlockedResult zeroBlocked(ParticleSet& s, double max_mass = 1.0) const;
  // n poses uniform over the free floor (yaw uniform; roll, pitch from the floor). May return
  // fewer when the map has (almost) no free floor.
  std::vector<Pose> sampleFree(size_t n, const CounterRng& rng, uint64_t stream) const;

 private:
  bool isFloorLabel(uint32_t label) const;
  // Per points[which[k]]: 1 when rays in 8 horizontal directions all hit the map (inside).
  std::vector<uint8_t> enclosed(const std::vector<Eigen::Vector3f>& points, const std::vector<size_t>& which) const;
  const RayCaster& caster_;
  const MclConfig& config_;
  Eigen::AlignedBox3f bounds_;
  std::vector<uint8_t> floor_label_;  // per label: counts as floor
};

}  // namespace polyloc
