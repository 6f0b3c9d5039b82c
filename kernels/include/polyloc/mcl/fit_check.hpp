// Is the estimate lost, or do people and clutter just hide the map? After each round the beams
// of the round's frames are cast from the estimate (full range) and each valid reading is
// compared with the surface the map puts on its ray: explained (within tolerance), shorter
// (something in front of the map: a person, a chair, a box — the map is not contradicted) or
// longer (the beam went through where the map has a wall: no unexpected obstacle does that, a
// wrong pose does). A round whose share of longer beams exceeds mcl.fit.max_seen_through
// contradicts the estimate; only such rounds count towards injection and sensor resetting.
// Real maps are a few centimetres off and have holes, so the tolerance is generous; at a wrong
// place half the beams typically see through.
#pragma once

#include <polyloc/geometry/pose.hpp>
#include <polyloc/mcl/refine.hpp>
#include <polyloc/raycast/ray_caster.hpp>
#include <polyloc/sensors/rig.hpp>

#include <cstddef>
#include <span>

namespace polyloc {

struct ScanFit {
  size_t beams = 0;      // valid readings compared
  size_t explained = 0;  // |measured - expected| <= tolerance
  size_t shorter = 0;    // measured < expected - tolerance (or the map has nothing on the ray)
  size_t longer = 0;     // measured > expected + tolerance: seen through the map
  double seenThrough() const { return beams ? double(longer) / double(beams) : 0.0; }
  double explainedShare() const { return beams ? double(explained) / double(beams) : 0.0; }
};

// scans as refinePose takes them; at most beams_per_scan valid beams of each, evenly spread
// (0: all). Casts on the caller's threads.
ScanFit checkFit(const RayCaster& caster, const Rig& rig, std::span<const RefineScan> scans, const Pose& map_T_base,
                 double tolerance, size_t beams_per_scan);

}  // namespace polyloc
