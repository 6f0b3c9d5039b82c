#include "pipeline/input_gate.hpp"

#include <fmt/core.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cstring>
#include <ctime>
#include <iterator>

namespace polyloc::pipeline {
namespace {
constexpr int64_t kMaxSleepNs = 20'000'000;  // health and silence checks go on at least this often
}  // namespace

int64_t clockNs(clockid_t clock) {
  timespec ts{};
  clock_gettime(clock, &ts);
  return int64_t(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

InputGate::InputGate(shm::Segment& seg, const ChannelTable& table, const DaemonConfig& cfg, TimeJump on_jump)
    : seg_(seg), table_(table), cfg_(cfg), on_jump_(std::move(on_jump)),
      clock_(cfg.max_age_ns, cfg.max_future_ns, cfg.clock_agree) {
  for (int ch : table_.inputs) readers_.emplace_back(seg_, ch, shm::Reader::Start::Next);
  const size_t n = table_.inputs.size();
  health_.assign(n, polyloc_input_health{});
  for (auto& h : health_) h.silent = 1;  // until the first frame
  last_taken_mono_.assign(n, 0);
  announced_.assign(n, false);
  logged_.assign(n, 0);
  const auto odom = std::find(table_.inputs.begin(), table_.inputs.end(), table_.odom);
  if (odom != table_.inputs.end()) odom_input_ = int(odom - table_.inputs.begin());
}

const polyloc_channel_desc& InputGate::desc(size_t input) const { return seg_.channel(table_.inputs[input]); }

int64_t InputGate::now() const { return cfg_.source_clock && clock_.started() ? clock_.now() : clockNs(CLOCK_REALTIME); }

void InputGate::reject(size_t input, const shm::Validation& v) {
  polyloc_input_health& h = health_[input];
  switch (v.reject) {
    case shm::Reject::Size: ++h.rejected_size; break;
    case shm::Reject::NaN: ++h.rejected_nan; break;
    case shm::Reject::Stale: ++h.rejected_stale; break;
    case shm::Reject::Future: ++h.rejected_future; break;
    case shm::Reject::None: return;
  }
  // The first few of each input, then every 1000th: a flood of bad frames must not flood the log.
  const uint64_t k = logged_[input]++;
  if (k < 5 || k % 1000 == 0) spdlog::warn("rejected ({}): {}{}", shm::toString(v.reject), v.why, k >= 5 ? " (and more)" : "");
}

// The stamp rules of clock: source (SourceClock); true when the frame is taken.
bool InputGate::admit(size_t i, int64_t stamp) {
  using V = SourceClock::Verdict;
  const int64_t before = clock_.now();
  const V v = clock_.judge(i, stamp, health_[i].last_stamp_ns);
  if (v == V::Take) {
    clock_.taken(stamp);
    return true;
  }
  shm::Validation why;
  why.reject = v == V::Future ? shm::Reject::Future : shm::Reject::Stale;
  if (v == V::Repeat) {
    why.why = fmt::format("{} frame stamped {} ns: not after the last frame's {}", desc(i).name, stamp, health_[i].last_stamp_ns);
    reject(i, why);
    return false;
  }
  why.why = fmt::format("{} frame stamped {} ns: {:.3f} s {} the source clock ({} ns; max_{} {:.3f} s)", desc(i).name, stamp,
                        std::abs(double(static_cast<__int128>(stamp) - before)) * 1e-9, v == V::Stale ? "before" : "after", before,
                        v == V::Stale ? "age" : "future", double(v == V::Stale ? cfg_.max_age_ns : cfg_.max_future_ns) * 1e-9);
  reject(i, why);
  if (clock_.refused(i, stamp)) {
    // What was held of the old time goes: stamps, frames taken and waiting.
    for (auto& h : health_) h.last_stamp_ns = 0;
    ready_.clear(), held_.clear();
    on_jump_(before, clock_.now());
  }
  return false;
}

bool InputGate::read() {
  ready_.clear();
  bool any = false;
  // One `now` for the whole pass: with clock: source, a backlog read in one pass must not
  // make the slower channels' frames stale against the faster ones' newest stamps.
  const bool source = cfg_.source_clock;
  const int64_t now_ns = now();
  clock_.beginPass();
  // What every channel holds at one instant, and no more: a frame published while this pass
  // reads is newer than all of them (writers publish in stamp order), so the sorted pass never
  // puts a scan after odometry that came later than it. The counts are taken twice until both
  // agree: a frame published between two channels' counts would otherwise be left to the next
  // pass while one published after it is taken (a read thread pre-empted between the counts).
  std::vector<uint64_t> limit(readers_.size()), again(readers_.size());
  for (int tries = 0; tries < 100; ++tries) {
    for (size_t i = 0; i < readers_.size(); ++i) limit[i] = readers_[i].available();
    for (size_t i = 0; i < readers_.size(); ++i) again[i] = readers_[i].available();
    if (limit == again) break;
  }
  for (size_t i = 0; i < readers_.size(); ++i) {
    std::vector<uint8_t> buf;
    for (uint64_t k = 0; k < limit[i]; ++k) {
      auto f = readers_[i].next(buf);
      if (!f) break;
      any = true;
      shm::StampRules rules;
      rules.now_ns = now_ns;
      // source: SourceClock judges order too (a time that jumped back is a vote, not a repeat).
      rules.last_ns = health_[i].last_stamp_ns && !source ? health_[i].last_stamp_ns : INT64_MIN;
      rules.max_age_ns = source ? -1 : cfg_.max_age_ns;  // source: SourceClock judges age and future
      rules.max_future_ns = source ? -1 : cfg_.max_future_ns;
      const shm::Validation v = shm::validateInput(desc(i), f->frame, buf.data(), buf.size(), rules);
      if (!v) {
        reject(i, v);
        continue;
      }
      int64_t stamp = 0;
      std::memcpy(&stamp, buf.data(), sizeof stamp);  // every input payload starts with stamp_ns
      if (source && !admit(i, stamp)) continue;
      health_[i].last_stamp_ns = stamp;
      last_taken_mono_[i] = monotonicNs();
      ready_.push_back({stamp, f->publish_ns, last_taken_mono_[i], int(i), std::move(buf)});
      buf = {};
    }
    health_[i].overruns = readers_[i].overruns();
  }
  order(ready_);
  schedule(monotonicNs());
  return any;
}

// Stamp order across channels, odometry first at equal stamps (the localiser predicts with the
// odometry up to a scan before it weighs the scan), then the order the frames were published
// in, then the input's index. Publication order, not a rank of sensors: the frames of one
// instant may be read in one pass (a backlog) or over several (a feed at 1x), and only the order
// they were written in is the same both ways, so a replay gives the same poses at any speed
// (Polylocd.PacedUnderACpuHogGivesTheSamePoses). Frames held from earlier passes merge in.
void InputGate::order(std::vector<Frame>& pass) {
  auto before = [&](const Frame& a, const Frame& b) {
    if (a.stamp_ns != b.stamp_ns) return a.stamp_ns < b.stamp_ns;
    const bool ao = a.input == odom_input_, bo = b.input == odom_input_;
    if (ao != bo) return ao;
    return a.publish_ns != b.publish_ns ? a.publish_ns < b.publish_ns : a.input < b.input;
  };
  std::stable_sort(pass.begin(), pass.end(), before);
  if (held_.empty()) return;
  std::vector<Frame> merged;
  merged.reserve(held_.size() + pass.size());
  std::merge(std::make_move_iterator(held_.begin()), std::make_move_iterator(held_.end()), std::make_move_iterator(pass.begin()),
             std::make_move_iterator(pass.end()), std::back_inserter(merged), before);
  held_.clear();
  pass = std::move(merged);
}

// Each sensor frame goes after the odometry that covers its stamp (the first message at or
// after it): the localiser then interpolates the motion to the frame's stamp instead of
// extrapolating it, and the result does not depend on how the read passes group the frames
// (a scan read before the odometry that covers it waits for it). A frame waits at most
// odom_wait, then goes with the motion extrapolated and is counted (`extrapolated` of its
// input); the frames after it wait with it, so sensor frames go in stamp order. No waiting
// while the odometry input is silent (or absent): a robot whose odometry stopped still
// localises at its scanners' rate.
void InputGate::schedule(int64_t mono) {
  if (odom_input_ < 0 || health_[size_t(odom_input_)].last_stamp_ns == 0) return;  // no motion to extrapolate
  // Stamp order, but each odometry message moved before the sensor frames it covers.
  std::vector<Frame> out, uncovered;
  out.reserve(ready_.size());
  for (Frame& t : ready_) {
    if (t.input != odom_input_) {
      uncovered.push_back(std::move(t));
      continue;
    }
    out.push_back(std::move(t));
    for (Frame& s : uncovered) out.push_back(std::move(s));
    uncovered.clear();
  }
  const size_t covered_end = out.size();
  for (Frame& s : uncovered) out.push_back(std::move(s));
  ready_ = std::move(out);
  const int64_t wait = cfg_.odom_wait_ns;
  const bool waiting = wait > 0 && mono - last_taken_mono_[size_t(odom_input_)] <= cfg_.input_timeout_ns;
  const int64_t covered = health_[size_t(odom_input_)].last_stamp_ns;
  auto first_held = std::find_if(ready_.begin() + ptrdiff_t(covered_end), ready_.end(), [&](const Frame& t) {
    if (t.stamp_ns <= covered) return false;
    if (waiting && mono - t.read_mono < wait) return true;
    ++health_[size_t(t.input)].extrapolated;
    return false;
  });
  held_.assign(std::make_move_iterator(first_held), std::make_move_iterator(ready_.end()));
  ready_.erase(first_held, ready_.end());
}

int64_t InputGate::sleepNs(int64_t mono) const {
  if (held_.empty()) return kMaxSleepNs;
  return std::clamp<int64_t>(held_.front().read_mono + cfg_.odom_wait_ns - mono, 0, kMaxSleepNs);
}

const std::vector<polyloc_input_health>& InputGate::health(int64_t mono) {
  for (size_t i = 0; i < health_.size(); ++i) {
    // An input that never delivered is silent too (health), but only an input that stops is
    // worth a warning: at start every input is still coming up.
    const bool never = last_taken_mono_[i] == 0;
    const bool now_silent = never || mono - last_taken_mono_[i] > cfg_.input_timeout_ns;
    if (now_silent && !health_[i].silent && !never)
      spdlog::warn("input {} silent: no frame for {:.1f} s", desc(i).name, double(mono - last_taken_mono_[i]) * 1e-9);
    else if (!now_silent && health_[i].silent)
      spdlog::info("input {}: {}", desc(i).name, announced_[i] ? "frames again" : "first frames");
    if (!now_silent) announced_[i] = true;
    health_[i].silent = now_silent;
  }
  return health_;
}

}  // namespace polyloc::pipeline
