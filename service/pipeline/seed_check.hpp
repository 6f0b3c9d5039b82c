// SETPOSE's values against their domain (docs/failure.md): the seed's pose inside the map's box
// plus domain::kMapMargin, yaw and spreads within their limits. Its own file so that the control
// fuzzer (fuzz/fuzz_control_values.cpp) checks the very rule polylocd applies.
#pragma once

#include "protocol/handler.hpp"

#include <Eigen/Geometry>
#include <optional>
#include <string>

namespace polyloc::pipeline {

// The reason the seed is refused, or nothing. sigma_xy / sigma_yaw: the spreads that will be
// used (the seed's, or the defaults).
std::optional<std::string> seedProblem(const protocol::PoseSeed& seed, double sigma_xy, double sigma_yaw,
                                       const Eigen::AlignedBox3f& map);

}  // namespace polyloc::pipeline
