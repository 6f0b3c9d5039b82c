#include <polyloc/eval/stats.hpp>
#include <polyloc/eval/trajectory_metrics.hpp>
#include <polyloc/geometry/domain.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace polyloc {

ErrorSummary summarize(std::span<const FrameError> frames) {
  ErrorSummary s;
  s.frames = frames.size();
  std::vector<double> pos, yaw, z, rp;
  pos.reserve(frames.size()), yaw.reserve(frames.size()), z.reserve(frames.size()), rp.reserve(2 * frames.size());
  for (const FrameError& f : frames) {
    pos.push_back(f.pos_err);
    yaw.push_back(rad2deg(f.yaw_err));
    z.push_back(f.dz);
    rp.push_back(rad2deg(f.roll_err));
    rp.push_back(rad2deg(f.pitch_err));
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  double sum = 0;
  for (double p : pos) sum += p;
  s.mean_pos_err_m = pos.empty() ? nan : sum / static_cast<double>(pos.size());
  s.ate_rmse_m = rms(pos);
  s.max_pos_err_m = maxAbs(pos);
  s.p95_pos_err_m = percentile(pos, 95);
  s.yaw_rmse_deg = rms(yaw);
  s.max_yaw_err_deg = maxAbs(yaw);
  for (double& y : yaw) y = std::abs(y);  // the percentile is of the magnitude
  s.p95_yaw_err_deg = percentile(std::move(yaw), 95);
  s.z_rmse_m = rms(z);
  s.max_z_err_m = maxAbs(z);
  s.roll_pitch_rmse_deg = rms(rp);  // pooled: each frame gives a roll and a pitch sample
  s.max_roll_pitch_err_deg = maxAbs(rp);
  return s;
}

namespace {

// Index of the convergence frame, or frames.size() when there is none.
size_t convergenceIndex(const std::vector<FrameError>& frames, const MetricsOptions& o) {
  const size_t n = frames.size();
  if (n == 0) return 0;
  const double yaw_max = deg2rad(o.converge_yaw_deg);
  const int64_t hold_ns = static_cast<int64_t>(std::llround(o.converge_hold_s * 1e9));
  auto good = [&](const FrameError& f) { return f.pos_err < o.converge_pos_m && std::abs(f.yaw_err) < yaw_max; };
  // next_bad[i]: the first frame at or after i that is outside the bounds (n if none).
  std::vector<size_t> next_bad(n + 1, n);
  for (size_t i = n; i-- > 0;) next_bad[i] = good(frames[i]) ? next_bad[i + 1] : i;
  const int64_t last = frames.back().stamp_ns;
  for (size_t i = 0; i < n; ++i) {
    // Convergence starts at an estimate the filter calls tracking: a run that never claimed to
    // track, however close its initial guess, has not converged.
    if (frames[i].status != MclStatus::Tracking) continue;
    const int64_t until = frames[i].stamp_ns + hold_ns;
    if (until > last) break;  // not enough run left to show it holds
    if (next_bad[i] == n || frames[next_bad[i]].stamp_ns > until) return i;
  }
  return n;
}

}  // namespace

TrajectoryMetrics evaluateTrajectory(std::vector<EstimatedPose> estimates, const GroundTruth& truth,
                                     const MetricsOptions& o) {
  TrajectoryMetrics m;
  m.estimates = estimates.size();
  std::stable_sort(estimates.begin(), estimates.end(),
                   [](const EstimatedPose& a, const EstimatedPose& b) { return a.stamp_ns < b.stamp_ns; });
  const int64_t start = o.start_ns != 0 ? o.start_ns : (estimates.empty() ? 0 : estimates.front().stamp_ns);
  for (const EstimatedPose& e : estimates) {
    const std::optional<Pose> gt = domain::validPose(e.pose) ? truth.at(e.stamp_ns) : std::nullopt;
    if (!gt) {
      ++m.skipped;
      continue;
    }
    FrameError f;
    f.stamp_ns = e.stamp_ns;
    f.t_s = static_cast<double>(e.stamp_ns - start) * 1e-9;
    f.estimate = e.pose;
    f.truth = *gt;
    const Eigen::Vector3d d = e.pose.translation() - gt->translation();
    f.dx = d.x(), f.dy = d.y(), f.dz = d.z();
    f.pos_err = std::hypot(d.x(), d.y());
    // Euler differences: fine for ground robots (|pitch| far from 90 deg); angleDiff wraps at +-pi.
    f.yaw_err = angleDiff(e.pose.yaw(), gt->yaw());
    f.roll_err = angleDiff(e.pose.roll(), gt->roll());
    f.pitch_err = angleDiff(e.pose.pitch(), gt->pitch());
    f.status = e.status;
    const auto si = static_cast<size_t>(e.status);
    if (si < m.frames_by_status.size()) ++m.frames_by_status[si];
    m.frames.push_back(f);
  }
  m.all = summarize(m.frames);
  const size_t c = convergenceIndex(m.frames, o);
  if (c < m.frames.size()) {
    m.converged_at_ns = m.frames[c].stamp_ns;
    m.converged_after_s = static_cast<double>(m.converged_at_ns - start) * 1e-9;
    for (size_t i = c; i < m.frames.size(); ++i) m.frames[i].converged = true;
    m.after_convergence = summarize(std::span<const FrameError>(m.frames).subspan(c));
  } else {
    m.after_convergence = summarize({});
  }
  return m;
}

HeadingSplit splitByHeading(std::span<const FrameError> frames) {
  HeadingSplit h;
  if (frames.empty()) return h;
  for (const FrameError& f : frames) {
    const double c = std::cos(f.truth.yaw()), s = std::sin(f.truth.yaw());
    h.along_rmse_m += std::pow(c * f.dx + s * f.dy, 2);
    h.across_rmse_m += std::pow(-s * f.dx + c * f.dy, 2);
  }
  h.along_rmse_m = std::sqrt(h.along_rmse_m / double(frames.size()));
  h.across_rmse_m = std::sqrt(h.across_rmse_m / double(frames.size()));
  return h;
}

}  // namespace polyloc
