// One-way latency of a message from a writer thread to a reader thread that sleeps until it
// arrives, over a shm channel (futex wake-up), a UNIX domain socket and loopback TCP: the
// measurement behind `polyloc bench ipc` (docs/interface.md, "Latency").
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace polyloc::engines {

struct IpcLatencyConfig {
  uint32_t bytes = 2180;        // a 541-beam scan: 16 + 541 * 4
  size_t messages = 20000;
  size_t warmup = 200;          // sent first, not counted
  double period_us = 50;        // one message every period: the reader has gone to sleep again
  int64_t spin_ns = 0;          // shm: Reader::wait spins this long before FUTEX_WAIT
  int writer_cpu = -1, reader_cpu = -1;   // pinning (-1: not pinned)
  int rt_priority = 0;          // > 0: both threads SCHED_FIFO at this priority (as a control loop runs)
};

struct IpcSamples {
  std::vector<int64_t> latency_ns;  // send call to the message copied out on the reader's side
  std::vector<int64_t> send_ns;     // how long the writer's send call took
};

// One sample per counted message that arrived. Throws std::runtime_error naming the transport and the failing call (also
// when rt_priority is refused).
IpcSamples shmLatency(const IpcLatencyConfig& c, const std::function<void(double)>& progress);
IpcSamples udsLatency(const IpcLatencyConfig& c, const std::function<void(double)>& progress);
IpcSamples tcpLatency(const IpcLatencyConfig& c, const std::function<void(double)>& progress);

}  // namespace polyloc::engines
