#include <polyloc/mcl/plane_fragments.hpp>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <variant>

namespace polyloc {

LineSegment transformSegment(const Pose& T, const LineSegment& s) {
  LineSegment o = s;
  o.a = T * s.a, o.b = T * s.b, o.dir = T.rotate(s.dir);
  return o;
}

std::vector<PlaneFragment> buildFragments(std::span<const LineSegment> a, const Eigen::Vector3d& na,
                                          std::span<const LineSegment> b, const Eigen::Vector3d& nb,
                                          size_t cast_sensor, const FragmentParams& prm) {
  std::vector<PlaneFragment> out;
  const double sin_min = std::sin(prm.min_angle), cos_min = std::cos(prm.min_angle);
  for (const LineSegment& s1 : a) {
    const double l1 = s1.length();
    for (const LineSegment& s2 : b) {
      // Closest points of the lines s1.a + s d1 and s2.a + t d2 (unit directions).
      const Eigen::Vector3d &d1 = s1.dir, &d2 = s2.dir;
      const double c = d1.dot(d2), denom = 1.0 - c * c;
      if (denom < sin_min * sin_min) continue;  // too parallel: the crossing is ill-defined
      const Eigen::Vector3d w0 = s1.a - s2.a;
      const double d = d1.dot(w0), e = d2.dot(w0);
      const double s = (c * e - d) / denom, t = (e - c * d) / denom;
      if (s < -prm.extent_margin || s > l1 + prm.extent_margin) continue;
      if (t < -prm.extent_margin || t > s2.length() + prm.extent_margin) continue;
      const Eigen::Vector3d p1 = s1.a + s * d1, p2 = s2.a + t * d2;
      if ((p1 - p2).norm() > prm.intersect_tolerance) continue;
      const Eigen::Vector3d n = d1.cross(d2).normalized();
      // A surface (nearly) in one scan plane cannot give a line in it: two lines of one plane.
      if (std::abs(n.dot(na)) > cos_min || std::abs(n.dot(nb)) > cos_min) continue;
      out.push_back({0.5 * (p1 + p2), n, cast_sensor});
    }
  }
  return out;
}

PlaneFragmentModel::PlaneFragmentModel(const RayCaster& caster, const Rig& rig, const MclConfig& config)
    : caster_(caster), rig_(rig), config_(config), beam_(caster, rig, config) {
  size_t planar = 0;
  for (const auto& s : rig.sensors) {
    beams_.push_back(s.beams());
    planar_.push_back(std::holds_alternative<PlanarScannerSpec>(s.spec));
    planar += planar_.back();
  }
  if (planar < 2)
    throw std::invalid_argument("measurement model 'plane_fragments' needs at least two planar scanners; rig '" +
                                rig.name + "' has " + std::to_string(planar));
  latest_.resize(rig.size());
}

double PlaneFragmentModel::floorDensity() const {
  const auto& m = config_.plane_fragments;
  return m.z_rand / (2.0 * m.window);  // uniform over the window of distance differences
}

double PlaneFragmentModel::unexplainedLogLikelihood(size_t sensor) const {
  if (sensor < planar_.size() && !planar_[sensor]) return beam_.unexplainedLogLikelihood(sensor);
  return std::log(floorDensity());
}

double PlaneFragmentModel::logLikelihood(double expected, float range, const Eigen::Vector3d& n,
                                         const Eigen::Vector3d& hn) const {
  const auto& m = config_.plane_fragments;
  double p_hit = 0;
  if (std::isfinite(range)) {
    const double dd = (double(range) - expected) / m.sigma_distance;
    const double ang = std::acos(std::min(1.0, std::abs(n.dot(hn))));
    const double da = ang / m.sigma_angle;
    p_hit = m.z_hit * std::exp(-0.5 * (dd * dd + da * da)) / (m.sigma_distance * 2.5066282746310002);
  }
  return std::log(p_hit + floorDensity());
}

const std::vector<PlaneFragment>& PlaneFragmentModel::fragments(const SensorFrame& frame) {
  const auto& m = config_.plane_fragments;
  const size_t S = frame.sensor;
  const Sensor& sensor = rig_.sensors.at(S);
  frags_.clear();
  if (!planar_.at(S)) return frags_;
  const LineFitParams lp{m.split_threshold, m.min_points, m.min_length, m.max_gap};
  Latest& cur = latest_[S];
  cur.segments = fitLineSegments(frame.ranges, beams_[S], lp);
  for (auto& s : cur.segments) s = transformSegment(sensor.mount, s);
  cur.valid = true, cur.stamp_ns = frame.stamp_ns, cur.odom_T_base = frame.odom_T_base;
  const Eigen::Vector3d n_cur = sensor.mount.rotate(Eigen::Vector3d::UnitZ());
  const FragmentParams fp{m.intersect_tolerance, m.extent_margin, m.min_angle};
  const double max_age_ns = m.max_age * 1e9;
  std::vector<LineSegment> moved;
  for (size_t k = 0; k < latest_.size(); ++k) {
    const Latest& o = latest_[k];
    if (k == S || !o.valid || o.segments.empty() || std::abs(double(frame.stamp_ns - o.stamp_ns)) > max_age_ns)
      continue;
    // base_now <- base_then by odometry: good over the fraction of a second max_age allows.
    const Pose now_T_then = frame.odom_T_base.inverse() * o.odom_T_base;
    moved.clear();
    for (const auto& s : o.segments) moved.push_back(transformSegment(now_T_then, s));
    const Eigen::Vector3d n_k = now_T_then.rotate(rig_.sensors[k].mount.rotate(Eigen::Vector3d::UnitZ()));
    const auto f = buildFragments(cur.segments, n_cur, moved, n_k, S, fp);
    frags_.insert(frags_.end(), f.begin(), f.end());
  }
  if (m.max_fragments > 0 && frags_.size() > m.max_fragments) {
    // Evenly spread over what was found: every scanner pair keeps its say.
    std::vector<PlaneFragment> keep(m.max_fragments);
    for (size_t i = 0; i < keep.size(); ++i) keep[i] = frags_[(i * frags_.size()) / keep.size()];
    frags_.swap(keep);
  }
  return frags_;
}

size_t PlaneFragmentModel::weigh(const ParticleSet& ps, const SensorFrame& frame, std::span<double> loglik) {
  if (!planar_.at(frame.sensor)) return beam_.weigh(ps, frame, loglik);
  const auto& frags = fragments(frame);
  const size_t F = frags.size(), P = ps.size();
  if (F == 0 || P == 0) return 0;
  const auto& m = config_.plane_fragments;
  const Pose& mount = rig_.sensors[frame.sensor].mount;
  // Per fragment, in the base frame: unit ray direction from the sensor and expected distance.
  std::vector<Eigen::Vector3d> dir(F);
  std::vector<double> expected(F);
  for (size_t f = 0; f < F; ++f) {
    const Eigen::Vector3d v = frags[f].point - mount.translation();
    expected[f] = v.norm();
    dir[f] = expected[f] > 1e-9 ? Eigen::Vector3d(v / expected[f]) : Eigen::Vector3d::UnitX();
  }
  const size_t N = P * F;
  for (auto* v : {&ox_, &oy_, &oz_, &dx_, &dy_, &dz_, &tmin_, &tmax_, &range_, &nx_, &ny_, &nz_}) v->resize(N);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, P, 256), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t p = r.begin(); p < r.end(); ++p) {
      const Pose base = ps.pose(p);
      const Eigen::Vector3d o = base * mount.translation();
      for (size_t f = 0; f < F; ++f) {
        const size_t i = p * F + f;
        const Eigen::Vector3d d = base.rotate(dir[f]);
        ox_[i] = float(o.x()), oy_[i] = float(o.y()), oz_[i] = float(o.z());
        dx_[i] = float(d.x()), dy_[i] = float(d.y()), dz_[i] = float(d.z());
        tmin_[i] = float(std::max(0.0, expected[f] - m.window));
        tmax_[i] = float(expected[f] + m.window);
      }
    }
  });
  RayBatch rays{ox_.data(), oy_.data(), oz_.data(), dx_.data(), dy_.data(), dz_.data(), tmin_.data(), tmax_.data(), N};
  HitBuffers out;
  out.range = range_.data(), out.nx = nx_.data(), out.ny = ny_.data(), out.nz = nz_.data();
  caster_.castRays(rays, out);
  // Per particle, a sequential sum over its fragments: the same for any split over threads.
  tbb::parallel_for(tbb::blocked_range<size_t>(0, P, 256), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t p = r.begin(); p < r.end(); ++p) {
      const Eigen::Quaterniond q = Eigen::Quaterniond(ps.qw[p], ps.qx[p], ps.qy[p], ps.qz[p]).normalized();
      double s = 0;
      for (size_t f = 0; f < F; ++f) {
        const size_t i = p * F + f;
        const Eigen::Vector3d hn(nx_[i], ny_[i], nz_[i]);
        s += logLikelihood(expected[f], range_[i], q * frags[f].normal, hn);
      }
      loglik[p] += m.log_scale * s;
    }
  });
  return F;
}

}  // namespace polyloc
