#include <polyloc/mcl/beam_model.hpp>
#include <polyloc/mcl/motion_model.hpp>
#include <polyloc/mcl/scan_screen.hpp>
#include <polyloc/raycast/grid2d.hpp>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace polyloc {

namespace {
// At most this many cells (80 MB): a campus-sized map gets coarser cells, not an exception.
constexpr double kMaxCells = 2e7;

double cellSize(const Mesh& map, double resolution) {
  const Eigen::Vector3f size = map.bounds().sizes();
  const double area = (double(size.x()) + 1.0) * (double(size.y()) + 1.0);
  return std::max(resolution, std::sqrt(area / kMaxCells));
}
}  // namespace

struct ScanScreen::Impl {
  Impl(const Mesh& map, double height, const ScanScreenConfig& c)
      : grid(map, Grid2dOptions{cellSize(map, c.resolution), height, 0.5, true, 0}), config(c) {}
  Grid2dCaster grid;
  ScanScreenConfig config;
};

ScanScreen::ScanScreen(const Mesh& map, double height, const ScanScreenConfig& config)
    : impl_(std::make_unique<Impl>(map, height, config)) {}
ScanScreen::~ScanScreen() = default;

std::vector<Pose> ScanScreen::best(const Rig& rig, std::span<const RefineScan> scans, std::span<const Pose> positions,
                                   double separation, double separation_yaw, double heading_window) const {
  const Impl& m = *impl_;
  const ScanScreenConfig& cfg = m.config;
  std::vector<Pose> out;
  const size_t P = positions.size(), H = cfg.headings;
  if (cfg.keep == 0 || P == 0 || H == 0) return out;
  // Beam end points in the base frame at the particles' time, flattened onto the floor plane.
  std::vector<float> bx, by;
  for (const RefineScan& s : scans) {
    if (s.sensor >= rig.size() || !rig.isLevelScanner(s.sensor)) continue;
    const Sensor& sensor = rig.sensors[s.sensor];
    const BeamSet all = sensor.beams();
    const Pose S = s.base_T_base_at_scan * sensor.mount;
    for (size_t b : BeamSensorModel::selectBeams(all, s.ranges, cfg.beams_per_scan)) {
      const Eigen::Vector3d e = S * (Eigen::Vector3d(all.dx[b], all.dy[b], all.dz[b]) * double(s.ranges[b]));
      bx.push_back(float(e.x())), by.push_back(float(e.y()));
    }
  }
  const size_t B = bx.size();
  if (B == 0) return out;
  const std::span<const float> dist = m.grid.clearance();
  const long nx = long(m.grid.width()), ny = long(m.grid.height());
  const float res = float(m.grid.resolution()), ox = float(m.grid.originX()), oy = float(m.grid.originY());
  const float trunc = float(cfg.truncate), trunc2 = trunc * trunc;
  std::vector<float> cost(P * H);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, P, 64), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t p = r.begin(); p < r.end(); ++p) {
      const float x = float(positions[p].x()), y = float(positions[p].y());
      const double own = positions[p].yaw();
      for (size_t h = 0; h < H; ++h) {
        const double yaw = 2 * M_PI * double(h) / double(H);
        if (heading_window > 0 && std::abs(angleDiff(yaw, own)) > heading_window) {
          cost[p * H + h] = std::numeric_limits<float>::infinity();
          continue;
        }
        const float c = float(std::cos(yaw)), s = float(std::sin(yaw));
        float sum = 0;
        for (size_t i = 0; i < B; ++i) {
          const long cx = long(std::floor((x + c * bx[i] - s * by[i] - ox) / res));
          const long cy = long(std::floor((y + s * bx[i] + c * by[i] - oy) / res));
          if (cx < 0 || cy < 0 || cx >= nx || cy >= ny) {
            sum += trunc2;
            continue;
          }
          const float d = std::min(dist[size_t(cy * nx + cx)], trunc);
          sum += d * d;
        }
        cost[p * H + h] = sum;
      }
    }
  });
  // The best few hundred per kept candidate are enough to find `keep` distinct ones.
  const size_t pool = std::min(cost.size(), cfg.keep * 200);
  std::vector<size_t> order(cost.size());
  std::iota(order.begin(), order.end(), size_t{0});
  auto better = [&](size_t a, size_t b) { return cost[a] != cost[b] ? cost[a] < cost[b] : a < b; };
  std::partial_sort(order.begin(), order.begin() + ptrdiff_t(pool), order.end(), better);
  std::vector<double> yaws;
  const double sep2 = separation * separation;
  for (size_t k = 0; k < pool && out.size() < cfg.keep; ++k) {
    if (!std::isfinite(cost[order[k]])) break;
    const Pose& at = positions[order[k] / H];
    const double yaw = angleDiff(2 * M_PI * double(order[k] % H) / double(H), 0.0);
    bool near = false;
    for (size_t j = 0; j < out.size() && !near; ++j)
      near = (out[j].translation() - at.translation()).head<2>().squaredNorm() < sep2 &&
             std::abs(angleDiff(yaw, yaws[j])) < separation_yaw;
    if (near) continue;
    out.push_back(Pose::fromXYZRPY(at.x(), at.y(), at.z(), at.roll(), at.pitch(), yaw));
    yaws.push_back(yaw);
  }
  return out;
}

}  // namespace polyloc
