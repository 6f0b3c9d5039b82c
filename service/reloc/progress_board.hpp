// The progress line of `polyloc relocalize` on a terminal (stderr): overall and per running
// task. Tasks report from any thread; drawing is throttled and never waits for a lock.
#pragma once

#include <atomic>
#include <chrono>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace polyloc::reloc {

class ProgressBoard {
 public:
  // labels: one per task of this process; enabled false: say nothing (not a terminal).
  ProgressBoard(std::vector<std::string> labels, bool enabled);
  void start(size_t task);
  void update(size_t task, double fraction);
  void finish(size_t task);
  // A line of its own (a failure, a warning), above the bar.
  void message(const std::string& line);
  void close();  // the final bar and a newline

 private:
  void draw(bool force);
  std::vector<std::string> labels_;
  std::unique_ptr<std::atomic<float>[]> fraction_;  // < 0: not started, > 1: done
  bool enabled_;
  std::mutex draw_;
  std::chrono::steady_clock::time_point last_{};
};

}  // namespace polyloc::reloc
