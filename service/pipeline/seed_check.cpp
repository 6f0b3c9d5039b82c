#include "pipeline/seed_check.hpp"

#include <polyloc/geometry/domain.hpp>

namespace polyloc::pipeline {

std::optional<std::string> seedProblem(const protocol::PoseSeed& seed, double sigma_xy, double sigma_yaw,
                                       const Eigen::AlignedBox3f& map) {
  if (auto why = domain::checkPlanar(seed.x, seed.y, seed.yaw, map)) return why;
  if (auto why = domain::checkSpread("sigma_xy", sigma_xy, domain::kMaxPositionSigma)) return why;
  return domain::checkSpread("sigma_yaw", sigma_yaw, domain::kMaxAngle);
}

}  // namespace polyloc::pipeline
