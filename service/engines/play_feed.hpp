// The shared-memory side of `polyloc play`: the recorded messages into polylocd's input channels
// (pipeline/message_feed.hpp), readers for pose and health, and what they saw. Stamps are moved
// onto the wall clock: stamp - first log time + CLOCK_REALTIME at the start. Re-attaches when
// polylocd restarts (generation changes).
#pragma once

#include "pipeline/message_feed.hpp"
#include "shm/channel.hpp"

#include <polyloc/eval/trajectory_metrics.hpp>
#include <polyloc/io/recording.hpp>

#include <nlohmann/json.hpp>

#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace polyloc::engines {

struct PlayResult {
  uint64_t sent = 0, late = 0, reattached = 0;
  std::map<std::string, uint64_t> per_channel;   // frames written
  std::map<std::string, uint64_t> skipped;       // topic -> messages with no channel
  std::vector<EstimatedPose> estimates;          // poses polylocd published (stamps as sent)
  std::vector<StampedPose> truth;                // /ground_truth of the source, restamped
  std::vector<double> latency_ms;                // per pose: scan publish -> pose publish
  double latency_p50_ms = 0, latency_p99_ms = 0, latency_max_ms = 0;
  uint64_t dropped = 0;   // polylocd: frames overwritten before it read them (health overruns)
  uint64_t rejected = 0;  // polylocd: frames it rejected (health)
  uint64_t poses_missed = 0;  // poses this reader missed (overruns of its pose reader)
  uint64_t undelivered = 0;   // messages not sent: polylocd was stopped or gone
  bool answered = false;      // a pose or a health frame came back
  bool up_at_end = true;      // polylocd was running when the source ended
};

class PlayFeed {
 public:
  // Waits up to wait_s for the segment /polyloc.<instance> to be ready; throws shm::ShmError.
  PlayFeed(const std::string& instance, double wait_s);
  ~PlayFeed();

  // m.log_time_ns already moved by offset_ns (--loop); header stamps are moved here the same way.
  void send(const RecordedMessage& m, int64_t offset_ns, int64_t first_log_ns);
  void poll();         // reads new poses and health
  // About twice a second (cheaper calls return at once): notices a polylocd that stopped, died
  // or restarted, re-attaches to a new one, and says so once per change. send() calls it.
  void watch();
  void finish();       // flushes pending depth frames, waits briefly for the last outputs
  void countLate() { ++r_.late; }
  int64_t baseNs() const { return base_ns_; }
  bool up() const { return up_; }  // attached to a running polylocd (as of the last check)
  // Counts the segments attached so far: readers of polylocd's outputs elsewhere (play --drive)
  // re-attach when it changes.
  uint64_t attachments() const { return attachments_; }
  const shm::Segment& segment() const { return *seg_; }  // while up()  // CLOCK_REALTIME the source's first stamp is moved to
  // Stamps from `first_log_ns` on stay the source's own (not moved onto the wall clock): for a
  // polylocd on the source clock, so that a run does not depend on when it was started.
  void keepSourceStamps(int64_t first_log_ns) { base_ns_ = first_log_ns; }
  std::string statusLine(double t_s, double span_s) const;
  PlayResult result() const;
  // Called with each pose polylocd publishes and each ground-truth pose of the source, as they
  // come (polyloc play --live).
  std::function<void(const polyloc_pose&)> on_pose;
  std::function<void(int64_t stamp_ns, const Pose& map_T_base)> on_truth;
  nlohmann::json resultJson() const;

 private:
  bool attach(double wait_s);  // false: no running polylocd within wait_s

  bool up_ = false;
  uint64_t attachments_ = 0;
  std::chrono::steady_clock::time_point next_check_{};
  std::vector<std::string> input_names_;  // of the health entries, read with them
  std::string instance_;
  double wait_s_;
  std::optional<shm::Segment> seg_;
  std::unique_ptr<pipeline::MessageFeed> feed_;
  std::unique_ptr<shm::Reader> pose_reader_, health_reader_;
  uint64_t sent_before_ = 0;  // by the feeds of earlier attachments
  std::map<std::string, uint64_t> per_channel_before_;
  int64_t base_ns_ = 0;
  int64_t odom_offset_ = 0;       // --loop: the pass whose odometry odom_fix_ moves
  Pose odom_fix_;                 // last pass's end * this pass's start^-1
  std::optional<Pose> last_odom_;
  std::optional<polyloc_health> health_;
  PlayResult r_;
  std::vector<uint8_t> buf_;
};

}  // namespace polyloc::engines
