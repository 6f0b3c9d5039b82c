// Odometry motion model: the base moved by `delta` (base_prev -> base_now, from two cumulative
// odometry poses); every particle moves by a noisy copy of it. Planar noise follows Thrun's
// alpha1..alpha4 (differential: rotate-translate-rotate; omni: x, y, yaw independently); the
// out-of-plane part of the delta (z, roll, pitch: 6-DoF odometry) is kept, and for dof 6 it is
// diffused per metre travelled. Noise is drawn with CounterRng(step, particle), so the result
// does not depend on how particles are split over threads.
#pragma once

#include <polyloc/geometry/random.hpp>
#include <polyloc/mcl/config.hpp>
#include <polyloc/mcl/particles.hpp>

namespace polyloc {

// Moves particle i (one pose) by a noisy delta; `step` and `index` select the random draws.
Pose sampleMotion(const Pose& particle, const Pose& delta, const MotionNoise& noise, int dof,
                  const CounterRng& rng, uint64_t step, uint64_t index);

// All particles, in parallel (TBB).
void applyMotion(ParticleSet& particles, const Pose& delta, const MotionNoise& noise, int dof,
                 const CounterRng& rng, uint64_t step);

}  // namespace polyloc
