// The robot's height and tilt from the floor under it: rays cast down at the contact points
// (footprint corners) find the walkable surface (labels floor, ramp), a smooth random height
// field adds unevenness, and a least-squares plane through the contact heights gives z, roll and
// pitch. Ramps and raised platforms come from the map this way; nothing is special-cased.
#pragma once

#include <polyloc/geometry/pose.hpp>
#include <polyloc/map/mesh.hpp>
#include <polyloc/raycast/ray_caster.hpp>
#include <polyloc/sim/trajectory.hpp>

#include <span>
#include <string>
#include <vector>

namespace polyloc {

struct FloorSpec {
  bool follow = true;          // z, roll, pitch from the map (false: flat at z = 0 + unevenness)
  double unevenness = 0.0;     // m, RMS of the smooth height field added to the floor (0 = off)
  double wavelength = 1.0;     // m, mean wavelength of the height field
  double probe_height = 1.5;   // m, the downward rays start at this z (above every walkable floor)
  std::vector<std::string> labels{"floor", "ramp"};  // surfaces the robot stands on
  std::vector<Eigen::Vector2d> contact_points;       // base frame; empty = the robot's
};

class FloorModel {
 public:
  // The caster must treat back faces as surfaces (CastOptions::backface_is_solid = false) so
  // that probes can pass through furniture above the floor.
  FloorModel(const FloorSpec& spec, const RayCaster& caster, const Mesh& mesh,
             std::vector<Eigen::Vector2d> contacts, uint64_t seed);

  // map_T_base for planar states (batched: one ray cast call per pass over all contacts).
  void poses(std::span<const PlanarState> states, Pose* out) const;
  Pose pose(const PlanarState& s) const;
  double unevenness(double x, double y) const;  // m
  // Walkable floor height under (x, y), or NaN when there is none below probe_height.
  double floorHeight(double x, double y) const;
  uint64_t misses() const { return misses_; }  // contact probes that found no floor

 private:
  void heights(std::span<const Eigen::Vector2d> xy, double* z) const;

  FloorSpec spec_;
  const RayCaster& caster_;
  std::vector<Eigen::Vector2d> contacts_;
  std::vector<bool> walkable_;  // per label id
  struct Wave {
    double kx, ky, phase;
  };
  std::vector<Wave> waves_;
  mutable uint64_t misses_ = 0;
};

}  // namespace polyloc
