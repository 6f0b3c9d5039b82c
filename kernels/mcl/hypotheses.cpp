#include <polyloc/mcl/hypotheses.hpp>
#include <polyloc/mcl/particles.hpp>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace polyloc {
namespace {

double yawOf(const ParticleSet& s, size_t i) { return yawOfQuaternion(s.qw[i], s.qx[i], s.qy[i], s.qz[i]); }

}  // namespace

std::vector<size_t> distinctModes(const ParticleSet& s, size_t k, double separation, double separation_yaw) {
  std::vector<size_t> order;
  order.reserve(s.size());
  for (size_t i = 0; i < s.size(); ++i)
    if (std::isfinite(s.logw[i])) order.push_back(i);
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return s.logw[a] != s.logw[b] ? s.logw[a] > s.logw[b] : a < b; });
  std::vector<size_t> modes;
  std::vector<double> yaws;
  const double sep2 = separation * separation;
  for (size_t i : order) {
    if (modes.size() >= k) break;
    const double yaw = yawOf(s, i);
    bool near = false;
    for (size_t m = 0; m < modes.size() && !near; ++m) {
      const double dx = s.x[i] - s.x[modes[m]], dy = s.y[i] - s.y[modes[m]];
      near = dx * dx + dy * dy < sep2 && std::abs(angleDiff(yaw, yaws[m])) < separation_yaw;
    }
    if (!near) modes.push_back(i), yaws.push_back(yaw);
  }
  return modes;
}

std::vector<Hypothesis> refineModes(const RayCaster& caster, const Rig& rig, std::span<const RefineScan> scans,
                                    const ParticleSet& s, const GlobalHypotheses& config, const RefineConfig& base,
                                    std::span<const Pose> extra) {
  RefineConfig rc = base;
  rc.beams_per_scan = config.beams_per_scan;
  rc.max_correction = config.max_correction;
  rc.max_correction_yaw = config.max_correction_yaw;
  rc.min_inlier_ratio = config.min_inlier_ratio;
  std::vector<Hypothesis> out;
  std::vector<Pose> starts;
  for (size_t i : distinctModes(s, config.count, config.separation, config.separation_yaw)) starts.push_back(s.pose(i));
  starts.insert(starts.end(), extra.begin(), extra.end());
  for (const Pose& start : starts) {
    const RefineResult r = refinePose(caster, rig, scans, start, 3, rc);
    if (!r.accepted || r.beams == 0) continue;
    out.push_back(Hypothesis{r.pose, double(r.correspondences) / double(r.beams), r.rms});
  }
  double best = 0;
  for (const Hypothesis& h : out) best = std::max(best, h.inlier_ratio);
  std::erase_if(out, [&](const Hypothesis& h) { return h.inlier_ratio < best - config.ratio_margin; });
  return out;
}

size_t plantHypotheses(ParticleSet& s, std::span<const Hypothesis> hyps, const GlobalHypotheses& config,
                       const CounterRng& rng, uint64_t stream) {
  const size_t n = std::min(hyps.size() * config.particles, s.size() / 2);
  if (n == 0) return 0;
  std::vector<size_t> order(s.size());
  std::iota(order.begin(), order.end(), size_t{0});
  // Lightest first (-inf and NaN before everything).
  auto lighter = [&](size_t a, size_t b) {
    const double wa = std::isfinite(s.logw[a]) ? s.logw[a] : -INFINITY, wb = std::isfinite(s.logw[b]) ? s.logw[b] : -INFINITY;
    return wa != wb ? wa < wb : a < b;
  };
  std::nth_element(order.begin(), order.begin() + ptrdiff_t(n), order.end(), lighter);
  std::sort(order.begin(), order.begin() + ptrdiff_t(n));
  double heaviest = -INFINITY;
  for (double w : s.logw)
    if (std::isfinite(w)) heaviest = std::max(heaviest, w);
  if (!std::isfinite(heaviest)) heaviest = 0;
  for (size_t k = 0; k < n; ++k) {
    const Hypothesis& h = hyps[k % hyps.size()];
    const size_t i = order[k];
    const double dx = config.spread_xy * rng.normal(stream, k, 0), dy = config.spread_xy * rng.normal(stream, k, 1);
    const double dyaw = config.spread_yaw * rng.normal(stream, k, 2);
    const Pose& p = h.pose;
    setParticle(s, i, Pose::fromXYZRPY(p.x() + dx, p.y() + dy, p.z(), p.roll(), p.pitch(), p.yaw() + dyaw));
    s.logw[i] = heaviest;
  }
  return n;
}

bool samePlace(const Pose& a, const Pose& b) {
  return (a.translation() - b.translation()).head<2>().norm() <= 1.0 && std::abs(angleDiff(a.yaw(), b.yaw())) <= 0.5;
}

double evidence(const Hypothesis& h, double sigma) {
  return sigma > 0 ? h.inlier_ratio * std::exp(-0.5 * (h.rms / sigma) * (h.rms / sigma)) : h.inlier_ratio;
}

void trackPlaces(std::vector<TrackedPlace>& places, std::span<const Hypothesis> hyps, const Pose& moved, double lead,
                 double drop, double sigma) {
  for (TrackedPlace& t : places) t.pose = t.pose * moved;
  const TrackedPlace* ahead = bestPlace(places);
  const double leader = ahead ? ahead->deficit : 0.0;
  double best = 0;
  for (const Hypothesis& h : hyps) best = std::max(best, evidence(h, sigma));
  std::vector<double> gain(places.size(), 0.0);
  for (const Hypothesis& h : hyps) {
    size_t k = 0;
    while (k < places.size() && !samePlace(places[k].pose, h.pose)) ++k;
    if (k == places.size()) places.push_back({h.pose, leader + lead, 0, 0}), gain.push_back(0.0);
    const double e = evidence(h, sigma);
    if (e > gain[k]) gain[k] = e, places[k].pose = h.pose;
  }
  for (size_t k = 0; k < places.size(); ++k) {
    TrackedPlace& t = places[k];
    t.deficit += gain[k] > 0 ? best - gain[k] : lead;
    t.rounds += gain[k] > 0;
    t.missed = gain[k] > 0 ? 0 : t.missed + 1;
  }
  const TrackedPlace* first = bestPlace(places);
  const double limit = first ? first->deficit + drop : 0;
  std::erase_if(places, [&](const TrackedPlace& t) { return t.deficit > limit; });
}

const TrackedPlace* bestPlace(std::span<const TrackedPlace> places) {
  const TrackedPlace* best = nullptr;
  for (const TrackedPlace& t : places)
    if (!best || t.deficit < best->deficit) best = &t;
  return best;
}

bool contested(std::span<const TrackedPlace> places, double lead) {
  const TrackedPlace* best = bestPlace(places);
  if (!best) return false;
  for (const TrackedPlace& t : places)
    if (&t != best && !samePlace(t.pose, best->pose) && t.deficit < best->deficit + lead) return true;
  return false;
}

}  // namespace polyloc
