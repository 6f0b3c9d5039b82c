#include "engines/drive_loop.hpp"

#include "shm/validate.hpp"

#include <polyloc/tracking/people_tracker.hpp>

#include <fmt/core.h>

#include <chrono>
#include <cstring>
#include <thread>

namespace polyloc::engines {
namespace {

using Clock = std::chrono::steady_clock;

// Collects one event's messages.
class Collect final : public RecordingWriter {
 public:
  void write(const std::string& topic, int64_t log_time_ns, const msg::Message& m) override {
    out.push_back({topic, log_time_ns, log_time_ns, m});
  }
  void close() override {}
  std::vector<RecordedMessage> out;
};

}  // namespace

DriveLoop::DriveLoop(Simulator& sim, const std::string& instance, const DriveLoopOptions& options)
    : sim_(sim), opt_(options), feed_(instance, options.wait_attach_s), drive_(std::make_unique<DriveSim>(sim, options.drive)) {
  attachReaders();
  // polylocd renews the VRS at the frames of the last level scanner (pipeline.cpp).
  const auto& cfg = sim.scenario().config;
  PeopleTracker tracker(cfg.rig, cfg.tracking);
  if (!tracker.sensors().empty()) trigger_topic_ = "/scan/" + cfg.rig.sensors[tracker.sensors().back()].name;
  start_ns_ = sim.scenario().start_time_ns;
  // Faster or slower than real time needs polylocd on the source clock; then the scenario's own
  // stamps make the run the same whenever it is started (the localiser's random numbers are keyed
  // by stamps). At real time, stamps move onto the wall clock as in `polyloc play`.
  if (options.rate != 1.0) feed_.keepSourceStamps(start_ns_);
  t0_ = Clock::now();
}

DriveLoop::~DriveLoop() = default;

// The VRS and cmd_vel readers on the segment the feed is attached to: again after a restart of
// polylocd (the feed re-attaches; readers left on the dead segment would wait for ever).
void DriveLoop::attachReaders() {
  const shm::Segment& seg = feed_.segment();
  const int vrs = seg.find("vrs"), cmd = seg.find("cmd_vel");
  const std::string& instance = seg.instance();
  if (cmd < 0)
    throw std::runtime_error(fmt::format("polylocd '{}' has no cmd_vel channel: it is older than this polyloc "
                                         "(restart it from this build)", instance));
  if (vrs < 0) throw std::runtime_error(fmt::format("polylocd '{}' has no vrs channel", instance));
  vrs_ = std::make_unique<shm::Reader>(seg, vrs, shm::Reader::Start::Next);
  cmd_ = std::make_unique<shm::Reader>(seg, cmd, shm::Reader::Start::Next);
  if (readers_at_ != 0) ++counters_.reattached;
  readers_at_ = feed_.attachments();
  counters_.commands_since_attach = 0;
}

// False while polylocd is away; the readers follow the feed to a new segment.
bool DriveLoop::readersUp() {
  if (!feed_.up()) return false;
  if (feed_.attachments() != readers_at_) attachReaders();
  return true;
}

bool DriveLoop::waitFor(shm::Reader& r, int64_t stamp, double wait_s, bool at_least) {
  const auto deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(wait_s));
  for (;;) {
    while (auto f = r.next(buf_)) {
      if (&r == cmd_.get()) {
        // Handled like every command (readCommands), then checked against the stamp waited for.
        const int64_t s = f->stamp_ns;
        const shm::Validation v = shm::validateInput(r.channel(), f->frame, buf_.data(), buf_.size(),
                                                     {.now_ns = s, .last_ns = last_cmd_stamp_, .max_age_ns = -1, .max_future_ns = -1});
        if (!v) {
          ++counters_.commands_rejected;
          continue;
        }
        polyloc_command c;
        std::memcpy(&c, buf_.data(), sizeof c);
        last_cmd_stamp_ = c.stamp_ns;
        ++counters_.commands, ++counters_.commands_since_attach;
        last_status_ = c.status;
        drive_->command({c.stamp_ns - feed_.baseNs(), c.vx, c.vy, c.wz});
        if (on_command) on_command(c, double(c.stamp_ns - feed_.baseNs()) * 1e-9);
        if (s >= stamp) return true;
      } else if (at_least ? f->stamp_ns >= stamp : f->stamp_ns == stamp) {
        return true;
      }
    }
    if (Clock::now() >= deadline) return false;
    feed_.watch();
    if (!feed_.up() || feed_.attachments() != readers_at_) return false;  // polylocd went: do not wait for it
    if (&r == cmd_.get() && controller_alive && !controller_alive()) {  // it ended without answering
      controller_gone_ = true;
      return false;
    }
    r.wait(2'000'000);
    feed_.poll();
  }
}

bool DriveLoop::waitForController(double timeout_s, const std::function<bool()>& alive) {
  const auto deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(timeout_s));
  const polyloc_ring_control* ring = feed_.segment().ring(feed_.segment().find("cmd_vel"));
  while (__atomic_load_n(&ring->writer_pid, __ATOMIC_ACQUIRE) == 0) {
    if (Clock::now() >= deadline || (alive && !alive())) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  t0_ = Clock::now();
  return true;
}

void DriveLoop::readCommands() {
  if (readersUp()) waitFor(*cmd_, INT64_MAX, 0, true);
}

void DriveLoop::step() {
  const int64_t t = drive_->nextEventNs();
  // Pace: the event's simulated time against the wall clock at `rate`.
  const auto due = t0_ + std::chrono::nanoseconds(int64_t(double(t) / opt_.rate));
  while (Clock::now() < due) {
    feed_.poll();
    readCommands();
    std::this_thread::sleep_until(std::min(due, Clock::now() + std::chrono::milliseconds(2)));
  }
  Collect c;
  drive_->step(c);
  ++counters_.steps;
  // The VRS trigger's frames go last, after every other frame of their instant (polylocd sorts
  // them last too): its VRS comes when everything of that instant has been taken. (A run is the
  // same every time when every sensor's frames fall on odometry ticks, as in lab_nav.yaml: then
  // polylocd never extrapolates odometry, whichever frames its read passes group.)
  std::vector<int64_t> triggers;
  std::vector<RecordedMessage> trigger_frames;
  for (const RecordedMessage& m : c.out) {
    if (m.topic == trigger_topic_) trigger_frames.push_back(m);
    else feed_.send(m, 0, start_ns_);
  }
  for (const RecordedMessage& m : trigger_frames) {
    feed_.send(m, 0, start_ns_);
    triggers.push_back(m.log_time_ns - start_ns_);
  }
  feed_.poll();
  for (int64_t t_trigger : triggers) {
    ++counters_.triggers;
    const int64_t stamp = feed_.baseNs() + t_trigger;
    if (!readersUp() || !waitFor(*vrs_, stamp, opt_.wait_vrs_s, false)) ++counters_.vrs_missed;
    else if (!controller_gone_ && !waitFor(*cmd_, stamp, opt_.wait_command_s, true) && !controller_gone_)
      ++counters_.commands_late;
  }
  readCommands();
}

}  // namespace polyloc::engines
