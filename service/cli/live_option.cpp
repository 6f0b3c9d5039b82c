#include "cli/live_option.hpp"

#include "cli/parse_number.hpp"
#include "pipeline/shm_payloads.hpp"

#include <fmt/core.h>

#include <thread>

namespace polyloc::cli {

void addLiveOptions(CLI::App& cmd, LiveArgs& a, bool pacing) {
  cmd.add_option("--live", a.port, "Serve the live view on this port while it runs: Foxglove ws://ADDRESS:PORT and a page on http://ADDRESS:PORT/ (docs/live.md)")
      ->check(CLI::Range(1, 65535));
  cmd.add_option("--live-address", a.address, "Address of the live view (default 127.0.0.1: this computer only)")->capture_default_str();
  if (pacing)
    cmd.add_option("--live-rate", a.rate, "With --live: pace the data to this many times real time (0: as fast as it computes)")
      ->capture_default_str()->check(finiteRange(0.0, 1e4));
  cmd.add_option("--live-linger", a.linger, "With --live: s to keep serving after the end")->capture_default_str()->check(finiteRange(0.0, 86400.0));
}

LiveHook::LiveHook(const LiveArgs& a, const Mesh& map, const Rig& rig, bool ground_truth) : args_(a) {
  if (a.port == 0) return;
  live::LiveConfig c;
  c.address = a.address, c.port = uint16_t(a.port), c.ground_truth = ground_truth;
  std::vector<std::string> names;
  for (const Sensor& s : rig.sensors) names.push_back(s.name);
  view_ = std::make_unique<live::LiveView>(c, map, rig, std::move(names));
  fmt::print(stderr, "live view on http://{}:{}/ (Foxglove: ws://{}:{})\n", a.address, view_->port(), a.address, view_->port());
}

LiveHook::~LiveHook() = default;

void LiveHook::pace(int64_t stamp_ns) {
  if (!first_ns_) first_ns_ = stamp_ns, start_ = std::chrono::steady_clock::now();
  if (args_.rate <= 0 || stamp_ns <= *first_ns_) return;
  const auto due = start_ + std::chrono::nanoseconds(int64_t(double(stamp_ns - *first_ns_) / args_.rate));
  std::this_thread::sleep_until(due);
}

void LiveHook::frame(size_t sensor, int64_t stamp_ns, std::span<const float> ranges) {
  if (!view_) return;
  pace(stamp_ns);
  view_->scan(sensor, stamp_ns, ranges);
}

void LiveHook::update(const MclEstimate& e, const ParticleSet& particles, const Pose& odom_T_base) {
  if (view_) view_->pose(e, e.pose * odom_T_base.inverse(), &particles);
}

void LiveHook::published(const polyloc_pose& p) {
  if (!view_) return;
  MclEstimate e;
  e.stamp_ns = p.stamp_ns, e.pose = pipeline::posePose(p);
  e.covariance = Eigen::Map<const Eigen::Matrix<double, 6, 6, Eigen::RowMajor>>(p.covariance);
  e.status = static_cast<MclStatus>(std::min<uint32_t>(p.status, 3));
  e.particles = p.particles, e.ess = p.ess, e.updates = p.updates;
  view_->pose(e, pipeline::mapOdomPose(p), nullptr);
}

void LiveHook::truth(int64_t stamp_ns, const Pose& map_T_base) {
  if (view_) view_->groundTruth(stamp_ns, map_T_base);
}

void LiveHook::finish() {
  if (!view_ || args_.linger <= 0) return;
  fmt::print(stderr, "live view: serving for {:.0f} s more (Ctrl-C ends it)\n", args_.linger);
  std::this_thread::sleep_for(std::chrono::duration<double>(args_.linger));
}

}  // namespace polyloc::cli
