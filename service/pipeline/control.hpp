// polylocd's side of the TCP control endpoint (service/protocol): answers from what the pipeline
// last published (LiveState) and posts SETPOSE / global localisation / collision-avoidance
// switches to the pipeline thread, which takes them at its next cycle. Scanner 0 is the VRS,
// then the planar scanners of the rig in rig order (GETSCANRADIALSCANNER).
#pragma once

#include "pipeline/daemon_config.hpp"
#include "pipeline/live_state.hpp"
#include "protocol/handler.hpp"

#include <Eigen/Geometry>
#include <chrono>
#include <mutex>
#include <vector>

namespace polyloc::pipeline {

class DaemonControl final : public protocol::ControlHandler {
 public:
  // input_names: the input channels in health order.
  // map: the map's bounding box; SETPOSE beyond it plus domain::kMapMargin is bad_argument.
  DaemonControl(LiveState& live, const ServiceConfig& config, std::vector<std::string> input_names,
                const Eigen::AlignedBox3f& map);

  std::optional<protocol::PoseReport> pose() override;
  protocol::Status setPose(const protocol::PoseSeed& seed) override;
  protocol::Status globalLocalization() override;
  std::vector<protocol::ScannerInfo> scanners() override;
  std::optional<protocol::PolarScan> scan(uint32_t index) override;
  bool collisionAvoidance() override;
  void setCollisionAvoidance(bool on) override;
  protocol::TrackList tracks() override;
  protocol::HealthReport health() override;

 private:
  LiveState& live_;
  const ServiceConfig& cfg_;
  std::vector<std::string> inputs_;
  Eigen::AlignedBox3f map_;
  std::vector<size_t> scanners_;  // rig indices of scanners()[1..]
  uint32_t vrs_segments_ = 0;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  // For rates: the health seen at the previous health() call.
  std::mutex m_;
  std::optional<polyloc_health> prev_;
  std::chrono::steady_clock::time_point prev_time_;
};

}  // namespace polyloc::pipeline
