#include "engines/play_feed.hpp"

#include "pipeline/shm_payloads.hpp"

#include <polyloc/io/message_pose.hpp>
#include <polyloc/eval/stats.hpp>

#include <fmt/core.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <ctime>
#include <thread>
#include <tuple>

namespace polyloc::engines {
namespace {

int64_t realtimeNs() {
  timespec ts{};
  clock_gettime(CLOCK_REALTIME, &ts);
  return int64_t(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

// What polylocd lost over all inputs: frames overwritten before it read them, frames it rejected.
std::pair<uint64_t, uint64_t> lostFrames(const polyloc_health& health) {
  uint64_t dropped = 0, rejected = 0;
  for (uint32_t i = 0; i < health.inputs && i < POLYLOC_MAX_INPUTS; ++i)
    dropped += health.input[i].overruns, rejected += pipeline::rejectedFrames(health.input[i]);
  return {dropped, rejected};
}

void add(std::map<std::string, uint64_t>& to, const std::map<std::string, uint64_t>& from) {
  for (const auto& [k, v] : from) to[k] += v;
}

}  // namespace

PlayFeed::PlayFeed(const std::string& instance, double wait_s) : instance_(instance), wait_s_(wait_s) {
  if (!attach(wait_s_)) {
    shm::Segment::attach(instance_);  // throws, naming the segment and why
    throw std::runtime_error(fmt::format("polylocd '{}' has stopped (segment {} says STOPPED): start it first",
                                         instance_, shm::segmentName(instance_)));
  }
  up_ = true;
  base_ns_ = realtimeNs();
}

PlayFeed::~PlayFeed() = default;

bool PlayFeed::attach(double wait_s) {
  if (feed_) feed_->flush(), sent_before_ += feed_->sent(), add(per_channel_before_, feed_->perChannel());
  feed_.reset();
  pose_reader_.reset(), health_reader_.reset();
  seg_.reset();
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(wait_s);
  for (;;) {
    try {
      seg_.emplace(shm::Segment::attach(instance_));
      // READY and its owner alive: a daemon that was killed leaves READY behind.
      if (seg_->header().state == POLYLOC_STATE_READY && !seg_->stale()) break;
      seg_.reset();  // stopped: a daemon that ended, died, or whose start failed
    } catch (const shm::ShmError&) {
    }
    if (std::chrono::steady_clock::now() >= deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  ++attachments_;
  feed_ = std::make_unique<pipeline::MessageFeed>(*seg_);
  if (const int p = seg_->find("pose"); p >= 0) pose_reader_ = std::make_unique<shm::Reader>(*seg_, p, shm::Reader::Start::Next);
  if (const int p = seg_->find("health"); p >= 0) health_reader_ = std::make_unique<shm::Reader>(*seg_, p, shm::Reader::Start::Newest);
  return true;
}

// About twice a second (stale() costs system calls): a daemon that stopped or restarted is
// re-attached; one message per change of state, not per message sent.
void PlayFeed::watch() {
  const auto now = std::chrono::steady_clock::now();
  if (now < next_check_) return;
  next_check_ = now + std::chrono::milliseconds(500);
  if (up_ && !seg_->stale()) return;
  const bool was_up = up_;
  up_ = attach(0);
  if (up_ && was_up) {  // between two checks it died and another one started
    ++r_.reattached;
    fmt::print(stderr, "\npolyloc play: polylocd '{}' restarted: re-attached (generation {})\n", instance_, seg_->generation());
  } else if (up_) {
    ++r_.reattached;
    fmt::print(stderr, "\npolyloc play: polylocd '{}' is back (generation {}): sending again\n", instance_, seg_->generation());
  } else if (was_up) {
    fmt::print(stderr, "\npolyloc play: polylocd '{}' stopped or died: messages are not delivered until it is back\n", instance_);
  }
}

void PlayFeed::send(const RecordedMessage& m, int64_t offset_ns, int64_t first_log_ns) {
  watch();
  if (!up_) {
    ++r_.undelivered;
    return;
  }
  const int64_t shift = base_ns_ - first_log_ns + offset_ns;
  if (const auto* p = std::get_if<msg::PoseStamped>(&m.message); p && m.topic == "/ground_truth") {
    const int64_t t = msg::toNs(p->header.stamp) ? msg::toNs(p->header.stamp) : m.log_time_ns - offset_ns;
    r_.truth.push_back({t + shift, fromMsgPose(p->pose)});
    if (on_truth) on_truth(r_.truth.back().stamp_ns, r_.truth.back().pose);
    return;
  }
  if (const auto* o = std::get_if<msg::Odometry>(&m.message)) {
    // --loop: each pass's odometry starts again where the simulator starts it; moved onto where
    // the last pass left it, the robot drives on without a jump (the route closes on itself).
    const Pose odom = fromMsgPose(o->pose.pose);
    if (offset_ns != odom_offset_) {
      odom_offset_ = offset_ns;
      if (last_odom_) odom_fix_ = *last_odom_ * odom.inverse();
    }
    const Pose moved = odom_fix_ * odom;
    last_odom_ = moved;
    msg::Odometry copy = *o;
    copy.pose.pose = toMsgPose(moved);
    if (feed_->send(m.topic, m.log_time_ns - offset_ns, copy, shift) == pipeline::MessageFeed::Sent::NoChannel) ++r_.skipped[m.topic];
    return;
  }
  if (feed_->send(m.topic, m.log_time_ns - offset_ns, m.message, shift) == pipeline::MessageFeed::Sent::NoChannel) ++r_.skipped[m.topic];
}

void PlayFeed::poll() {
  if (pose_reader_)
    while (auto f = pose_reader_->next(buf_)) {
      if (buf_.size() < sizeof(polyloc_pose)) continue;
      polyloc_pose p;
      std::memcpy(&p, buf_.data(), sizeof p);
      r_.estimates.push_back({p.stamp_ns, pipeline::posePose(p), static_cast<MclStatus>(std::min<uint32_t>(p.status, 3))});
      r_.latency_ms.push_back(double(p.latency_ns) * 1e-6);
      if (on_pose) on_pose(p);
    }
  if (health_reader_)
    if (auto f = health_reader_->newest(buf_); f && buf_.size() >= sizeof(polyloc_health)) {
      health_.emplace();
      std::memcpy(&*health_, buf_.data(), sizeof(polyloc_health));
      input_names_.clear();  // inputs are the first channels of the table, in order (docs/interface.md)
      for (uint32_t i = 0; i < health_->inputs && i < POLYLOC_MAX_INPUTS && int(i) < seg_->channelCount(); ++i)
        input_names_.emplace_back(seg_->channel(int(i)).name, strnlen(seg_->channel(int(i)).name, POLYLOC_NAME_LEN));
    }
}

void PlayFeed::finish() {
  if (!feed_) return;
  feed_->flush();
  // The last frames are still in the pipeline: give polylocd a moment, and its health a beat.
  const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(500);
  while (std::chrono::steady_clock::now() < end) {
    poll();
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  if (pose_reader_) r_.poses_missed = pose_reader_->overruns();
}

std::string PlayFeed::statusLine(double t_s, double span_s) const {
  std::string s = fmt::format("play {:5.1f}/{:.0f} s  sent {}", t_s, span_s, sent_before_ + (feed_ ? feed_->sent() : 0));
  if (!r_.estimates.empty()) {
    const EstimatedPose& e = r_.estimates.back();
    s += fmt::format("  pose ({:.2f}, {:.2f}, {:.0f} deg) {}", e.pose.x(), e.pose.y(), rad2deg(e.pose.yaw()), toString(e.status));
    auto it = std::lower_bound(r_.truth.begin(), r_.truth.end(), e.stamp_ns,
                               [](const StampedPose& p, int64_t t) { return p.stamp_ns < t; });
    if (it != r_.truth.end()) {
      const double dxy = (it->pose.translation().head<2>() - e.pose.translation().head<2>()).norm();
      s += fmt::format("  err {:.3f} m {:.1f} deg", dxy, rad2deg(std::abs(angleDiff(e.pose.yaw(), it->pose.yaw()))));
    }
    s += fmt::format("  {:.1f} poses/s  latency {:.1f} ms", t_s > 0 ? double(r_.estimates.size()) / t_s : 0.0, r_.latency_ms.back());
  } else {
    s += "  (no pose yet)";
  }
  if (health_) {
    const auto [dropped, rejected] = lostFrames(*health_);
    s += fmt::format("  dropped {} rejected {}{}{}", dropped, rejected, health_->flags & 1 ? "  INPUT SILENT" : "",
                     health_->flags & 8 ? "  GLOBAL SEARCH" : "");
  }
  return s;
}

PlayResult PlayFeed::result() const {
  PlayResult r = r_;
  r.sent = sent_before_ + (feed_ ? feed_->sent() : 0);
  r.per_channel = per_channel_before_;
  if (feed_) add(r.per_channel, feed_->perChannel());
  if (!r.latency_ms.empty()) {
    r.latency_p50_ms = percentile(r.latency_ms, 50);
    r.latency_p99_ms = percentile(r.latency_ms, 99);
    r.latency_max_ms = *std::max_element(r.latency_ms.begin(), r.latency_ms.end());
  }
  if (health_) std::tie(r.dropped, r.rejected) = lostFrames(*health_);
  r.answered = health_.has_value() || !r.estimates.empty();
  r.up_at_end = up_;
  return r;
}

nlohmann::json PlayFeed::resultJson() const {
  const PlayResult r = result();
  nlohmann::json j = {{"instance", instance_}, {"sent", r.sent}, {"late", r.late}, {"reattached", r.reattached},
                      {"undelivered", r.undelivered}, {"answered", r.answered},
                      {"per_channel", r.per_channel}, {"skipped_topics", r.skipped}, {"poses", r.estimates.size()},
                      {"latency_ms", {{"p50", r.latency_p50_ms}, {"p99", r.latency_p99_ms}, {"max", r.latency_max_ms}}},
                      {"dropped", r.dropped}, {"rejected", r.rejected}, {"poses_missed", r.poses_missed}};
  if (health_) {
    nlohmann::json inputs = nlohmann::json::object();
    for (uint32_t i = 0; i < health_->inputs && i < POLYLOC_MAX_INPUTS; ++i) {
      const auto& h = health_->input[i];
      // Inputs are the first channels of the table, in order (docs/interface.md).
      inputs[input_names_.at(i)] = {{"taken", h.taken}, {"overruns", h.overruns}, {"nan", h.rejected_nan},
                                            {"size", h.rejected_size}, {"stale", h.rejected_stale},
                                            {"future", h.rejected_future}, {"silent", bool(h.silent)}, {"extrapolated", h.extrapolated},
                                            {"map_fit", h.map_fit_permille == 0
                                                            ? nlohmann::json(nullptr) : nlohmann::json(h.map_fit_permille / 1000.0)}};
    }
    j["polylocd"] = {{"cycles", health_->cycles}, {"poses", health_->poses}, {"vrs", health_->vrs},
                     {"tracks", health_->tracks}, {"cycle_p50_ms", health_->cycle_p50_ms},
                     {"cycle_p99_ms", health_->cycle_p99_ms}, {"unfit", bool(health_->flags & 4u)}, {"searching", bool(health_->flags & 8u)}, {"inputs", inputs}};
  }
  return j;
}

}  // namespace polyloc::engines
