// The global search for places (docs/localization.md, "Global localisation"): each global round
// the cloud's best distinct modes and the best candidates of the scan screen (scan_screen.hpp, at
// positions drawn once over the free floor) are refined against the round's frames
// (hypotheses.hpp); those whose beams see through the map are dropped; the rest are matched to
// the places of earlier rounds, whose best is the estimate while the search goes on. Local
// recovery asks the same question near a prediction (fittingModes). The Localizer composes it;
// it owns nothing of the filter but the screen and the places it tracks.
#pragma once

#include <polyloc/geometry/pose.hpp>
#include <polyloc/map/mesh.hpp>
#include <polyloc/mcl/config.hpp>
#include <polyloc/mcl/free_floor.hpp>
#include <polyloc/mcl/hypotheses.hpp>
#include <polyloc/mcl/particles.hpp>
#include <polyloc/mcl/refine.hpp>
#include <polyloc/raycast/ray_caster.hpp>
#include <polyloc/sensors/rig.hpp>

#include <memory>
#include <optional>
#include <span>
#include <vector>

namespace polyloc {

class ScanScreen;

struct GlobalRound {
  std::vector<Hypothesis> hypotheses;  // the places that fit this round, best first
  bool ambiguous = false;              // another place is less than hypotheses.lead behind the best: the robot must move on
  std::optional<Pose> best;            // the best place tracked over the rounds (at this round's odometry)
};

class GlobalSearch {
 public:
  // `caster` refines (mcl.caster), `exact` checks the fit (the mesh); both, the rig and the config
  // must outlive the search. The screen is built when a weighed level scanner sees the map and
  // hypotheses.count, hypotheses.screen.keep and global_particles are all positive.
  GlobalSearch(const RayCaster& caster, const RayCaster& exact, const Mesh& map, const Rig& rig, const MclConfig& config);
  ~GlobalSearch();

  // A new uniform prior: the places of earlier rounds no longer count.
  void restart() { tracked_.clear(); }

  // One global round on `scans` (relative to `odom`, the odometry the particles are at). The
  // screen's positions are drawn from `floor` at the first round (stream `screen_stream` of `rng`).
  GlobalRound round(std::span<const RefineScan> scans, const ParticleSet& ps, const Pose& odom, const FreeFloor& floor,
                    const CounterRng& rng, uint64_t screen_stream);

  // The cloud's modes and the best screened candidates at `positions` (every heading within
  // `heading_window` of theirs; 0: every heading), refined; those whose beams see through the
  // map's walls are wrong places, however many of their beams found a wall. past_share as in
  // checkFit: local recovery near the track passes mcl.fit.past_share; the global round holds a
  // place to every beam (above 1), as a far place needs the stronger evidence.
  // `also`: more start poses, refined as they are (the tracked places).
  std::vector<Hypothesis> fittingModes(std::span<const RefineScan> scans, const ParticleSet& ps,
                                       std::span<const Pose> positions, double heading_window = 0,
                                       double past_share = 2.0, std::span<const Pose> also = {}) const;

  size_t trackedPlaces() const { return tracked_.size(); }

 private:
  const RayCaster& caster_;
  const RayCaster& exact_;
  const Rig& rig_;
  const MclConfig& config_;
  std::unique_ptr<ScanScreen> screen_;  // null: no level scanner, or screening off
  std::vector<Pose> screen_positions_;  // its candidate places, drawn at the first global round
  std::vector<TrackedPlace> tracked_;   // places of the global rounds since the last uniform prior
  Pose tracked_odom_;                   // odometry at which their poses hold
};

}  // namespace polyloc
