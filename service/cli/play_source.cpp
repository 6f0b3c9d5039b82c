#include "cli/play_source.hpp"

#include <polyloc/sim/scenario.hpp>
#include <polyloc/sim/simulator.hpp>

#include <condition_variable>
#include <deque>
#include <exception>
#include <mutex>
#include <thread>

namespace polyloc::cli {
namespace play_source_impl {  // named, not anonymous: the CLI is compiled in batches (unity build)

class RecordingSource final : public PlaySource {
 public:
  explicit RecordingSource(const std::string& path) : path_(path), reader_(openRecording(path)) {
    const RecordingSpan s = spanOf(reader_->topics());
    duration_ = double(s.last_ns - s.first_ns) * 1e-9;
  }
  bool next(RecordedMessage& out) override { return reader_->next(out); }
  double durationS() const override { return duration_; }
  std::string describe() const override { return path_ + " (" + reader_->format() + ")"; }

 private:
  std::string path_;
  std::unique_ptr<RecordingReader> reader_;
  double duration_ = 0;
};

// The simulator writes into this queue; it blocks when `capacity` messages wait, so the
// simulation stays a few seconds ahead of playback and memory stays flat for long scenarios.
class QueueWriter final : public RecordingWriter {
 public:
  explicit QueueWriter(size_t capacity) : capacity_(capacity) {}
  void write(const std::string& topic, int64_t log_time_ns, const msg::Message& m) override {
    std::unique_lock l(m_);
    not_full_.wait(l, [&] { return q_.size() < capacity_ || cancelled_; });
    if (cancelled_) throw Cancelled{};
    q_.push_back({topic, log_time_ns, log_time_ns, m});
    not_empty_.notify_one();
  }
  void close() override { finish(nullptr); }
  void finish(std::exception_ptr e) {
    std::lock_guard l(m_);
    done_ = true, error_ = e;
    not_empty_.notify_all();
  }
  bool pop(RecordedMessage& out) {
    std::unique_lock l(m_);
    not_empty_.wait(l, [&] { return !q_.empty() || done_; });
    if (q_.empty()) {
      if (error_) std::rethrow_exception(error_);
      return false;
    }
    out = std::move(q_.front());
    q_.pop_front();
    not_full_.notify_one();
    return true;
  }
  void cancel() {
    std::lock_guard l(m_);
    cancelled_ = true;
    not_full_.notify_all();
  }
  struct Cancelled {};

 private:
  std::mutex m_;
  std::condition_variable not_full_, not_empty_;
  std::deque<RecordedMessage> q_;
  size_t capacity_;
  bool done_ = false, cancelled_ = false;
  std::exception_ptr error_;
};

class ScenarioSource final : public PlaySource {
 public:
  ScenarioSource(const std::string& path, double duration_s) : path_(path), queue_(20000) {
    Scenario s = loadScenario(path);
    sim_ = std::make_unique<Simulator>(s, loadScenarioMap(s));
    // Cut short, never lengthen: a scenario run past its route only stands still (--loop
    // repeats the route instead).
    if (duration_s > 0 && duration_s < sim_->duration()) {
      s.duration = duration_s;
      sim_ = std::make_unique<Simulator>(s, loadScenarioMap(s));
    }
    thread_ = std::thread([this] {
      try {
        sim_->run(queue_);
        queue_.finish(nullptr);
      } catch (const QueueWriter::Cancelled&) {
        queue_.finish(nullptr);
      } catch (...) {
        queue_.finish(std::current_exception());
      }
    });
  }
  ~ScenarioSource() override {
    queue_.cancel();
    if (thread_.joinable()) thread_.join();
  }
  bool next(RecordedMessage& out) override { return queue_.pop(out); }
  double durationS() const override { return sim_->duration(); }
  std::string describe() const override { return path_ + " (live simulation)"; }
  const Mesh* map() const override { return &sim_->world(); }

 private:
  std::string path_;
  QueueWriter queue_;
  std::unique_ptr<Simulator> sim_;
  std::thread thread_;
};

}  // namespace play_source_impl

std::unique_ptr<PlaySource> playRecording(const std::string& path) {
  return std::make_unique<play_source_impl::RecordingSource>(path);
}
std::unique_ptr<PlaySource> playScenario(const std::string& path, double duration_s) {
  using namespace play_source_impl;
  return std::make_unique<ScenarioSource>(path, duration_s);
}

}  // namespace polyloc::cli
