#include <polyloc/mcl/beam_model.hpp>
#include <polyloc/mcl/pose_search.hpp>
#include <polyloc/mcl/level_beams.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace polyloc {
namespace {

// One scan's selected beams with their windows.
struct ScanBeams {
  BeamSet beams;
  std::vector<float> measured, tmin, tmax;
  Pose base_T_sensor;
};

}  // namespace

PoseSearchResult searchPose(const RayCaster& caster, const Rig& rig, std::span<const RefineScan> scans,
                            const Pose& guess, const PoseSearch& o) {
  PoseSearchResult res;
  res.pose = guess;
  std::vector<ScanBeams> sb;
  const float w = float(3 * o.truncate);
  // Level beams only (level_beams.hpp), unless the round has none: the search is planar, and
  // the lab rig's four tilted scanners tripled its rays for floor hits that fit every candidate.
  for (const bool level_only : {true, false}) {
    for (const RefineScan& s : scans) {
      if (s.sensor >= rig.size()) continue;
      const Sensor& sensor = rig.sensors[s.sensor];
      const BeamSet all = sensor.beams();
      ScanBeams b;
      b.beams.range_min = all.range_min, b.beams.range_max = all.range_max;
      b.base_T_sensor = s.base_T_base_at_scan * sensor.mount;
      const Pose map_T_sensor = guess * b.base_T_sensor;
      for (size_t k : BeamSensorModel::selectBeams(all, s.ranges, o.beams_per_scan)) {
        if (level_only && !isLevelRay(map_T_sensor.rotate(Eigen::Vector3d(all.dx[k], all.dy[k], all.dz[k])))) continue;
        b.beams.push(all.dx[k], all.dy[k], all.dz[k]);
        b.measured.push_back(s.ranges[k]);
        b.tmin.push_back(std::max(all.range_min, s.ranges[k] - w));
        b.tmax.push_back(std::min(all.range_max, s.ranges[k] + w));
      }
      res.beams += b.measured.size();
      if (!b.measured.empty()) sb.push_back(std::move(b));
    }
    if (!sb.empty()) break;
  }
  if (sb.empty() || (o.window_xy <= 0 && o.window_yaw <= 0)) return res;

  const double t2 = o.truncate * o.truncate;
  std::vector<float> hits;
  std::vector<Pose> sensor_poses;
  // Scores a grid of (2 nxy + 1)^2 (2 nyaw + 1) candidates around `centre`; keeps the best in res.
  auto stage = [&](const Pose& centre, double step_xy, double step_yaw, int nxy, int nyaw, bool spread) {
    std::vector<Pose> cand;
    std::vector<Eigen::Vector3d> offset;  // of each candidate from the centre (x, y, yaw)
    for (int i = -nxy; i <= nxy; ++i)
      for (int j = -nxy; j <= nxy; ++j)
        for (int k = -nyaw; k <= nyaw; ++k) {
          Pose c = centre * Pose::planar(0, 0, k * step_yaw);
          cand.push_back(Pose(c.rotation(), c.translation() + Eigen::Vector3d(i * step_xy, j * step_xy, 0)));
          offset.emplace_back(i * step_xy, j * step_xy, k * step_yaw);
        }
    // A weak pull towards the given pose: where the scans do not decide (along a corridor) the
    // nearest candidate wins, not the first of many that fit alike.
    std::vector<double> cost(cand.size(), 0.0);
    const double pull = o.pull * double(res.beams);
    for (size_t c = 0; c < cand.size(); ++c) {
      const Pose d = guess.inverse() * cand[c];
      cost[c] = pull * (d.translation().head<2>().squaredNorm() + d.yaw() * d.yaw());
    }
    const std::vector<double> pulled = cost;
    std::vector<size_t> in(cand.size(), 0);
    for (const ScanBeams& b : sb) {
      const size_t B = b.measured.size();
      sensor_poses.resize(cand.size());
      for (size_t c = 0; c < cand.size(); ++c) sensor_poses[c] = cand[c] * b.base_T_sensor;
      hits.resize(cand.size() * B);
      HitBuffers out;
      out.range = hits.data();
      caster.castScans(sensor_poses, b.beams, out, ScanWindow{b.tmin.data(), b.tmax.data()});
      for (size_t c = 0; c < cand.size(); ++c)
        for (size_t k = 0; k < B; ++k) {
          const float h = hits[c * B + k];
          const double d = std::isfinite(h) ? double(b.measured[k]) - double(h) : o.truncate;
          if (std::abs(d) < o.truncate) cost[c] += d * d, ++in[c];
          else cost[c] += t2;
        }
    }
    const size_t best = size_t(std::min_element(cost.begin(), cost.end()) - cost.begin());
    res.pose = cand[best], res.cost = cost[best], res.inliers = in[best];
    res.candidates += cand.size();
    if (!spread || o.spread_beams <= 0 || o.spread_sigma <= 0) return;
    // The data alone, tempered as the weighting tempers it; moments about the best candidate.
    const double scale = std::min(1.0, o.spread_beams / double(res.beams)) / (2 * o.spread_sigma * o.spread_sigma);
    std::vector<double> data(cand.size());
    for (size_t c = 0; c < cand.size(); ++c) data[c] = cost[c] - pulled[c];
    const double data_min = *std::min_element(data.begin(), data.end());
    double mass = 0;
    Eigen::Matrix3d m2 = Eigen::Matrix3d::Zero();
    for (size_t c = 0; c < cand.size(); ++c) {
      const double w = std::exp(-scale * (data[c] - data_min));
      const Eigen::Vector3d d = offset[c] - offset[best];
      mass += w, m2 += w * d * d.transpose();
    }
    res.spread = m2 / mass;  // the offsets are in map x, y and the turn about z already
  };
  // Coarse: the window at the step; fine: +- half a step around the best cell, at a quarter step.
  const int nxy = int(std::ceil(o.window_xy / o.step_xy - 1e-9)), nyaw = int(std::ceil(o.window_yaw / o.step_yaw - 1e-9));
  stage(guess, o.step_xy, o.step_yaw, nxy, nyaw, true);
  stage(res.pose, o.step_xy / 4, o.step_yaw / 4, o.window_xy > 0 ? 2 : 0, o.window_yaw > 0 ? 2 : 0, false);
  return res;
}

}  // namespace polyloc
