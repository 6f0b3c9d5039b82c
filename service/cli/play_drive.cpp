// polyloc play --scenario S --drive: the scenario's world, people and sensors, but the robot
// goes where a controller's commands on cmd_vel take it (drive_loop.hpp). Prints what the base
// did: commands taken and rejected, collisions with where and what, the loop's waits.
#include "cli/play_drive.hpp"

#include "engines/drive_loop.hpp"
#include "engines/drive_report.hpp"
#include "cli/progress_bar.hpp"

#include <polyloc/sim/scenario.hpp>

#include <fmt/core.h>
#include <unistd.h>

#include <chrono>

namespace polyloc::cli {

using engines::DriveLoop;
using engines::DriveLoopOptions;
using engines::driveJson;
using engines::PlayResult;

void runPlayDrive(const PlayDriveArgs& a) {
  Scenario s = loadScenario(a.scenario);
  Simulator sim(s, loadScenarioMap(s));
  DriveLoopOptions o;
  o.rate = a.rate;
  o.wait_attach_s = a.wait;
  o.drive.command_latency = a.command_latency;
  DriveLoop loop(sim, a.shm, o);
  // A controller started beside this one may still be loading its map: give it --wait seconds.
  if (!loop.waitForController(a.wait))
    fmt::print(stderr, "polyloc play: no controller holds '{}' cmd_vel yet: driving on (the base stands until one commands it)\n", a.shm);
  const double span = a.duration > 0 ? a.duration : sim.duration();
  const bool tty = isatty(fileno(stderr));
  auto last_status = std::chrono::steady_clock::now();
  while (loop.nowS() < span) {
    loop.step();
    if (!a.quiet && std::chrono::steady_clock::now() - last_status > std::chrono::milliseconds(tty ? 250 : 5000)) {
      last_status = std::chrono::steady_clock::now();
      const Pose p = loop.drive().truth();
      fmt::print(stderr, "{}drive {:.1f}/{:.0f} s  robot ({:.2f}, {:.2f})  collisions {}  commands {}  {}{}", tty ? "\r" : "",
                 loop.nowS(), span, p.x(), p.y(), loop.drive().collisions().size(), loop.counters().commands,
                 loop.lastCommandStatus(), tty ? "\033[K" : "\n");
    }
  }
  loop.feed().finish();
  if (!a.quiet && tty) fmt::print(stderr, "\n");
  nlohmann::json j = driveJson(loop);
  j["scenario"] = a.scenario;
  const PlayResult r = loop.feed().result();
  j["poses"] = r.estimates.size();
  j["latency_p99_ms"] = r.latency_p99_ms;
  if (a.json) fmt::print("{}\n", j.dump());
  else
    fmt::print("drive: {:.1f} s simulated, {} commands ({} rejected by the base), {} collisions, final pose ({:.3f}, {:.3f})\n",
               loop.nowS(), loop.counters().commands, loop.drive().base().counters().rejected,
               loop.drive().collisions().size(), loop.drive().truth().x(), loop.drive().truth().y());
  if (loop.counters().commands == 0)
    throw std::runtime_error(fmt::format("no controller answered on '{}' cmd_vel: the robot stood still", a.shm));
}

}  // namespace polyloc::cli
