// The particle set of the filter: poses and log weights, structure of arrays, and the few
// helpers that set, resize and gather its particles.
#pragma once

#include <polyloc/geometry/pose.hpp>

#include <cstddef>
#include <vector>

namespace polyloc {

// Particles, structure of arrays; orientation as unit quaternion, weights in log space.
struct ParticleSet {
  std::vector<double> x, y, z;
  std::vector<double> qw, qx, qy, qz;
  std::vector<double> logw;
  size_t size() const { return x.size(); }
  Pose pose(size_t i) const;
};

// Helpers on the SoA set.
void setParticle(ParticleSet& s, size_t i, const Pose& p);
void resizeParticles(ParticleSet& s, size_t n);
// New set holding the particles at `indices`, uniform weights.
ParticleSet gatherParticles(const ParticleSet& s, const std::vector<size_t>& indices);

}  // namespace polyloc
