#include <polyloc/eval/mot_metrics.hpp>
#include <polyloc/tracking/hungarian.hpp>

#include <cmath>
#include <limits>

namespace polyloc {

void MotAccumulator::addFrame(double dt_s, std::span<const MotObject> truth_in, std::span<const MotObject> hyps_in) {
  std::vector<const MotObject*> truth, hyps;
  for (const MotObject& o : truth_in)
    if (o.position.allFinite()) truth.push_back(&o);
  for (const MotObject& o : hyps_in)
    if (o.position.allFinite()) hyps.push_back(&o);
  ++m_.frames;
  std::vector<int> of_truth(truth.size(), -1);
  std::vector<char> hyp_used(hyps.size(), 0);
  auto dist = [&](size_t t, size_t h) { return (truth[t]->position - hyps[h]->position).norm(); };

  // Care objects first, so that a hypothesis between a walking and a standing person goes to
  // the walking one; then don't-care objects absorb what is on them.
  for (bool care : {true, false}) {
    // 1. Correspondences of the last frame that still hold.
    for (size_t t = 0; t < truth.size(); ++t) {
      if (truth[t]->care != care) continue;
      const auto it = current_.find(truth[t]->id);
      if (it == current_.end()) continue;
      for (size_t h = 0; h < hyps.size(); ++h)
        if (!hyp_used[h] && hyps[h]->id == it->second && dist(t, h) <= threshold_) {
          of_truth[t] = int(h), hyp_used[h] = 1;
          break;
        }
    }
    // 2. The rest by the Hungarian method on distance.
    std::vector<size_t> rt, rh;
    for (size_t t = 0; t < truth.size(); ++t)
      if (truth[t]->care == care && of_truth[t] < 0) rt.push_back(t);
    for (size_t h = 0; h < hyps.size(); ++h)
      if (!hyp_used[h]) rh.push_back(h);
    Eigen::MatrixXd cost(Eigen::Index(rt.size()), Eigen::Index(rh.size()));
    for (size_t i = 0; i < rt.size(); ++i)
      for (size_t j = 0; j < rh.size(); ++j) {
        const double d = dist(rt[i], rh[j]);
        cost(Eigen::Index(i), Eigen::Index(j)) = d <= threshold_ ? d : std::numeric_limits<double>::infinity();
      }
    const std::vector<int> a = solveAssignment(cost);
    for (size_t i = 0; i < rt.size(); ++i)
      if (a[i] >= 0) of_truth[rt[i]] = int(rh[size_t(a[i])]), hyp_used[rh[size_t(a[i])]] = 1;
  }

  std::map<uint64_t, uint64_t> now;
  for (size_t t = 0; t < truth.size(); ++t) {
    const MotObject& o = *truth[t];
    if (of_truth[t] < 0) {
      m_.misses += o.care;
      m_.ground_truth += o.care;
      continue;
    }
    const uint64_t h = hyps[size_t(of_truth[t])]->id;
    now[o.id] = h;
    if (!o.care) continue;
    ++m_.ground_truth;
    ++m_.matches;
    const double d = dist(t, size_t(of_truth[t]));
    sum_d_ += d, sum_d2_ += d * d;
    m_.track_seconds += dt_s;
    const auto last = last_.find(o.id);
    if (last != last_.end() && last->second != h) {
      const auto seen = in_view_.find(o.id);
      const bool back = seen != in_view_.end() && t_ - seen->second > forget_s_;
      ++(back ? m_.reentries : m_.id_switches);
    }
    last_[o.id] = h;
  }
  for (size_t h = 0; h < hyps.size(); ++h) m_.false_positives += !hyp_used[h];
  current_ = std::move(now);
  for (const MotObject* o : truth)
    if (o->care) in_view_[o->id] = t_;
  t_ += dt_s;
}

MotMetrics MotAccumulator::metrics() const {
  MotMetrics m = m_;
  m.mota = m.ground_truth > 0 ? 1.0 - double(m.misses + m.false_positives + m.id_switches) / double(m.ground_truth) : 0.0;
  m.motp_m = m.matches > 0 ? sum_d_ / double(m.matches) : 0.0;
  m.rmse_m = m.matches > 0 ? std::sqrt(sum_d2_ / double(m.matches)) : 0.0;
  m.id_switches_per_100s = m.track_seconds > 0 ? 100.0 * double(m.id_switches) / m.track_seconds : 0.0;
  return m;
}

}  // namespace polyloc
