#include <polyloc/mcl/estimate.hpp>

#include <cmath>
#include <unordered_map>
#include <vector>

namespace polyloc {

namespace {
uint64_t cellKey(int64_t cx, int64_t cy) { return uint64_t(cx & 0xFFFFFFFF) << 32 | uint64_t(cy & 0xFFFFFFFF); }
}  // namespace

ClusterEstimate dominantCluster(const ParticleSet& s, double cell) {
  ClusterEstimate e;
  const size_t n = s.size();
  if (n == 0) return e;
  // Cells with their weight; then connected components by flood fill.
  std::unordered_map<uint64_t, double> weight;
  std::vector<uint64_t> key(n);
  for (size_t i = 0; i < n; ++i) {
    key[i] = cellKey(int64_t(std::floor(s.x[i] / cell)), int64_t(std::floor(s.y[i] / cell)));
    weight[key[i]] += std::exp(s.logw[i]);
  }
  std::unordered_map<uint64_t, int> comp;
  std::vector<double> comp_mass;
  for (const auto& [k0, w0] : weight) {
    if (comp.count(k0)) continue;
    const int id = int(comp_mass.size());
    comp_mass.push_back(0);
    std::vector<uint64_t> stack{k0};
    comp[k0] = id;
    while (!stack.empty()) {
      const uint64_t k = stack.back();
      stack.pop_back();
      comp_mass[id] += weight[k];
      const auto cx = int64_t(int32_t(k >> 32)), cy = int64_t(int32_t(k & 0xFFFFFFFF));
      for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy) {
          const uint64_t nk = cellKey(cx + dx, cy + dy);
          if (weight.count(nk) && !comp.count(nk)) comp[nk] = id, stack.push_back(nk);
        }
    }
  }
  int best = 0;
  for (int c = 1; c < int(comp_mass.size()); ++c)
    if (comp_mass[c] > comp_mass[best]) best = c;
  e.clusters = comp_mass.size();
  e.mass = comp_mass[best];

  // Weighted mean: translation linear, orientation by sign-aligned quaternion average.
  double W = 0;
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  Eigen::Vector4d q = Eigen::Vector4d::Zero();
  Eigen::Vector4d ref(s.qw[0], s.qx[0], s.qy[0], s.qz[0]);
  bool have_ref = false;
  for (size_t i = 0; i < n; ++i) {
    if (comp[key[i]] != best) continue;
    const double w = std::exp(s.logw[i]);
    Eigen::Vector4d qi(s.qw[i], s.qx[i], s.qy[i], s.qz[i]);
    if (!have_ref) ref = qi, have_ref = true;
    if (qi.dot(ref) < 0) qi = -qi;
    W += w, t += w * Eigen::Vector3d(s.x[i], s.y[i], s.z[i]), q += w * qi;
  }
  if (W <= 0 || q.norm() == 0) return e;
  t /= W;
  q.normalize();
  e.pose = Pose(Eigen::Quaterniond(q[0], q[1], q[2], q[3]), t);
  const double r0 = e.pose.roll(), p0 = e.pose.pitch(), y0 = e.pose.yaw();
  Eigen::Matrix<double, 6, 6> C = Eigen::Matrix<double, 6, 6>::Zero();
  for (size_t i = 0; i < n; ++i) {
    if (comp[key[i]] != best) continue;
    const double w = std::exp(s.logw[i]) / W;
    const Pose p = s.pose(i);
    Eigen::Matrix<double, 6, 1> d;
    d << p.x() - t.x(), p.y() - t.y(), p.z() - t.z(), angleDiff(p.roll(), r0), angleDiff(p.pitch(), p0),
        angleDiff(p.yaw(), y0);
    C += w * d * d.transpose();
  }
  e.covariance = C;
  return e;
}

MclStatus statusOf(const ClusterEstimate& e, const MclConfig& cfg) {
  const double sxy = std::sqrt(std::max(e.covariance(0, 0), e.covariance(1, 1)));
  const double syaw = std::sqrt(e.covariance(5, 5));
  if (e.mass < 0.8 || sxy > cfg.uncertain_xy || syaw > cfg.uncertain_yaw) return MclStatus::Uncertain;
  return MclStatus::Tracking;
}

}  // namespace polyloc
