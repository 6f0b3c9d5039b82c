// `--live PORT` of the CLI (polyloc localize, play): the live view of polylocd (docs/live.md) on
// what the command computes (localize) or sees (play: polylocd's poses beside the truth), paced to the data's time so that a viewer sees it
// as it happened (`--live-rate`), and kept open for `--live-linger` seconds at the end.
#pragma once

#include "live/live_view.hpp"

#include <CLI/CLI.hpp>

#include <chrono>
#include <memory>
#include <optional>

namespace polyloc::cli {

struct LiveArgs {
  int port = 0;  // 0: no live view
  std::string address = "127.0.0.1";
  double rate = 1.0;  // times real time; 0: as fast as it computes
  double linger = 0;  // s to keep serving after the end
};
// pacing: --live-rate too (a command that runs as fast as it computes).
void addLiveOptions(CLI::App& cmd, LiveArgs& a, bool pacing = true);

class LiveHook {
 public:
  // Binds now (throws std::runtime_error naming address:port); does nothing when a.port is 0.
  // ground_truth: a /ground_truth channel too (play: the source's truth beside polylocd's poses).
  LiveHook(const LiveArgs& a, const Mesh& map, const Rig& rig, bool ground_truth = false);
  ~LiveHook();
  bool on() const { return view_ != nullptr; }
  void frame(size_t sensor, int64_t stamp_ns, std::span<const float> ranges);
  void update(const MclEstimate& e, const ParticleSet& particles, const Pose& odom_T_base);
  void published(const polyloc_pose& p);  // a pose polylocd published (polyloc play)
  void truth(int64_t stamp_ns, const Pose& map_T_base);
  void finish();  // lingers

 private:
  void pace(int64_t stamp_ns);
  LiveArgs args_;
  std::unique_ptr<live::LiveView> view_;
  std::optional<int64_t> first_ns_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace polyloc::cli
