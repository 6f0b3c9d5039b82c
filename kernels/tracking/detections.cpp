#include <polyloc/tracking/detections.hpp>

#include <Eigen/Geometry>
#include <numeric>

namespace polyloc {

std::vector<Detection> clusterDetections(std::span<const MotionPoint> points, const ClusterConfig& c,
                                         int64_t stamp_ns) {
  std::vector<size_t> idx;
  for (size_t i = 0; i < points.size(); ++i)
    if (points[i].point.allFinite() && points[i].sensor.allFinite()) idx.push_back(i);
  // Union-find over all pairs closer than the distance: a few hundred moved points per step.
  std::vector<size_t> parent(idx.size());
  std::iota(parent.begin(), parent.end(), 0);
  auto root = [&](size_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  const double d2 = c.distance * c.distance;
  for (size_t a = 0; a < idx.size(); ++a)
    for (size_t b = a + 1; b < idx.size(); ++b)
      if ((points[idx[a]].point - points[idx[b]].point).squaredNorm() < d2) parent[root(a)] = root(b);
  std::vector<std::vector<size_t>> groups(idx.size());
  for (size_t a = 0; a < idx.size(); ++a) groups[root(a)].push_back(idx[a]);

  std::vector<Detection> out;
  for (const auto& g : groups) {
    size_t seeds = 0;
    for (size_t i : g) seeds += points[i].seed;
    if (g.empty() || seeds < c.min_points) continue;
    Eigen::AlignedBox2d box;
    std::vector<Eigen::Vector2d> q;
    q.reserve(g.size());
    for (size_t i : g) {
      const MotionPoint& m = points[i];
      box.extend(m.point);
      // The beams end on the faces turned towards the scanner: the object's centre lies behind.
      const Eigen::Vector2d ray = m.point - m.sensor;
      const double len = ray.norm();
      q.push_back(len > 1e-9 ? Eigen::Vector2d(m.point + c.surface_offset * ray / len) : m.point);
    }
    if (box.sizes().norm() > c.max_extent) continue;
    Detection d;
    d.stamp_ns = stamp_ns;
    d.points = q.size();
    d.seeds = seeds;
    for (const auto& p : q) d.position += p;
    d.position /= double(q.size());
    Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
    for (const auto& p : q) cov += (p - d.position) * (p - d.position).transpose();
    d.covariance = cov / double(q.size()) + Eigen::Matrix2d::Identity() * c.min_sigma * c.min_sigma;
    out.push_back(d);
  }
  return out;
}

}  // namespace polyloc
