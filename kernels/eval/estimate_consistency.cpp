#include <polyloc/eval/estimate_consistency.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

namespace polyloc {
namespace {
constexpr double kChi2Dof2At95 = 5.991;
}

Consistency evaluateConsistency(std::span<const PublishedPose> published, const GroundTruth& truth,
                                const ConsistencyOptions& o) {
  Consistency c;
  double nees_sum = 0;
  size_t over = 0;
  std::optional<Eigen::Vector2d> last_err;
  MclStatus last_status = MclStatus::Initialising;
  for (const PublishedPose& p : published) {
    const auto gt = truth.at(p.stamp_ns);
    if (!gt) continue;
    ++c.frames;
    const bool tracking = p.status == MclStatus::Tracking;
    const Eigen::Vector2d e = (p.pose.translation() - gt->translation()).head<2>();
    if (last_err && (e - *last_err).norm() > o.jump_m) {
      ++c.jumps;
      if (tracking && last_status == MclStatus::Tracking)
        ++c.unannounced_jumps, c.worst_unannounced_jump_m = std::max(c.worst_unannounced_jump_m, (e - *last_err).norm());
    }
    last_err = e, last_status = p.status;
    if (!tracking) continue;
    ++c.tracking;
    c.worst_tracking_err_m = std::max(c.worst_tracking_err_m, e.norm());
    c.tracking_beyond += e.norm() > o.confident_limit_m;
    Eigen::Matrix2d P = p.cov_xy;
    P(0, 0) = std::max(P(0, 0), o.min_std_m * o.min_std_m);
    P(1, 1) = std::max(P(1, 1), o.min_std_m * o.min_std_m);
    const double nees = e.dot(P.ldlt().solve(e));
    nees_sum += nees;
    over += !(nees <= kChi2Dof2At95);
  }
  c.nees_mean = c.tracking ? nees_sum / double(c.tracking) : std::numeric_limits<double>::quiet_NaN();
  c.nees_over_95 = c.tracking ? double(over) / double(c.tracking) : std::numeric_limits<double>::quiet_NaN();
  return c;
}

}  // namespace polyloc
