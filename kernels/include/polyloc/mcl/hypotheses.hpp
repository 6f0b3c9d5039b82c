// Global hypotheses: the best distinct modes of a spread particle cloud, refined against the mesh
// (refine.hpp) and planted back as tight clouds. Used by the Localizer while it weighs coarse
// (after a uniform prior): a prior of 100,000 particles over a building has next to none within
// centimetres of the truth, so the fine weighting that follows would choose between modes by the
// luck of their best particle. Refined, each mode is judged by how well the place itself fits.
#pragma once

#include <polyloc/geometry/pose.hpp>
#include <polyloc/geometry/random.hpp>
#include <polyloc/mcl/config.hpp>
#include <polyloc/mcl/localizer.hpp>
#include <polyloc/mcl/refine.hpp>
#include <polyloc/raycast/ray_caster.hpp>
#include <polyloc/sensors/rig.hpp>

#include <span>
#include <vector>

namespace polyloc {

struct Hypothesis {
  Pose pose;                // refined map_T_base
  double inlier_ratio = 0;  // of the refinement's beams
  double rms = 0;           // m, of the inliers
};

// Indices of up to k particles, best weight first, each at least `separation` (m) or
// `separation_yaw` (rad) away from every better one taken. Particles of weight zero are skipped.
std::vector<size_t> distinctModes(const ParticleSet& s, size_t k, double separation, double separation_yaw);

// Refines the modes (distinctModes with the config's count and separation), then the `extra`
// start poses (scan_screen.hpp), in 3 DoF against the scans and keeps those that fit: inlier ratio >= min_inlier_ratio and within ratio_margin of the
// best. `base` supplies the Gauss-Newton settings (huber, max_correspondence, iterations).
std::vector<Hypothesis> refineModes(const RayCaster& caster, const Rig& rig, std::span<const RefineScan> scans,
                                    const ParticleSet& s, const GlobalHypotheses& config, const RefineConfig& base,
                                    std::span<const Pose> extra = {});

// Replaces the lightest particles (at most half of the set) by `config.particles` per hypothesis,
// drawn around it (spread_xy, spread_yaw; z, roll, pitch as refined), each with the weight of the
// heaviest particle. Returns the number planted. logw is left unnormalised.
size_t plantHypotheses(ParticleSet& s, std::span<const Hypothesis> hyps, const GlobalHypotheses& config,
                       const CounterRng& rng, uint64_t stream);

// A place the global rounds found, carried from round to round by odometry and refined again in
// each round (GlobalSearch passes the carried poses as starts). The best tracked place, not the
// dominant particle cluster, is the estimate while the global phase searches: the coarse
// weighting cannot tell a place where 0.95 of a scan's beams lie on walls from one with 0.85
// (CARMEN aces: the truth refined best in round 10 while the cluster sat on a corridor end 9 m
// away), and along a corridor one round's best fit is chance, while the place that keeps fitting
// as the robot moves is the truth. The evidence is a sum over rounds, as a log-likelihood ratio
// is in a sequential test: each round a place falls behind by the shortfall of its inlier share
// against the round's best fit.
struct TrackedPlace {
  Pose pose;            // map_T_base
  double deficit = 0;   // summed shortfall of evidence() against each round's best (a round that missed it: the lead)
  size_t rounds = 0;    // rounds that found it
  size_t missed = 0;    // rounds in a row that did not (carried by odometry meanwhile)
};

// Two poses are one place within 1 m and 0.5 rad (the global rounds' places, the count of
// distinct refined modes).
bool samePlace(const Pose& a, const Pose& b);

// One round: every place moved by `moved` (the base's motion since the last round, base frame);
// each hypothesis matched to the first place within 1 m and 0.5 rad, a place found takes the
// pose of its best match and falls behind by (round's best evidence - its own); a place not
// found falls behind by `lead`. A hypothesis matching no place is a newcomer: it joins `lead`
// behind the leader (it has no earlier rounds; it must out-fit the leader to contend). Places
// more than `drop` behind the leader are dropped (a place missed for a round or two, by people in
// front of the scanner, is not: its deficit says how much that costs it).
void trackPlaces(std::vector<TrackedPlace>& places, std::span<const Hypothesis> hyps, const Pose& moved, double lead,
                 double drop, double sigma = 0);

// A round's evidence for a place: its inlier share times the Gaussian likelihood (std `sigma`) of
// its inliers' RMS residual (sigma <= 0: the share alone). 60 beams a scan give shares in steps of
// 1/60: along a corridor the true place and its look-alikes 20 m on tie for ten rounds, while
// their residuals differ (2-3 cm on the walls that are there, 5-6 cm on walls that are similar).
double evidence(const Hypothesis& h, double sigma);

// The leader: the place of the smallest deficit (the first of equals), null when there is none.
const TrackedPlace* bestPlace(std::span<const TrackedPlace> places);

// Another place than the leader less than `lead` behind it: the rounds so far cannot tell them apart.
bool contested(std::span<const TrackedPlace> places, double lead);

}  // namespace polyloc
