#include "pipeline/localizer_worker.hpp"

#include <spdlog/spdlog.h>
#include <tbb/task_arena.h>

#include <algorithm>

namespace polyloc::pipeline {

struct LocalizerWorker::Job {
  enum class Kind { Odometry, Scan, InitPose, InitGlobal } kind = Kind::Odometry;
  int64_t stamp = 0;
  Pose pose;
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();
  size_t sensor = 0;
  std::vector<float> ranges;
  uint64_t tag = 0, epoch = 0;
  size_t bytes() const { return sizeof(Job) + ranges.size() * sizeof(float); }
};

struct LocalizerWorker::ArenaHolder {
  tbb::task_arena arena;
  explicit ArenaHolder(int threads) : arena(threads > 0 ? threads : tbb::task_arena::automatic) {}
};

LocalizerWorker::LocalizerWorker(std::unique_ptr<Localizer> loc, LocalizerWorkerConfig config)
    : loc_(std::move(loc)), cfg_(config) {
  if (!cfg_.threaded) return;
  arena_ = std::make_unique<ArenaHolder>(cfg_.threads);
  thread_ = std::thread([this] { loop(); });
}

LocalizerWorker::~LocalizerWorker() {
  if (!thread_.joinable()) return;
  {
    std::lock_guard lock(m_);
    stop_ = true;
    queue_.clear();
  }
  wake_.notify_all();
  thread_.join();
}

void LocalizerWorker::addOdometry(int64_t stamp_ns, const Pose& odom_T_base) {
  Job j;
  j.kind = Job::Kind::Odometry, j.stamp = stamp_ns, j.pose = odom_T_base;
  submit(std::move(j));
}

void LocalizerWorker::addScan(size_t sensor, int64_t stamp_ns, std::span<const float> ranges, uint64_t tag) {
  Job j;
  j.kind = Job::Kind::Scan, j.stamp = stamp_ns, j.sensor = sensor, j.tag = tag;
  j.ranges.assign(ranges.begin(), ranges.end());
  submit(std::move(j));
}

void LocalizerWorker::initPose(const Pose& map_T_base, const Eigen::Matrix<double, 6, 6>& covariance, int64_t stamp_ns) {
  Job j;
  j.kind = Job::Kind::InitPose, j.stamp = stamp_ns, j.pose = map_T_base, j.covariance = covariance;
  submit(std::move(j));
}

void LocalizerWorker::initGlobal(int64_t stamp_ns) {
  Job j;
  j.kind = Job::Kind::InitGlobal, j.stamp = stamp_ns;
  submit(std::move(j));
}

void LocalizerWorker::submit(Job job) {
  std::unique_lock lock(m_);
  if (job.kind == Job::Kind::InitPose || job.kind == Job::Kind::InitGlobal) {
    ++epoch_;
    done_.clear();
    // Odometry stays: the buffer must see every message to interpolate the frames after.
    const auto before = queue_.size();
    std::erase_if(queue_, [](const Job& q) { return q.kind == Job::Kind::Scan; });
    counters_.cancelled += before - queue_.size();
    queued_bytes_ = 0;
    for (const Job& q : queue_) queued_bytes_ += q.bytes();
  }
  job.epoch = epoch_;
  if (!cfg_.threaded) {
    lock.unlock();
    return runJob(job);
  }
  queued_bytes_ += job.bytes();
  queue_.push_back(std::move(job));
  // Over budget: the oldest frames go first; what is left of the search uses the newer ones.
  while (queued_bytes_ > cfg_.max_queue_bytes) {
    auto it = std::find_if(queue_.begin(), queue_.end(), [](const Job& q) { return q.kind == Job::Kind::Scan; });
    if (it == queue_.end() || std::next(it) == queue_.end()) break;  // never the frame just given
    queued_bytes_ -= it->bytes();
    queue_.erase(it);
    if (counters_.dropped++ == 0)
      spdlog::warn("localiser: frames queued behind the global search beyond {} MiB: the oldest are dropped (counted)",
                   cfg_.max_queue_bytes >> 20);
  }
  lock.unlock();
  wake_.notify_one();
}

void LocalizerWorker::runJob(Job& j) {
  try {
    switch (j.kind) {
      case Job::Kind::Odometry: loc_->addOdometry(j.stamp, j.pose); break;
      case Job::Kind::InitPose: loc_->initPose(j.pose, j.covariance, j.stamp); break;
      case Job::Kind::InitGlobal: loc_->initGlobal(j.stamp); break;
      case Job::Kind::Scan: {
        if (!loc_->addScan(j.sensor, j.stamp, j.ranges)) break;
        Round r{loc_->estimate(), loc_->odometryAt(j.stamp), loc_->searching(), j.tag, nullptr};
        if (cfg_.copy_particles) r.particles = std::make_shared<const ParticleSet>(loc_->particles());
        std::lock_guard lock(m_);
        if (j.epoch == epoch_) done_.push_back(std::move(r));
        break;
      }
    }
  } catch (const std::exception& e) {
    // The localiser rejects bad input by counting it; a throw is a defect, not a reason to stop.
    std::lock_guard lock(m_);
    if (counters_.failed++ < 10) spdlog::error("localiser: a job at stamp {} failed: {}", j.stamp, e.what());
  }
}

void LocalizerWorker::loop() {
  for (;;) {
    Job j;
    {
      std::unique_lock lock(m_);
      wake_.wait(lock, [&] { return stop_ || !queue_.empty(); });
      if (stop_) return;
      j = std::move(queue_.front());
      queue_.pop_front();
      queued_bytes_ -= j.bytes();
      busy_ = true;
    }
    arena_->arena.execute([&] { runJob(j); });
    {
      std::lock_guard lock(m_);
      busy_ = false;
    }
    idle_.notify_all();
  }
}

std::vector<LocalizerWorker::Round> LocalizerWorker::take() {
  std::lock_guard lock(m_);
  std::vector<Round> out;
  out.swap(done_);
  return out;
}

bool LocalizerWorker::idle() const {
  std::lock_guard lock(m_);
  return !busy_ && queue_.empty();
}

void LocalizerWorker::waitIdle() const {
  std::unique_lock lock(m_);
  idle_.wait(lock, [&] { return !busy_ && queue_.empty(); });
}

LocalizerWorker::Counters LocalizerWorker::counters() const {
  std::lock_guard lock(m_);
  return counters_;
}

}  // namespace polyloc::pipeline
