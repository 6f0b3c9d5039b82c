#include <polyloc/mcl/fit_check.hpp>
#include <polyloc/mcl/global_search.hpp>
#include <polyloc/mcl/scan_screen.hpp>
#include <polyloc/mcl/weighing.hpp>

namespace polyloc {

GlobalSearch::GlobalSearch(const RayCaster& caster, const RayCaster& exact, const Mesh& map, const Rig& rig,
                           const MclConfig& config)
    : caster_(caster), exact_(exact), rig_(rig), config_(config) {
  const std::vector<uint8_t> weighed = weighedSensors(rig, config);
  bool level = false;
  for (size_t k = 0; k < rig.size(); ++k) level = level || (weighed[k] && rig.isLevelScanner(k));
  if (level && !map.triangles.empty() && config.hypotheses.count > 0 && config.hypotheses.screen.keep > 0 &&
      config.global_particles > 0)
    screen_ = std::make_unique<ScanScreen>(map, weighingSliceHeight(rig, config), config.hypotheses.screen);
}

GlobalSearch::~GlobalSearch() = default;

GlobalRound GlobalSearch::round(std::span<const RefineScan> scans, const ParticleSet& ps, const Pose& odom,
                                const FreeFloor& floor, const CounterRng& rng, uint64_t screen_stream) {
  GlobalRound r;
  if (scans.empty()) return r;
  if (screen_ && screen_positions_.empty())
    screen_positions_ = floor.sampleFree(config_.hypotheses.screen.positions, rng, screen_stream);
  // The places of earlier rounds are refined again where odometry carried them: a place is kept
  // by its own fit, not by the chance that this round's modes or screen land near it again.
  if (tracked_.empty()) tracked_odom_ = odom;
  const Pose moved = tracked_odom_.inverse() * odom;
  std::vector<Pose> carried;
  for (const TrackedPlace& t : tracked_) carried.push_back(t.pose * moved);
  r.hypotheses = fittingModes(scans, ps, screen_positions_, 0, 2.0, carried);
  const GlobalHypotheses& h = config_.hypotheses;
  // The residuals' std: half the refinement's inlier gate.
  trackPlaces(tracked_, r.hypotheses, moved, h.lead, h.drop, 0.5 * config_.refine.max_correspondence);
  tracked_odom_ = odom;
  // Several places fit alike over the rounds so far (a corridor seen both ways, twin rooms).
  r.ambiguous = contested(tracked_, h.lead);
  if (const TrackedPlace* best = bestPlace(tracked_)) r.best = best->pose;
  return r;
}

std::vector<Hypothesis> GlobalSearch::fittingModes(std::span<const RefineScan> scans, const ParticleSet& ps,
                                                   std::span<const Pose> positions, double heading_window,
                                                   double past_share, std::span<const Pose> also) const {
  const GlobalHypotheses& h = config_.hypotheses;
  std::vector<Pose> screened;
  if (screen_ && !positions.empty())
    screened = screen_->best(rig_, scans, positions, h.separation, h.separation_yaw, heading_window);
  screened.insert(screened.end(), also.begin(), also.end());
  std::vector<Hypothesis> hyps = refineModes(caster_, rig_, scans, ps, h, config_.refine, screened);
  std::erase_if(hyps, [&](const Hypothesis& x) {
    return checkFit(exact_, rig_, scans, x.pose, config_.fit.tolerance, config_.fit.beams_per_scan, past_share).seenThrough() >
           config_.fit.max_seen_through;
  });
  return hyps;
}

}  // namespace polyloc
