// The closed loop of `polyloc play --drive` and `polyloc eval nav`: the simulated robot (sim/drive)
// sends its sensor frames into polylocd, and executes the commands a controller writes on the
// segment's `cmd_vel` channel. In lockstep: after each scan of polylocd's VRS trigger sensor the
// loop waits (bounded, wall clock) for the VRS of that scan and for the controller's command that
// answers it, so the run does not depend on the machine's speed and the same seed gives the same
// run. A controller that does not answer within wait_command_s is not waited for: the base's
// command timeout stops the robot, as on a real robot.
#pragma once

#include "engines/play_feed.hpp"

#include <polyloc/sim/drive.hpp>

#include <functional>
#include <memory>
#include <optional>
#include <string>

namespace polyloc::engines {

struct DriveLoopOptions {
  DriveOptions drive;
  double rate = 1.0;            // pacing against the wall clock (1: real time; large: as fast as the loop goes)
  double wait_vrs_s = 5.0;      // wall s for polylocd's VRS of a trigger scan
  double wait_command_s = 2.0;  // wall s for the controller's answer to it
  double wait_attach_s = 10.0;  // wall s for polylocd's segment to appear
};

struct DriveCounters {
  uint64_t steps = 0, triggers = 0;
  uint64_t vrs_missed = 0;       // trigger scans whose VRS did not come within wait_vrs_s
  uint64_t commands = 0;         // commands read from cmd_vel
  uint64_t commands_late = 0;    // trigger scans the controller did not answer within wait_command_s
  uint64_t commands_rejected = 0;  // by the validation of the channel (out of domain, bad size)
  uint64_t reattached = 0;         // readers moved to a restarted polylocd's segment
  uint64_t commands_since_attach = 0;  // commands read since the last (re-)attachment
};

class DriveLoop {
 public:
  // Attaches to polylocd `instance` (its segment must have `cmd_vel`). Throws std::runtime_error.
  DriveLoop(Simulator& sim, const std::string& instance, const DriveLoopOptions& options);
  ~DriveLoop();

  // Waits (wall clock) until a controller holds the cmd_vel writer role, so that the first scans
  // are not sent before it listens; false after timeout_s or when `alive` says it is gone.
  bool waitForController(double timeout_s, const std::function<bool()>& alive = {});
  // One simulator event: move, simulate, send, and in lockstep wait for polylocd and the
  // controller. `on_command` sees every command read (t: simulated s of its stamp).
  void step();
  std::function<void(const polyloc_command&, double t)> on_command;
  // Takes the commands written so far (e.g. the controller's last stop after it ended).
  void readCommands();
  // When set: asked while waiting for a command. Once false, steps no longer wait for the
  // controller's answers (the base runs on its last command and its watchdog), nor count them late.
  std::function<bool()> controller_alive;

  const DriveSim& drive() const { return *drive_; }
  PlayFeed& feed() { return feed_; }
  const DriveCounters& counters() const { return counters_; }
  double nowS() const { return drive_->nowS(); }
  const std::string& lastCommandStatus() const { return last_status_; }

 private:
  bool waitFor(shm::Reader& r, int64_t stamp, double wait_s, bool at_least);
  void attachReaders();
  bool readersUp();
  uint64_t readers_at_ = 0;  // the feed's attachment the readers are on
  bool controller_gone_ = false;

  Simulator& sim_;
  DriveLoopOptions opt_;
  PlayFeed feed_;
  std::unique_ptr<DriveSim> drive_;
  std::unique_ptr<shm::Reader> vrs_, cmd_;
  std::string trigger_topic_;
  int64_t start_ns_ = 0;  // the scenario's start stamp
  std::vector<uint8_t> buf_;
  int64_t last_cmd_stamp_ = INT64_MIN;
  std::chrono::steady_clock::time_point t0_;
  DriveCounters counters_;
  std::string last_status_;
};

}  // namespace polyloc::engines
