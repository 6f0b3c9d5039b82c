// polylocd: the co-process. Reads its config (map, robot, rig, filters, MCL, VRS, tracking and
// the `polylocd:` section), creates the shared-memory segment, and runs until SIGINT/SIGTERM.
// docs/polylocd.md is the user guide.
#include "cli/parse_number.hpp"
#include "pipeline/control.hpp"
#include "pipeline/daemon.hpp"
#include "protocol/server.hpp"

#include <polyloc/geometry/domain.hpp>

#include <CLI/CLI.hpp>
#include <fmt/core.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <atomic>
#include <csignal>
#include <cstring>
#include <sstream>

namespace {

std::atomic<bool> g_stop{false};
extern "C" void onSignal(int) { g_stop.store(true); }

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"polylocd: localisation, virtual range scans and people tracking for a robot, over shared memory"};
  std::string config, instance, init, log_level;
  int threads = -1, port = -1, live_port = -1;
  bool global = false, check = false;
  app.add_option("--config", config, "polyloc config: map, robot, rig, mcl, vrs, tracking, depth_filter, polylocd")->required();
  app.add_option("--instance", instance, "Segment name /polyloc.NAME (default: polylocd.instance)");
  app.add_option("--init", init, "Start pose x,y,yaw or x,y,z,yaw (m, deg; default: polylocd.init, else global localisation)");
  app.add_flag("--global", global, "Start with global localisation, whatever the config says");
  app.add_option("--threads", threads, "TBB threads for the kernels (0: all cores)")->check(polyloc::cli::finiteRange(0, 4096));
  app.add_option("--control-port", port, "TCP control port (0: any free one; default: polylocd.control.port)")
      ->check(CLI::Range(0, 65535));
  app.add_option("--live-port", live_port, "Live view port: Foxglove WebSocket and the page (0: off; default: polylocd.live.port)")
      ->check(CLI::Range(0, 65535));
  app.add_option("--log-level", log_level, "trace, debug, info, warn, error, off");
  app.add_flag("--check", check, "Validate the config and exit");
  app.set_version_flag("--version", "polylocd 0.1.0");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;  // usage errors exit 2, as polyloc's
  }
  spdlog::set_default_logger(spdlog::stderr_color_mt("polylocd"));  // stdout stays for --check's answer

  try {
    polyloc::pipeline::ServiceConfig cfg = polyloc::pipeline::loadServiceConfig(config);
    auto& d = cfg.daemon;
    if (!instance.empty()) d.instance = instance;
    if (threads >= 0) d.threads = threads;
    if (port >= 0) d.control.port = static_cast<uint16_t>(port);
    if (live_port >= 0) d.live.port = static_cast<uint16_t>(live_port);
    if (!log_level.empty()) d.log_level = log_level;
    if (global) d.init.reset();
    if (!init.empty()) {
      d.init = polyloc::pipeline::InitPose{polyloc::cli::parseStartPose(init, "--init")};
    }
    spdlog::set_level(spdlog::level::from_str(d.log_level));
    spdlog::set_pattern("[%H:%M:%S.%e] [polylocd] [%l] %v");
    if (check) {
      fmt::print("{}: ok (rig '{}', {} sensors, instance '{}')\n", config, cfg.polyloc.rig.name, cfg.polyloc.rig.size(), d.instance);
      return 0;
    }
    struct sigaction sa {};
    sa.sa_handler = onSignal;  // no SA_RESTART: the futex wait returns, the loop sees the flag
    sigaction(SIGINT, &sa, nullptr);
    sigaction(SIGTERM, &sa, nullptr);
    polyloc::pipeline::Daemon daemon(std::move(cfg));
    std::unique_ptr<polyloc::pipeline::DaemonControl> control;
    std::unique_ptr<polyloc::protocol::Server> server;
    const auto& cc = daemon.config().daemon.control;
    if (cc.enabled) {
      control = std::make_unique<polyloc::pipeline::DaemonControl>(daemon.live(), daemon.config(), daemon.channels().inputNames(),
                                                                daemon.mapBounds());
      polyloc::protocol::ServerConfig sc;
      sc.bind_address = cc.bind, sc.port = cc.port;
      server = std::make_unique<polyloc::protocol::Server>(sc, *control);
      server->start();
      spdlog::info("control endpoint on {}:{} (docs/protocol.md)", cc.bind, server->port());
    }
    daemon.run(g_stop);
    if (server) server->stop();
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
  return 0;
}

