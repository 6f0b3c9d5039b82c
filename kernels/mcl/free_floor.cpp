#include <polyloc/mcl/free_floor.hpp>
#include <polyloc/mcl/particles.hpp>

#include <tbb/parallel_for.h>

#include <cmath>
#include <limits>

namespace polyloc {

namespace {
constexpr uint64_t kGlobalStream = 0x474C4FULL << 40;

// Orientation on a floor with normal n, keeping the heading `yaw`.
Eigen::Quaterniond onFloor(const Eigen::Vector3d& n, double yaw) {
  return Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), n) *
         Eigen::Quaterniond(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()));
}
}  // namespace

FreeFloor::FreeFloor(const RayCaster& caster, const Mesh& map, const MclConfig& config)
    : caster_(caster), config_(config), bounds_(map.bounds()) {
  floor_label_.assign(map.label_names.size(), 0);
  bool any = false;
  for (size_t l = 0; l < map.label_names.size(); ++l) {
    const auto& name = map.label_names[l];
    if (name.find("floor") != std::string::npos || name.find("ramp") != std::string::npos) floor_label_[l] = 1, any = true;
  }
  if (!any) floor_label_.assign(map.label_names.size(), 1);  // unlabelled map: any surface
}

bool FreeFloor::isFloorLabel(uint32_t l) const { return l < floor_label_.size() && floor_label_[l]; }

void FreeFloor::snapToFloor(ParticleSet& s, double step_up, double max_drop) const {
  const size_t n = s.size();
  if (n == 0) return;
  std::vector<float> ox(n), oy(n), oz(n), dx(n, 0.f), dy(n, 0.f), dz(n, -1.f), tmax(n, float(step_up + max_drop));
  for (size_t i = 0; i < n; ++i) ox[i] = float(s.x[i]), oy[i] = float(s.y[i]), oz[i] = float(s.z[i] + step_up);
  std::vector<float> r(n), nx(n), ny(n), nz(n);
  RayBatch rays{ox.data(), oy.data(), oz.data(), dx.data(), dy.data(), dz.data(), nullptr, tmax.data(), n};
  HitBuffers out;
  out.range = r.data(), out.nx = nx.data(), out.ny = ny.data(), out.nz = nz.data();
  caster_.castRays(rays, out);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1024), [&](const tbb::blocked_range<size_t>& b) {
    for (size_t i = b.begin(); i < b.end(); ++i) {
      if (!std::isfinite(r[i]) || r[i] <= 0.f || nz[i] < 0.5f) continue;  // no floor, in solid, a wall
      const Pose p = s.pose(i);
      setParticle(s, i, Pose(onFloor(Eigen::Vector3d(nx[i], ny[i], nz[i]).normalized(), p.yaw()),
                             Eigen::Vector3d(p.x(), p.y(), double(oz[i]) - r[i])));
    }
  });
}

BlockedResult FreeFloor::zeroBlocked(ParticleSet& s, double max_mass) const {
  const size_t n = s.size();
  std::vector<Eigen::Vector3f> pts(n);
  for (size_t i = 0; i < n; ++i) pts[i] = (s.pose(i) * Eigen::Vector3d(0, 0, config_.body_height)).cast<float>();
  std::vector<uint8_t> free(n);
  caster_.queryFree(pts, float(config_.clearance), free.data());
  // Weight share of the blocked particles (log weights are unnormalised here).
  double top = -std::numeric_limits<double>::infinity();
  for (double w : s.logw)
    if (std::isfinite(w)) top = std::max(top, w);
  double all = 0, blocked_mass = 0;
  size_t blocked = 0;
  for (size_t i = 0; i < n; ++i) {
    const double w = std::isfinite(s.logw[i]) ? std::exp(s.logw[i] - top) : 0.0;
    all += w;
    if (!free[i]) blocked_mass += w, ++blocked;
  }
  BlockedResult r;
  if (blocked == 0) return r;
  if (all > 0 && blocked < n && blocked_mass > max_mass * all) return r.ignored = blocked, r;
  for (size_t i = 0; i < n; ++i)
    if (!free[i]) s.logw[i] = -std::numeric_limits<double>::infinity();
  r.zeroed = blocked;
  return r;
}

std::vector<uint8_t> FreeFloor::enclosed(const std::vector<Eigen::Vector3f>& points,
                                         const std::vector<size_t>& which) const {
  constexpr int kDirs = 8;
  const size_t m = which.size() * kDirs;
  std::vector<float> ox(m), oy(m), oz(m), dx(m), dy(m), dz(m, 0.f), r(m);
  for (size_t k = 0; k < which.size(); ++k)
    for (int j = 0; j < kDirs; ++j) {
      const size_t i = k * kDirs + size_t(j);
      const Eigen::Vector3f& p = points[which[k]];
      ox[i] = p.x(), oy[i] = p.y(), oz[i] = p.z();
      dx[i] = float(std::cos(2 * M_PI * j / kDirs)), dy[i] = float(std::sin(2 * M_PI * j / kDirs));
    }
  HitBuffers hb;
  hb.range = r.data();
  caster_.castRays(RayBatch{ox.data(), oy.data(), oz.data(), dx.data(), dy.data(), dz.data(), nullptr, nullptr, m}, hb);
  std::vector<uint8_t> inside(which.size(), 1);
  for (size_t i = 0; i < m; ++i)
    if (!std::isfinite(r[i])) inside[i / kDirs] = 0;
  return inside;
}

std::vector<Pose> FreeFloor::sampleFree(size_t n, const CounterRng& rng, uint64_t stream) const {
  std::vector<Pose> out;
  if (bounds_.isEmpty() || n == 0) return out;
  const size_t batch = std::max<size_t>(4 * n, 1024);
  const auto lo = bounds_.min(), hi = bounds_.max();
  std::vector<float> ox(batch), oy(batch), oz(batch), dx(batch, 0.f), dy(batch, 0.f), dz(batch, -1.f);
  std::vector<float> r(batch), nx(batch), ny(batch), nz(batch), yaw(batch);
  std::vector<uint32_t> label(batch);
  std::vector<Eigen::Vector3f> body(batch);
  std::vector<uint8_t> free(batch);
  const float cos_max_tilt = float(std::cos(deg2rad(15.0)));
  // Rounds of candidates, accepted in index order: the same poses for any thread count.
  for (uint64_t round = 0; round < 50 && out.size() < n; ++round) {
    for (size_t c = 0; c < batch; ++c) {
      const uint64_t idx = round * batch + c;
      ox[c] = float(rng.uniform(lo.x(), hi.x(), kGlobalStream + stream, idx, 0));
      oy[c] = float(rng.uniform(lo.y(), hi.y(), kGlobalStream + stream, idx, 1));
      oz[c] = float(rng.uniform(lo.z(), hi.z(), kGlobalStream + stream, idx, 2));
      yaw[c] = float(rng.uniform(-M_PI, M_PI, kGlobalStream + stream, idx, 3));
    }
    RayBatch rays{ox.data(), oy.data(), oz.data(), dx.data(), dy.data(), dz.data(), nullptr, nullptr, batch};
    HitBuffers hb;
    hb.range = r.data(), hb.nx = nx.data(), hb.ny = ny.data(), hb.nz = nz.data(), hb.label = label.data();
    caster_.castRays(rays, hb);
    for (size_t c = 0; c < batch; ++c) {
      const bool floor = std::isfinite(r[c]) && r[c] > 1e-4f && nz[c] >= cos_max_tilt && isFloorLabel(label[c]);
      body[c] = floor ? Eigen::Vector3f(ox[c], oy[c], oz[c] - r[c] + float(config_.body_height))
                      : Eigen::Vector3f(lo.x() - 1e3f, lo.y() - 1e3f, lo.z() - 1e3f);  // far outside: skipped below
      if (!floor) r[c] = -1.f;
    }
    caster_.queryFree(body, float(config_.clearance), free.data());
    // Inside the building: a floor slab or a ground plane reaching beyond the outer walls is
    // floor too, but a robot standing there would see no wall in some direction.
    std::vector<size_t> cand;
    for (size_t c = 0; c < batch; ++c)
      if (r[c] >= 0.f && free[c]) cand.push_back(c);
    const std::vector<uint8_t> inside = enclosed(body, cand);
    for (size_t k = 0; k < cand.size() && out.size() < n; ++k) {
      const size_t c = cand[k];
      if (!inside[k]) continue;
      const Eigen::Vector3d t(ox[c], oy[c], double(oz[c]) - r[c]);
      out.emplace_back(onFloor(Eigen::Vector3d(nx[c], ny[c], nz[c]).normalized(), yaw[c]), t);
    }
  }
  return out;
}

}  // namespace polyloc
