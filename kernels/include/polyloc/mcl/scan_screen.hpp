// Scan screening for global localisation: every pose of a fixed candidate set (free floor
// positions x evenly spaced headings) scored by how well the round's level scanner beams land on
// the map's walls, the best distinct ones handed to the hypotheses' refinement. The particle
// cloud alone leaves the truth uncovered on a building-sized real map: 20,000 particles over
// 2,000 m2 put about 0.2 particles within the refinement's basin (0.5 m, 15 deg) of the true
// pose, and a particle that far off weighs too little to be among the modes refined (CARMEN
// logs: in most failed global trials no mode was near the truth in any round).
//
// The score is the likelihood-field idea (Thrun et al., Probabilistic Robotics 6.4) on a 2D
// distance transform of the map sliced at the scanner height: per beam the endpoint's distance
// to the nearest wall, truncated, squared and summed: one table lookup per beam and pose, no
// ray cast, so every candidate can be scored each round.
#pragma once

#include <polyloc/geometry/pose.hpp>
#include <polyloc/map/mesh.hpp>
#include <polyloc/mcl/config.hpp>
#include <polyloc/mcl/refine.hpp>
#include <polyloc/sensors/rig.hpp>

#include <cstddef>
#include <memory>
#include <span>
#include <vector>

namespace polyloc {

class ScanScreen {
 public:
  // The map sliced at `height` (m, the scanner's) as grid2d does, at config.resolution (coarser
  // where that would take more than 2e7 cells: maps over about 0.2 km2). Throws what
  // Grid2dCaster throws for a map without triangles.
  ScanScreen(const Mesh& map, double height, const ScanScreenConfig& config);
  ~ScanScreen();

  // Up to config.keep best-scoring candidates for the scans (as refinePose takes them; only level
  // scanners count), best first, each at least `separation` (m) or `separation_yaw` (rad) from
  // every better one; empty when no scan has a level beam. Deterministic: ties keep the lower
  // candidate index.
  // Candidates: `positions` (map_T_base; their headings ignored) x config.headings.
  // heading_window > 0: only headings within it (rad) of each position's own heading.
  std::vector<Pose> best(const Rig& rig, std::span<const RefineScan> scans, std::span<const Pose> positions,
                         double separation, double separation_yaw, double heading_window = 0) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace polyloc
