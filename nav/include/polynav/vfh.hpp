// The Vector Field Histogram (Borenstein & Koren, IEEE T-RA 7(3), 1991), in the VFH+ form with a
// binary histogram and obstacles enlarged by the hull: the alternative to nearness_diagram.hpp,
// with the same inputs and command. Simpler and smoother in open space; ND does better in narrow,
// dense places. Stateless (no hysteresis between calls): one scan in, one command out.
//
//  1. sectors of sector_deg all around, sector k centred on k x sector (0: straight ahead);
//  2. each obstacle point within window_m of the hull has a nearness m = 1 - clearance / window_m
//     and, enlarged by the hull's half width + margin, covers the directions within
//     asin((width / 2 + margin) / range) of its bearing (a half turn when nearer than that): the
//     directions in which the driving robot's sides would pass it closer than the margin;
//  3. a sector is blocked where its centre is covered by a nearness above threshold;
//  4. per run of free sectors, candidates: the goal's direction when in the run; for a run wider
//     than wide_valley_deg, half of that in from each edge; else the run's middle. The candidate
//     nearest the goal wins (ties: the one nearest straight ahead);
//  5. steer() (local_command.hpp) with the speed scale 1 - the chosen sector's nearness. All
//     sectors blocked: v = w = 0, blocked.
#pragma once

#include <polynav/hull.hpp>
#include <polynav/local_command.hpp>
#include <polynav/polar_scan.hpp>

#include <Eigen/Core>

namespace polynav {

struct VfhConfig {
  double sector_deg = 5;        // histogram resolution, in (0, 90]; rounded to divide the full turn
  double window_m = 2.0;        // the active window: obstacles this far from the hull or farther are ignored; > 0
  double threshold = 0.25;      // nearness in [0, 1) that blocks: by default obstacles within 1.5 m of the hull
  double margin = 0.1;          // m kept between the hull's sides and an obstacle; >= 0
  double wide_valley_deg = 80;  // smax: a wider run of free sectors is wide; > 0
};

// Throws std::invalid_argument naming the field for a goal that is not finite, a bad scan, hull,
// config or limits.
LocalCommand vfh(const PolarScan& scan, const Eigen::Vector2d& goal_in_base, const RectHull& hull,
                 const VfhConfig& config = {}, const NdLimits& limits = {});

}  // namespace polynav
