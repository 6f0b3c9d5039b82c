// Helpers of the MCL tests: small rooms, a one-scanner rig, scans ray cast from a true pose with
// counter-based noise (so runs repeat exactly), and a driver that feeds a trajectory.
#pragma once

#include "fixtures.hpp"

#include <polyloc/geometry/random.hpp>
#include <polyloc/mcl/localizer.hpp>
#include <polyloc/mcl/weighing.hpp>
#include <polyloc/raycast/embree.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>
#include <vector>

namespace polyloc::test {

// The box room of fixtures.hpp plus two boxes that break its symmetry.
inline Mesh asymmetricRoom() {
  Mesh m = boxRoom(4.f, 3.f, 2.5f, 0.2f);
  mapgen::MeshBuilder b(m);
  b.box({2.6f, 1.6f, 0.f}, {3.8f, 2.8f, 1.0f}, "cabinet");  // clear of the walls: no shared faces
  b.box({-1.5f, -2.8f, 0.f}, {-0.9f, -2.2f, 0.8f}, "bin");
  return m;
}

inline Rig scannerRig(double range_max = 10.0, double res_deg = 1.0) {
  PlanarScannerSpec spec;
  spec.fov_rad = deg2rad(270.0);
  spec.resolution_rad = deg2rad(res_deg);
  spec.range_max = range_max;
  Rig rig;
  rig.name = "test";
  rig.add(Sensor{"front", spec, Pose::fromXYZRPY(0.1, 0, 0.2, 0, 0, 0)}, "");
  return rig;
}

// Ranges a sensor on a robot at map_T_base sees, with Gaussian noise; misses stay +inf.
inline std::vector<float> simulateScan(const RayCaster& caster, const Sensor& s, const Pose& map_T_base,
                                       double sigma, uint64_t step, uint64_t seed = 99) {
  const BeamSet beams = s.beams();
  std::vector<float> r(beams.size());
  const Pose sp = s.worldPose(map_T_base);
  HitBuffers out;
  out.range = r.data();
  caster.castScans(std::span<const Pose>(&sp, 1), beams, out);
  CounterRng rng(seed);
  for (size_t b = 0; b < r.size(); ++b)
    if (std::isfinite(r[b])) r[b] = float(r[b] + sigma * rng.normal(step, b));
  return r;
}

inline Eigen::Matrix<double, 6, 6> planarCov(double sxy, double syaw) {
  Eigen::Matrix<double, 6, 6> c = Eigen::Matrix<double, 6, 6>::Zero();
  c(0, 0) = c(1, 1) = sxy * sxy;
  c(5, 5) = syaw * syaw;
  return c;
}

// A loop in the asymmetric room: true poses every 0.1 m, turning gently.
inline std::vector<Pose> loopTrajectory(size_t steps) {
  std::vector<Pose> out;
  double x = -1.5, y = -0.5, yaw = 0.2;
  for (size_t i = 0; i < steps; ++i) {
    out.push_back(Pose::planar(x, y, yaw));
    yaw += 0.06;
    x += 0.1 * std::cos(yaw), y += 0.1 * std::sin(yaw);
  }
  return out;
}

// Feeds the trajectory: odometry (exact, in an odom frame offset from map) then one scan per pose;
// `after(i)`, when given, after the scan of pose i (to look at each round's estimate).
inline void drive(Localizer& loc, const RayCaster& caster, const Rig& rig, const std::vector<Pose>& truth,
                  double scan_sigma = 0.01, const std::function<void(size_t)>& after = {}) {
  const Pose map_T_odom = Pose::planar(0.7, -0.3, 0.5);
  for (size_t i = 0; i < truth.size(); ++i) {
    const int64_t t = int64_t(i) * 100'000'000;
    loc.addOdometry(t, map_T_odom.inverse() * truth[i]);
    const auto r = simulateScan(caster, rig.sensors[0], truth[i], scan_sigma, i);
    loc.addScan(0, t, r);
    if (after) after(i);
  }
}

// Particles at the given poses, equal log-weights (for weighing a model at chosen poses).
inline ParticleSet particlesAt(const std::vector<Pose>& poses) {
  ParticleSet ps;
  for (const Pose& p : poses) {
    const Eigen::Quaterniond& q = p.rotation();
    ps.x.push_back(p.x()), ps.y.push_back(p.y()), ps.z.push_back(p.z());
    ps.qw.push_back(q.w()), ps.qx.push_back(q.x()), ps.qy.push_back(q.y()), ps.qz.push_back(q.z());
    ps.logw.push_back(0.0);
  }
  return ps;
}

// The particles after a short loop in the asymmetric room with measurement model `model` on
// `threads` threads: for the checks that results do not depend on the thread count.
inline ParticleSet runWithThreads(int threads, const std::string& model = "beam") {
  const Mesh mesh = asymmetricRoom();
  EmbreeOptions opt;
  opt.threads = threads;
  EmbreeCaster caster(mesh, opt);
  const Rig rig = scannerRig();
  MclConfig cfg;
  cfg.model = model;
  cfg.particles = 800;
  cfg.threads = threads;
  Localizer loc(caster, mesh, rig, cfg);
  const auto truth = loopTrajectory(20);
  loc.initPose(truth[0], planarCov(0.3, 0.2), 0);
  drive(loc, caster, rig, truth);
  return loc.particles();
}


// Bit-identical particle sets (position, yaw component, weight), e.g. from 1 and 2 threads.
inline void expectIdenticalParticles(const ParticleSet& a, const ParticleSet& b) {
  ASSERT_EQ(a.size(), b.size());
  ASSERT_GT(a.size(), 0u);
  for (size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a.x[i], b.x[i]) << i;
    ASSERT_EQ(a.y[i], b.y[i]) << i;
    ASSERT_EQ(a.qz[i], b.qz[i]) << i;
    ASSERT_EQ(a.logw[i], b.logw[i]) << i;
  }
}

inline double posErr(const Pose& a, const Pose& b) { return std::hypot(a.x() - b.x(), a.y() - b.y()); }
inline double yawErrDeg(const Pose& a, const Pose& b) { return std::abs(rad2deg(angleDiff(a.yaw(), b.yaw()))); }

// The loop of the asymmetric room tracked by a filter that weighs against the map representation
// `caster` (mcl.caster; the floor and free space stay on Embree), from a start 0.25 m and 5 deg off.
struct LoopRun {
  std::string weighed_by;  // the weighing caster's name
  MclEstimate estimate;
  double pos_err = 0, yaw_err_deg = 0;
};
inline LoopRun trackLoopWeighingOn(const std::string& caster) {
  const Mesh mesh = asymmetricRoom();
  EmbreeCaster exact(mesh);
  const Rig rig = scannerRig();
  MclConfig cfg;
  cfg.particles = 1000;
  cfg.caster = caster;
  const std::unique_ptr<RayCaster> weigh = makeWeighingCaster(mesh, rig, cfg, 1);
  const auto truth = loopTrajectory(60);
  Localizer loc(exact, mesh, rig, cfg, weigh.get());
  const Pose& t0 = truth[0];
  loc.initPose(Pose::planar(t0.x() + 0.2, t0.y() - 0.15, t0.yaw() + deg2rad(5)), planarCov(0.25, 0.1), 0);
  drive(loc, exact, rig, truth);
  LoopRun r;
  r.weighed_by = weigh ? weigh->name() : exact.name();
  r.estimate = loc.estimate();
  r.pos_err = posErr(r.estimate.pose, truth.back()), r.yaw_err_deg = yawErrDeg(r.estimate.pose, truth.back());
  std::printf("[mcl] weighing on %s: pos err %.4f m, yaw err %.3f deg\n", r.weighed_by.c_str(), r.pos_err, r.yaw_err_deg);
  return r;
}

}  // namespace polyloc::test
