#include <polyloc/mcl/particles.hpp>

#include <cmath>

namespace polyloc {

Pose ParticleSet::pose(size_t i) const {
  return Pose(Eigen::Quaterniond(qw[i], qx[i], qy[i], qz[i]), Eigen::Vector3d(x[i], y[i], z[i]));
}

void setParticle(ParticleSet& s, size_t i, const Pose& p) {
  s.x[i] = p.x(), s.y[i] = p.y(), s.z[i] = p.z();
  const auto& q = p.rotation();
  s.qw[i] = q.w(), s.qx[i] = q.x(), s.qy[i] = q.y(), s.qz[i] = q.z();
}

void resizeParticles(ParticleSet& s, size_t n) {
  for (auto* v : {&s.x, &s.y, &s.z, &s.qw, &s.qx, &s.qy, &s.qz, &s.logw}) v->resize(n);
}

ParticleSet gatherParticles(const ParticleSet& s, const std::vector<size_t>& idx) {
  ParticleSet o;
  resizeParticles(o, idx.size());
  const double lw = idx.empty() ? 0.0 : -std::log(double(idx.size()));
  for (size_t j = 0; j < idx.size(); ++j) {
    const size_t i = idx[j];
    o.x[j] = s.x[i], o.y[j] = s.y[i], o.z[j] = s.z[i];
    o.qw[j] = s.qw[i], o.qx[j] = s.qx[i], o.qy[j] = s.qy[i], o.qz[j] = s.qz[i];
    o.logw[j] = lw;
  }
  return o;
}

}  // namespace polyloc
