#include <polyloc/geometry/random.hpp>
#include <polyloc/sim/floor.hpp>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace polyloc {

namespace {
constexpr uint64_t kUnevennessStream = 0x464C4F4F52ULL;  // "FLOOR"
constexpr int kWaves = 8;
constexpr int kMaxPasses = 16;  // furniture surfaces a probe may pass before the floor
}  // namespace

FloorModel::FloorModel(const FloorSpec& spec, const RayCaster& caster, const Mesh& mesh,
                       std::vector<Eigen::Vector2d> contacts, uint64_t seed)
    : spec_(spec), caster_(caster), contacts_(std::move(contacts)) {
  if (!spec.contact_points.empty()) contacts_ = spec.contact_points;
  if (contacts_.size() < 3) throw std::invalid_argument("floor: needs at least 3 contact points");
  walkable_.assign(mesh.label_names.size(), false);
  for (size_t i = 0; i < mesh.label_names.size(); ++i)
    walkable_[i] = std::find(spec.labels.begin(), spec.labels.end(), mesh.label_names[i]) != spec.labels.end();
  const CounterRng rng(seed);
  for (int i = 0; i < kWaves; ++i) {
    const double lambda = spec.wavelength * rng.uniform(0.6, 1.4, kUnevennessStream, i, 0);
    const double dir = rng.uniform(0, 2 * M_PI, kUnevennessStream, i, 1);
    const double k = 2 * M_PI / lambda;
    waves_.push_back({k * std::cos(dir), k * std::sin(dir), rng.uniform(0, 2 * M_PI, kUnevennessStream, i, 2)});
  }
}

// RMS of a sum of K unit sines scaled by sqrt(2/K) is 1.
double FloorModel::unevenness(double x, double y) const {
  if (spec_.unevenness <= 0) return 0.0;
  double u = 0;
  for (const Wave& w : waves_) u += std::sin(w.kx * x + w.ky * y + w.phase);
  return spec_.unevenness * std::sqrt(2.0 / kWaves) * u;
}

void FloorModel::heights(std::span<const Eigen::Vector2d> xy, double* z) const {
  const size_t n = xy.size();
  if (!spec_.follow) {
    std::fill(z, z + n, 0.0);
    return;
  }
  // Active probes: origin z, travelled distance. Non-walkable hits are passed through.
  std::vector<size_t> active(n);
  for (size_t i = 0; i < n; ++i) active[i] = i, z[i] = std::nan("");
  std::vector<float> ox, oy, oz, dx, dy, dz, tmin, tmax, range, nz;
  std::vector<uint32_t> label;
  std::vector<double> start(n, spec_.probe_height);
  for (int pass = 0; pass < kMaxPasses && !active.empty(); ++pass) {
    const size_t m = active.size();
    ox.resize(m), oy.resize(m), oz.resize(m), dx.assign(m, 0.f), dy.assign(m, 0.f), dz.assign(m, -1.f);
    tmin.assign(m, 0.f), tmax.assign(m, static_cast<float>(spec_.probe_height + 20.0));
    range.resize(m), label.resize(m), nz.resize(m);
    std::vector<float> nx(m), ny(m);
    for (size_t j = 0; j < m; ++j) {
      ox[j] = static_cast<float>(xy[active[j]].x());
      oy[j] = static_cast<float>(xy[active[j]].y());
      oz[j] = static_cast<float>(start[active[j]]);
    }
    RayBatch rays{ox.data(), oy.data(), oz.data(), dx.data(), dy.data(), dz.data(), tmin.data(), tmax.data(), m};
    caster_.castRays(rays, {range.data(), nullptr, label.data(), nx.data(), ny.data(), nz.data()});
    std::vector<size_t> next;
    for (size_t j = 0; j < m; ++j) {
      const size_t i = active[j];
      if (!std::isfinite(range[j])) continue;  // nothing below: NaN
      const double hit = start[i] - range[j];
      if (label[j] < walkable_.size() && walkable_[label[j]] && nz[j] > 0.f) {
        z[i] = hit;
      } else {
        start[i] = hit - 1e-4;
        next.push_back(i);
      }
    }
    active.swap(next);
  }
}

double FloorModel::floorHeight(double x, double y) const {
  const Eigen::Vector2d p(x, y);
  double z;
  heights({&p, 1}, &z);
  return z;
}

void FloorModel::poses(std::span<const PlanarState> states, Pose* out) const {
  const size_t nc = contacts_.size();
  std::vector<Eigen::Vector2d> xy(states.size() * nc);
  for (size_t i = 0; i < states.size(); ++i) {
    const Eigen::Rotation2Dd r(states[i].yaw);
    for (size_t c = 0; c < nc; ++c) xy[i * nc + c] = Eigen::Vector2d(states[i].x, states[i].y) + r * contacts_[c];
  }
  std::vector<double> z(xy.size());
  heights(xy, z.data());
  Eigen::MatrixXd A(nc, 3);
  for (size_t c = 0; c < nc; ++c) A.row(c) << 1.0, contacts_[c].x(), contacts_[c].y();
  const Eigen::MatrixXd pinv = (A.transpose() * A).ldlt().solve(A.transpose());
  for (size_t i = 0; i < states.size(); ++i) {
    Eigen::VectorXd h(nc);
    for (size_t c = 0; c < nc; ++c) {
      double zc = z[i * nc + c];
      if (!std::isfinite(zc)) {
        ++misses_;
        zc = 0.0;  // no floor: keep the robot level at z = 0 rather than fail the run
      }
      h[c] = zc + unevenness(xy[i * nc + c].x(), xy[i * nc + c].y());
    }
    const Eigen::Vector3d abc = pinv * h;  // z = a + b u + c v in the yawed base frame
    // The plane normal (-b, -c, 1) is Ry(pitch) Rx(roll) e_z: pitch nose-down positive (REP-103).
    const double norm = std::sqrt(1 + abc[1] * abc[1] + abc[2] * abc[2]);
    const double pitch = -std::atan(abc[1]);
    const double roll = std::asin(std::clamp(abc[2] / norm, -1.0, 1.0));
    out[i] = Pose::fromXYZRPY(states[i].x, states[i].y, abc[0], roll, pitch, states[i].yaw);
  }
}

Pose FloorModel::pose(const PlanarState& s) const {
  Pose p;
  poses({&s, 1}, &p);
  return p;
}

}  // namespace polyloc
