#include <polyloc/mcl/motion_model.hpp>

#include <tbb/parallel_for.h>

#include <cmath>

namespace polyloc {

namespace {
// Random streams of the motion model, apart from those of resampling and injection.
constexpr uint64_t kMotionStream = 0x4D4F54ULL << 40;
}  // namespace

Pose sampleMotion(const Pose& particle, const Pose& delta, const MotionNoise& n, int dof,
                  const CounterRng& rng, uint64_t step, uint64_t index) {
  const uint64_t stream = kMotionStream + step;
  const double scale = rng.uniform(stream, index, 6) < n.outlier_ratio ? n.outlier_scale : 1.0;  // heavy tails
  auto gauss = [&](uint64_t k, double sigma) { return sigma > 0 ? scale * sigma * rng.normal(stream, index, k) : 0.0; };
  const double dx = delta.x(), dy = delta.y(), dyaw = delta.yaw();
  const double trans = std::hypot(dx, dy);
  double nx, ny, nyaw;
  if (n.omni) {
    const double st = n.alpha3 * trans + n.alpha4 * std::abs(dyaw);
    const double sr = n.alpha1 * std::abs(dyaw) + n.alpha2 * trans;
    nx = dx + gauss(0, st), ny = dy + gauss(1, st), nyaw = dyaw + gauss(2, sr);
  } else {
    // Rotate-translate-rotate; a backward move is a forward move with a half-turn folded out,
    // so driving backwards does not look like two half-turns.
    double rot1 = trans < 1e-6 ? 0.0 : std::atan2(dy, dx);
    double sign = 1.0;
    if (std::abs(rot1) > M_PI / 2) rot1 = wrapAngle(rot1 + M_PI), sign = -1.0;
    const double rot2 = angleDiff(dyaw, rot1);
    const double r1 = rot1 - gauss(0, n.alpha1 * std::abs(rot1) + n.alpha2 * trans);
    const double t = trans - gauss(1, n.alpha3 * trans + n.alpha4 * (std::abs(rot1) + std::abs(rot2)));
    const double r2 = rot2 - gauss(2, n.alpha1 * std::abs(rot2) + n.alpha2 * trans);
    nx = sign * t * std::cos(r1), ny = sign * t * std::sin(r1), nyaw = r1 + r2;
  }
  double nz = delta.z(), nroll = delta.roll(), npitch = delta.pitch();
  if (dof == 6) {
    const double dist = trans + std::abs(delta.z());
    nz += gauss(3, n.z_per_m * dist);
    nroll += gauss(4, n.roll_pitch_per_m * dist);
    npitch += gauss(5, n.roll_pitch_per_m * dist);
  } else {
    nz = nroll = npitch = 0;  // dof 3: the floor under the particle sets them
  }
  return particle * Pose::fromXYZRPY(nx, ny, nz, nroll, npitch, nyaw);
}

void applyMotion(ParticleSet& s, const Pose& delta, const MotionNoise& noise, int dof,
                 const CounterRng& rng, uint64_t step) {
  tbb::parallel_for(tbb::blocked_range<size_t>(0, s.size(), 256), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i < r.end(); ++i)
      setParticle(s, i, sampleMotion(s.pose(i), delta, noise, dof, rng, step, i));
  });
}

}  // namespace polyloc
