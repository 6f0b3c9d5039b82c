#include "cli/localize_report.hpp"

#include <fmt/core.h>

#include <cmath>
#include <fstream>
#include <stdexcept>

namespace polyloc::cli {

nlohmann::json num(double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr); }

nlohmann::json summaryJson(const ErrorSummary& s) {
  return {{"frames", s.frames},
          {"ate_rmse_m", num(s.ate_rmse_m)},
          {"mean_pos_err_m", num(s.mean_pos_err_m)},
          {"p95_pos_err_m", num(s.p95_pos_err_m)},
          {"max_pos_err_m", num(s.max_pos_err_m)},
          {"yaw_rmse_deg", num(s.yaw_rmse_deg)},
          {"p95_yaw_err_deg", num(s.p95_yaw_err_deg)},
          {"max_yaw_err_deg", num(s.max_yaw_err_deg)},
          {"z_rmse_m", num(s.z_rmse_m)},
          {"max_z_err_m", num(s.max_z_err_m)},
          {"roll_pitch_rmse_deg", num(s.roll_pitch_rmse_deg)},
          {"max_roll_pitch_err_deg", num(s.max_roll_pitch_err_deg)}};
}

void writeCsv(const std::string& path, const TrajectoryMetrics* metrics, const std::vector<EstimatedPose>& est) {
  std::ofstream f(path);
  if (!f) throw std::runtime_error(fmt::format("{}: cannot write", path));
  auto pose = [](const Pose& p) {
    return fmt::format("{:.6f},{:.6f},{:.6f},{:.4f},{:.4f},{:.4f}", p.x(), p.y(), p.z(), rad2deg(p.roll()),
                       rad2deg(p.pitch()), rad2deg(p.yaw()));
  };
  f << "stamp_ns,x,y,z,roll_deg,pitch_deg,yaw_deg,status";
  if (!metrics) {
    f << "\n";
    for (const auto& e : est) f << fmt::format("{},{},{}\n", e.stamp_ns, pose(e.pose), toString(e.status));
  } else {
    f << ",t_s,gt_x,gt_y,gt_z,gt_roll_deg,gt_pitch_deg,gt_yaw_deg,dx,dy,dz,pos_err_m,yaw_err_deg,roll_err_deg,"
         "pitch_err_deg,converged\n";
    for (const auto& e : metrics->frames)
      f << fmt::format("{},{},{},{:.6f},{},{:.6f},{:.6f},{:.6f},{:.6f},{:.4f},{:.4f},{:.4f},{}\n", e.stamp_ns,
                       pose(e.estimate), toString(e.status), e.t_s, pose(e.truth), e.dx, e.dy, e.dz, e.pos_err,
                       rad2deg(e.yaw_err), rad2deg(e.roll_err), rad2deg(e.pitch_err), e.converged ? 1 : 0);
  }
  if (!f) throw std::runtime_error(fmt::format("{}: write failed", path));
}

}  // namespace polyloc::cli
