// polylocd's work: the segment with its channel table, one thread that takes the input frames
// the input gate lets through (pipeline/input_gate.hpp: read, validate, clock, order; woken by the
// segment's doorbell), feeds the pipeline inside a TBB arena and writes pose, VRS, tracks and
// health back. Bad frames are rejected, counted per input and reason, logged (rate-limited),
// never fatal.
//
//   Daemon d(loadServiceConfig(file));   // loads the map, builds the caster, creates the segment
//   d.run(stop_flag);                    // until stop_flag; then the segment says STOPPED
#pragma once

#include "pipeline/channels.hpp"
#include "pipeline/daemon_config.hpp"
#include "pipeline/live_state.hpp"
#include "shm/segment.hpp"

#include <Eigen/Geometry>
#include <atomic>
#include <memory>

namespace polyloc::pipeline {

class Daemon {
 public:
  explicit Daemon(ServiceConfig config);
  ~Daemon();

  void run(const std::atomic<bool>& stop);
  const ServiceConfig& config() const { return cfg_; }
  const ChannelTable& channels() const { return table_; }
  LiveState& live() { return *live_; }  // for the control endpoint (thread-safe)
  const Eigen::AlignedBox3f& mapBounds() const;  // poses beyond it plus domain::kMapMargin are refused

 private:
  struct Impl;
  ServiceConfig cfg_;
  ChannelTable table_;
  std::unique_ptr<LiveState> live_;
  std::unique_ptr<Impl> impl_;
  bool ran_ = false;  // a daemon destroyed before run() stops its segment: no "starting" left behind
};

}  // namespace polyloc::pipeline
