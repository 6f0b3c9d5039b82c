#include <polyloc/mcl/beam_model.hpp>
#include <polyloc/mcl/pose_search.hpp>
#include <polyloc/mcl/refine.hpp>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

namespace polyloc {
namespace {

using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat6 = Eigen::Matrix<double, 6, 6>;
// The pose perturbation (6) and the range bias (refine.range_bias).
using Vec7 = Eigen::Matrix<double, 7, 1>;
using Mat7 = Eigen::Matrix<double, 7, 7>;

// The selected beams of all scans, fixed over the iterations (SoA, as the caster takes them).
struct Beams {
  std::vector<uint32_t> scan;        // index into the scan poses
  std::vector<float> sx, sy, sz;     // direction, sensor frame
  std::vector<float> measured, tmin, tmax;
  std::vector<uint8_t> biased;       // a level scanner's beam: the range bias applies
  size_t size() const { return scan.size(); }
};

// Apply a perturbation: translation in map axes, rotation about the base origin in map axes.
Pose perturb(const Pose& T, const Vec6& d) {
  const Eigen::Vector3d phi = d.tail<3>();
  const double angle = phi.norm();
  const Eigen::Quaterniond dq = angle > 0 ? Eigen::Quaterniond(Eigen::AngleAxisd(angle, phi / angle))
                                          : Eigen::Quaterniond::Identity();
  return Pose(dq * T.rotation(), T.translation() + d.head<3>());
}

Vec6 xyzrpy(const Pose& p) {
  Vec6 v;
  v << p.x(), p.y(), p.z(), p.roll(), p.pitch(), p.yaw();
  return v;
}

// Covariance of the perturbation -> covariance of (x y z roll pitch yaw), by the numeric Jacobian
// of the Euler angles at T (the rotation axes are map axes, roll and pitch are not).
Mat6 toEulerCovariance(const Pose& T, const Mat6& c) {
  constexpr double eps = 1e-6;
  Mat6 J;
  for (int i = 0; i < 6; ++i) {
    Vec6 d = Vec6::Zero();
    d[i] = eps;
    const Vec6 a = xyzrpy(perturb(T, d)), b = xyzrpy(perturb(T, -d));
    Vec6 diff = a - b;
    for (int k = 3; k < 6; ++k) diff[k] = angleDiff(a[k], b[k]);
    J.col(i) = diff / (2 * eps);
  }
  return J * c * J.transpose();
}

double rotationAngle(const Pose& a, const Pose& b) {
  return a.rotation().angularDistance(b.rotation());
}

}  // namespace

void subtractRangeBias(std::span<const float> ranges, double bias, float range_max, std::vector<float>& out) {
  out.assign(ranges.begin(), ranges.end());
  for (float& r : out)
    if (std::isfinite(r) && r < range_max) r = std::max(0.0f, r - float(bias));
}

RefineResult refinePose(const RayCaster& caster, const Rig& rig, std::span<const RefineScan> scans,
                        const Pose& map_T_base, int dof, const RefineConfig& cfg, double spread_beams) {
  if (dof != 3 && dof != 6) throw std::invalid_argument("refinePose: dof must be 3 or 6");
  RefineResult res;
  res.pose = map_T_base;

  // Beams: the valid ones of each scan, evenly spread, with the window each ray looks at.
  Beams bm;
  std::vector<Pose> base_T_sensor(scans.size());  // at the scan's stamp, from the reference base
  for (size_t k = 0; k < scans.size(); ++k) {
    const RefineScan& s = scans[k];
    if (s.sensor >= rig.size()) throw std::invalid_argument("refinePose: no sensor " + std::to_string(s.sensor));
    const Sensor& sensor = rig.sensors[s.sensor];
    const BeamSet all = sensor.beams();
    base_T_sensor[k] = s.base_T_base_at_scan * sensor.mount;
    for (size_t b : BeamSensorModel::selectBeams(all, s.ranges, cfg.beams_per_scan)) {
      bm.scan.push_back(uint32_t(k));
      bm.sx.push_back(all.dx[b]), bm.sy.push_back(all.dy[b]), bm.sz.push_back(all.dz[b]);
      bm.measured.push_back(s.ranges[b]);
      bm.tmin.push_back(all.range_min);
      bm.tmax.push_back(std::min<float>(all.range_max, s.ranges[b] + float(cfg.cast_margin)));
      bm.biased.push_back(cfg.range_bias && rig.isLevelScanner(s.sensor));
    }
  }
  const size_t N = bm.size();
  res.beams = N;
  if (N < cfg.min_correspondences || N == 0) {
    res.reason = "too few valid beams (" + std::to_string(N) + ")";
    return res;
  }

  // Ray buffers, reused over the iterations.
  std::vector<float> ox(N), oy(N), oz(N), dx(N), dy(N), dz(N), range(N), nx(N), ny(N), nz(N);
  RayBatch rays{ox.data(), oy.data(), oz.data(), dx.data(), dy.data(), dz.data(),
                bm.tmin.data(), bm.tmax.data(), N};
  HitBuffers hits;
  hits.range = range.data(), hits.nx = nx.data(), hits.ny = ny.data(), hits.nz = nz.data();
  const std::array<int, 3> planar_idx{0, 1, 5};
  const int n_pose = dof, n_par = dof + (cfg.range_bias ? 1 : 0);
  auto param = [&](int i) { return i == n_pose ? 6 : dof == 6 ? i : planar_idx[size_t(i)]; };
  double bias = 0;  // on top of what the ranges already had taken off
  // The prior in the units of the normal equations (residuals of about the Huber threshold):
  // weak, it only holds the bias where the beams cannot tell it from a translation.
  const double bias_info = cfg.range_bias ? std::pow(cfg.huber / cfg.range_bias_prior, 2) : 0.0;

  // Start from the best cell of a small exhaustive search (pose_search.hpp), if asked.
  Pose T = map_T_base;
  Eigen::Matrix3d spread = Eigen::Matrix3d::Zero();
  if (cfg.search_xy > 0 || cfg.search_yaw > 0) {
    const PoseSearch ps{cfg.search_xy, cfg.search_yaw, cfg.search_step_xy, cfg.search_step_yaw, 0.1, cfg.search_beams, 0.05,
                        spread_beams, cfg.huber};
    const PoseSearchResult found = searchPose(caster, rig, scans, map_T_base, ps);
    T = found.pose, spread = found.spread;
  }
  Eigen::MatrixXd H(n_par, n_par);
  double last_step = std::numeric_limits<double>::infinity();
  bool converged = false;
  double sum_we2 = 0;
  size_t inliers = 0;
  // The iterate of least robust cost: on maps whose walls are steps of grid cells the normals of
  // the correspondences flip between iterations and Gauss-Newton circles the optimum by
  // millimetres instead of settling; then that iterate, not the last, is the answer.
  struct Iterate {
    Pose T;
    double bias = 0;
    double cost = std::numeric_limits<double>::infinity(), sum_we2 = 0, rms = 0;
    size_t inliers = 0;
    Eigen::MatrixXd H;
  } best;
  const double cap = cfg.huber * (cfg.max_correspondence - 0.5 * cfg.huber);  // Huber cost at the gate
  for (int it = 0; it < cfg.iterations; ++it) {
    // Cast every selected beam from the sensor poses at T.
    std::vector<Pose> map_T_sensor(scans.size());
    for (size_t k = 0; k < scans.size(); ++k) map_T_sensor[k] = T * base_T_sensor[k];
    for (size_t i = 0; i < N; ++i) {
      const Pose& S = map_T_sensor[bm.scan[i]];
      const Eigen::Vector3d d = S.rotate(Eigen::Vector3d(bm.sx[i], bm.sy[i], bm.sz[i]));
      ox[i] = float(S.x()), oy[i] = float(S.y()), oz[i] = float(S.z());
      dx[i] = float(d.x()), dy[i] = float(d.y()), dz[i] = float(d.z());
    }
    caster.castRays(rays, hits);

    // Normal equations over the inliers; J = [n, (p - t) x n, -n.d] for the perturbation above
    // and the range bias (the measured range less the bias).
    Mat7 JtWJ = Mat7::Zero();
    Vec7 JtWe = Vec7::Zero();
    double sum_e2 = 0, cost = 0.5 * bias_info * bias * bias;
    sum_we2 = 0;
    inliers = 0;
    for (size_t i = 0; i < N; ++i) {
      if (!std::isfinite(range[i])) {
        cost += cap;
        continue;
      }
      const Eigen::Vector3d n(nx[i], ny[i], nz[i]), d(dx[i], dy[i], dz[i]);
      const double z = double(bm.measured[i]) - (bm.biased[i] ? bias : 0.0);
      const double e = (z - double(range[i])) * n.dot(d);
      if (!(std::abs(e) <= cfg.max_correspondence)) {
        cost += cap;
        continue;
      }
      cost += std::abs(e) <= cfg.huber ? 0.5 * e * e : cfg.huber * (std::abs(e) - 0.5 * cfg.huber);
      const Eigen::Vector3d p = Eigen::Vector3d(ox[i], oy[i], oz[i]) + z * d;
      Vec7 J;
      J.head<3>() = n;
      J.segment<3>(3) = (p - T.translation()).cross(n);
      J[6] = bm.biased[i] ? -n.dot(d) : 0.0;
      const double w = std::abs(e) <= cfg.huber ? 1.0 : cfg.huber / std::abs(e);
      JtWJ.selfadjointView<Eigen::Upper>().rankUpdate(J, w);
      JtWe += w * e * J;
      sum_e2 += e * e;
      sum_we2 += w * e * e;
      ++inliers;
    }
    JtWJ = JtWJ.selfadjointView<Eigen::Upper>();
    JtWJ(6, 6) += bias_info;  // the prior: the bias already applied is right, within range_bias_prior
    JtWe[6] += bias_info * bias;
    res.iterations = it + 1;
    res.correspondences = inliers;
    res.rms = inliers ? std::sqrt(sum_e2 / double(inliers)) : 0.0;
    if (inliers < std::max<size_t>(cfg.min_correspondences, size_t(n_par))) {
      res.reason = "too few correspondences (" + std::to_string(inliers) + ")";
      return res;
    }

    // Reduced system; a tiny damping keeps unobserved directions (corridor) at a zero step.
    Eigen::VectorXd g(n_par);
    for (int a = 0; a < n_par; ++a) {
      g[a] = JtWe[param(a)];
      for (int b = 0; b < n_par; ++b) H(a, b) = JtWJ(param(a), param(b));
    }
    if (cost < best.cost) best = Iterate{T, bias, cost, sum_we2, res.rms, inliers, H};
    const double mu = 1e-9 * H.diagonal().maxCoeff() + 1e-12;
    const Eigen::VectorXd h = -(H + mu * Eigen::MatrixXd::Identity(n_par, n_par)).ldlt().solve(g);
    if (!h.allFinite()) {
      res.reason = "singular normal equations";
      return res;
    }
    Vec6 delta = Vec6::Zero();
    for (int a = 0; a < n_pose; ++a) delta[param(a)] = h[a];
    T = perturb(T, delta);
    if (n_par > n_pose) bias += h[n_pose];
    last_step = std::hypot(delta.norm(), n_par > n_pose ? h[n_pose] : 0.0);

    // A correction this large means the estimate sat in another mode: leave it to MCL.
    const Eigen::Vector3d dt = T.translation() - map_T_base.translation();
    if (dt.norm() > cfg.max_correction || rotationAngle(T, map_T_base) > cfg.max_correction_yaw) {
      res.reason = "correction too large";
      return res;
    }
    if (last_step < cfg.min_step) {
      converged = true;
      break;
    }
  }
  if (!converged && !(last_step < cfg.max_final_step)) {
    // Circling: the least-cost iterate, checked by the same gates as a converged one.
    T = best.T, bias = best.bias, sum_we2 = best.sum_we2, inliers = best.inliers, H = best.H;
    res.rms = best.rms, res.correspondences = best.inliers;
  }
  if (double(inliers) < cfg.min_inlier_ratio * double(N)) {
    res.reason = "too few inliers (" + std::to_string(inliers) + " of " + std::to_string(N) + ")";
    return res;
  }

  // Covariance: residual variance times the inverse of J^T W J, with eigenvalues floored so
  // that an unobserved direction gets a large (finite) variance instead of inf/NaN.
  const double var = sum_we2 / double(std::max<size_t>(inliers - size_t(n_par), 1));
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(H);
  const Eigen::VectorXd ev = es.eigenvalues();
  const double floor = std::max(ev.maxCoeff() * 1e-9, 1e-12);
  const Eigen::MatrixXd Hinv =
      es.eigenvectors() * ev.cwiseMax(floor).cwiseInverse().asDiagonal() * es.eigenvectors().transpose();
  Mat6 c = Mat6::Zero();
  for (int a = 0; a < n_pose; ++a)
    for (int b = 0; b < n_pose; ++b) c(param(a), param(b)) = var * Hinv(a, b);
  res.covariance = toEulerCovariance(T, c);
  res.search_spread = spread;
  res.pose = T;
  if (n_par > n_pose) res.range_bias = bias, res.range_bias_std = std::sqrt(var * Hinv(n_pose, n_pose));
  res.accepted = true;
  return res;
}

}  // namespace polyloc
