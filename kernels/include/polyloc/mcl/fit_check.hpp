// Is the estimate lost, or do people and clutter just hide the map? After each round the beams
// of the round's frames are cast from the estimate (full range) and each valid reading is
// compared with the surface the map puts on its ray: explained (within tolerance), shorter
// (something in front of the map: a person, a chair, a box — the map is not contradicted) or
// longer (the beam went through where the map has a wall: no unexpected obstacle does that, a
// wrong pose does). A round whose share of longer beams exceeds mcl.fit.max_seen_through
// contradicts the estimate; only such rounds count towards injection and sensor resetting.
// Real maps are a few centimetres off and have holes, so the tolerance is generous; at a wrong
// place half the beams typically see through.
// A longer beam whose end point lies on another surface of its ray (within tolerance) went past
// something the map holds that is not there now: a door open now, a person the mapping run saw
// (a grid of end points keeps every one). When at least past_share of the longer beams of the
// scans given do so (the localizer gives one frame at a time), they are counted apart
// (past_surface), not as seen through: at the right place in freiburg-079's end-point map up to
// 45 % of the beams went past such things, 93-100 % of them ending on a wall behind, and the
// resets that set off put the track 19 m off. At a wrong place a beam through a wall ends on
// another surface only by chance (a third to a half of them in that cluttered map), so the
// longer beams stay seen through there.
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
  size_t longer = 0;     // measured > expected + tolerance, ending where the map has no surface: seen through
  size_t past_surface = 0;  // measured > expected + tolerance, ending on a surface further along the ray
  double seenThrough() const { return beams ? double(longer) / double(beams) : 0.0; }
  double explainedShare() const { return beams ? double(explained) / double(beams) : 0.0; }
};

// scans as refinePose takes them; at most beams_per_scan valid beams of each, evenly spread
// (0: all). past_share > 1: every longer beam is seen through (no second cast). Casts on the
// caller's threads.
ScanFit checkFit(const RayCaster& caster, const Rig& rig, std::span<const RefineScan> scans, const Pose& map_T_base,
                 double tolerance, size_t beams_per_scan, double past_share = 2.0);

}  // namespace polyloc
