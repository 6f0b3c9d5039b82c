// What the filter weighs particles with: which rig sensors (mcl.sensors) and which map
// representation (mcl.caster, a backend of raycast/factory.hpp). The Localizer keeps the exact
// mesh caster for the floor and free space; these choose only the measurement side, so that the
// map-representation benchmark and a grid-map deployment run the same filter.
//
//   std::unique_ptr<RayCaster> weigh = makeWeighingCaster(mesh, rig, cfg.mcl, threads);
//   Localizer loc(embree, mesh, rig, cfg.mcl, weigh.get());   // null: Embree weighs too
#pragma once

#include <polyloc/map/mesh.hpp>
#include <polyloc/mcl/config.hpp>
#include <polyloc/raycast/ray_caster.hpp>
#include <polyloc/sensors/rig.hpp>

#include <memory>
#include <vector>

namespace polyloc {

// Per rig sensor: 1 when the filter weighs it. Throws std::invalid_argument naming a sensor of
// mcl.sensors that the rig lacks, or (grid2d) one that is not a level planar scanner.
std::vector<uint8_t> weighedSensors(const Rig& rig, const MclConfig& config);

// mcl.caster_height, or the height of the lowest level scanner weighed (0.3 m without one).
double weighingSliceHeight(const Rig& rig, const MclConfig& config);

// The caster of mcl.caster built on the mesh, or null for "embree" (the caller's exact caster
// serves). threads as CasterOptions (< 0: the caller's arena). Throws what makeCaster throws.
std::unique_ptr<RayCaster> makeWeighingCaster(const Mesh& mesh, const Rig& rig, const MclConfig& config,
                                              int threads);

}  // namespace polyloc
