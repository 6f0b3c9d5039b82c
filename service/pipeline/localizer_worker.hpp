// The localiser behind a queue: odometry, frames and (re)starts go in in order and are run in
// that order, so the estimates are the ones the localiser gives when called directly, whatever
// the timing. Threaded (polylocd's `global_search: beside`), the jobs run on a thread of their
// own in a TBB arena of their own, and a global search (100,000 particles, 0.3-0.6 s a round)
// no longer holds up the caller's VRS, tracks and health; inline, each job runs in the caller.
//
//   LocalizerWorker w(std::move(localizer), {.threaded = true, .threads = 2});
//   w.addOdometry(t, odom_T_base);
//   w.addScan(sensor, t, ranges, tag);      // copies the ranges
//   for (auto& r : w.take()) publish(r);    // rounds ended since the last take, in order
//   w.waitIdle();                           // every job given is done (take() has them)
#pragma once

#include <polyloc/mcl/localizer.hpp>

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <span>
#include <thread>
#include <vector>

namespace polyloc::pipeline {

struct LocalizerWorkerConfig {
  bool threaded = false;
  int threads = 0;                 // the worker's TBB arena (0: all cores); threaded only
  bool copy_particles = false;     // each round's particles with its estimate (the live view)
  // Frames queued behind a slow round beyond this many bytes: the oldest queued frame is
  // dropped and counted (odometry is never dropped). 30 s of a 640x480 camera at 30 Hz
  // would be 1 GiB; a scanner's frame is a few KiB.
  size_t max_queue_bytes = size_t(256) << 20;
};

class LocalizerWorker {
 public:
  // A round the localiser ended (Localizer::addScan returned true).
  struct Round {
    MclEstimate estimate;
    Pose odom_at_stamp;                           // the odometry at the closing frame's stamp
    bool searching = false;                       // Localizer::searching() after the round
    uint64_t tag = 0;                             // addScan's tag of the closing frame
    std::shared_ptr<const ParticleSet> particles;  // copy_particles only
  };
  struct Counters {
    uint64_t dropped = 0;    // frames dropped from a full queue (max_queue_bytes)
    uint64_t cancelled = 0;  // queued frames a (re)start made obsolete
    uint64_t failed = 0;     // jobs that threw (logged; the localiser goes on)
  };

  LocalizerWorker(std::unique_ptr<Localizer> loc, LocalizerWorkerConfig config);
  ~LocalizerWorker();  // drops what is queued, waits for the job that runs
  LocalizerWorker(const LocalizerWorker&) = delete;
  LocalizerWorker& operator=(const LocalizerWorker&) = delete;

  void addOdometry(int64_t stamp_ns, const Pose& odom_T_base);
  void addScan(size_t sensor, int64_t stamp_ns, std::span<const float> ranges, uint64_t tag);
  // A (re)start drops the frames still queued (they are older than it) and the rounds not yet
  // taken: what the old particles would have said is no longer wanted.
  void initPose(const Pose& map_T_base, const Eigen::Matrix<double, 6, 6>& covariance, int64_t stamp_ns);
  void initGlobal(int64_t stamp_ns);

  std::vector<Round> take();
  bool idle() const;  // nothing queued or running: every round ended is in take()
  void waitIdle() const;
  Counters counters() const;

  // The localiser itself: its const state may be read only inline, or while idle().
  const Localizer& localizer() const { return *loc_; }

 private:
  struct Job;
  void submit(Job job);
  void runJob(Job& job);
  void loop();

  std::unique_ptr<Localizer> loc_;
  LocalizerWorkerConfig cfg_;
  struct ArenaHolder;
  std::unique_ptr<ArenaHolder> arena_;
  mutable std::mutex m_;
  mutable std::condition_variable wake_, idle_;
  std::deque<Job> queue_;
  size_t queued_bytes_ = 0;
  bool busy_ = false, stop_ = false;
  uint64_t epoch_ = 0;  // bumped by each (re)start; rounds of an older one are not handed out
  std::vector<Round> done_;
  Counters counters_;
  std::thread thread_;
};

}  // namespace polyloc::pipeline
