#include <polyloc/mcl/reset_policy.hpp>

namespace polyloc {

ResetPolicy::ResetPolicy(const MclConfig& config)
    : global_coarse_rounds_(config.global_coarse_rounds), global_max_coarse_rounds_(config.global_max_coarse_rounds),
      relocalize_rounds_(config.relocalize_rounds), relocalize_jump_(config.relocalize_jump) {}

void ResetPolicy::reset() {
  // Started at a given pose: no global phase to protect from another reset (a kidnapping five
  // rounds after the start is recovered as one after fifty).
  rounds_since_reset_ = 2 * relocalize_rounds_;
  low_rounds_ = 0;
  coarse_left_ = 0;
}

void ResetPolicy::startGlobal() {
  coarse_left_ = global_coarse_rounds_;
  global_rounds_ = 0;
  rounds_since_reset_ = low_rounds_ = 0;
}

bool ResetPolicy::beginRound() {
  const bool global_round = coarse_left_ > 0;  // one of the rounds right after a uniform prior
  if (coarse_left_ > 0) --coarse_left_;
  if (global_round) ++global_rounds_;
  return global_round;
}

bool ResetPolicy::jumped(bool was_tracking, bool global_round, const Pose& now, const Pose& predicted) const {
  return relocalize_jump_ > 0 && was_tracking && !global_round &&
         (now.translation() - predicted.translation()).head<2>().norm() > relocalize_jump_;
}

void ResetPolicy::extendGlobal(bool global_round, bool contradicted, bool refined, bool ambiguous) {
  // The global phase ends on a confirmed estimate only: refined against the mesh, not
  // contradicted by the fit check, and the only place the refined modes found. Committing after
  // a fixed number of rounds handed buildings of similar rooms, and corridors seen both ways,
  // to the first place that fitted a little better (real logs).
  if (global_round && coarse_left_ == 0 && (contradicted || !refined || ambiguous) &&
      global_rounds_ < global_max_coarse_rounds_)
    coarse_left_ = 1;
}

bool ResetPolicy::relocalize(bool jumped, bool contradicted, bool refined) {
  // Sensor resetting: for relocalize_rounds rounds in a row the scans have contradicted the
  // estimate (beams seen through the map's walls: fit_check.hpp), the filter tracks a wrong
  // place (kidnapped, or diverged). Injection alone draws too few particles near the truth in
  // a building-sized map; a fresh uniform prior does not. The likelihood level alone does not
  // decide: it drops with map error, people and clutter while the track is fine (real logs,
  // docs/benchmarks.md), and a round whose estimate the scans pin against the mesh (refine
  // accepted) is not lost either.
  // A round counts only when the refinement could not pin the estimate either: at the right
  // place a quarter of the beams may see through for minutes on end where the map holds a door
  // that is open now (a map made over a long run: freiburg-079), and the scans still fit it.
  // A jump into a contradicted place that local recovery could not explain (the localiser clears
  // `jumped` when a place near the prediction fits: a sharp turn on bad odometry throws the
  // cloud off for a round, and a global reset then cost 27 m for five rounds on a real log) is
  // a kidnapping: the global search starts at once.
  const bool low = (contradicted && !refined) || jumped;
  low_rounds_ = low ? low_rounds_ + 1 : 0;
  ++rounds_since_reset_;
  return jumped ||
         (relocalize_rounds_ > 0 && low_rounds_ >= relocalize_rounds_ && rounds_since_reset_ > 2 * relocalize_rounds_);
}

}  // namespace polyloc
