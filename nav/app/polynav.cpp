// polynav: the reference navigation controller. It is what a customer's controller would be: it
// links only libpolyloc_client (and its own polynav::core), reads pose and VRS from a running
// polylocd, and writes velocity commands on the segment's cmd_vel channel, one per VRS, stamped
// with the VRS's stamp. Goals come from the zone file (--goals NAMES or --random N). Status on
// stderr; a JSON summary of the missions on stdout at the end (--json).
#include <polyloc_client.h>

#include <polynav/controller.hpp>
#include <polynav/nearness_diagram.hpp>
#include <polynav/polygon.hpp>
#include <polynav/polylocd_link.hpp>
#include <polynav/vfh.hpp>

#include <CLI/CLI.hpp>

#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <sstream>
#include <thread>
#include <unistd.h>

namespace {

std::atomic<bool> g_stop{false};
void onSignal(int) { g_stop = true; }

struct Args {
  std::string shm, grid, zones, goals, local = "nd", footprint, trace;
  size_t random = 0;
  uint64_t seed = 1;
  double max_speed = 0.5, max_yaw_rate = 0.8, mission_timeout = 120, wait = 10, safety = 0.3, wide_valley = 90;
  bool json = false, quiet = false, exit_when_done = false;
};

[[noreturn]] void die(const std::string& what) {
  std::fprintf(stderr, "polynav: %s\n", what.c_str());
  std::exit(1);
}

polynav::Polygon parseFootprint(const std::string& s) {
  // "x,y;x,y;..." in base_link metres
  polynav::Polygon out;
  std::stringstream ss(s);
  for (std::string pt; std::getline(ss, pt, ';');) {
    double x, y;
    if (std::sscanf(pt.c_str(), "%lf,%lf", &x, &y) != 2 || !std::isfinite(x) || !std::isfinite(y))
      die("--footprint: '" + pt + "' is not x,y");
    out.emplace_back(x, y);
  }
  // A footprint with no area (points repeated, on a line) would make every pose look clear.
  if (const std::string p = polynav::polygonProblem(out); !p.empty()) die("--footprint '" + s + "': the polygon " + p);
  return out;
}

std::vector<polynav::GoalSpot> pickGoals(const Args& a, const polynav::Zones& z) {
  std::vector<polynav::GoalSpot> out;
  if (!a.goals.empty()) {
    std::stringstream ss(a.goals);
    for (std::string name; std::getline(ss, name, ',');) {
      const auto i = z.goalIndex(name);
      if (!i) die("--goals: no goal '" + name + "' in " + a.zones);
      out.push_back(z.goals[*i]);
    }
  }
  if (a.random) {
    if (z.goals.size() < 2) die("--random needs at least 2 goals in " + a.zones);
    const auto drawn = polynav::randomGoals(z, a.random, a.seed);
    out.insert(out.end(), drawn.begin(), drawn.end());
  }
  if (out.empty()) die("no goals: give --goals NAME,NAME or --random N");
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  Args a;
  CLI::App app{"polynav: the reference navigation controller on polylocd's VRS (docs/navigation.md)"};
  app.add_option("--shm", a.shm, "polylocd instance (segment /polyloc.NAME)")->required();
  app.add_option("--grid", a.grid, "Navigation grid (polyloc map navgrid: map_server YAML)")->required()->check(CLI::ExistingFile);
  app.add_option("--zones", a.zones, "Zone file: rooms, doors, corridors, danger, goals")->required()->check(CLI::ExistingFile);
  app.add_option("--goals", a.goals, "Goal names of the zone file, comma-separated, visited in order");
  app.add_option("--random", a.random, "Then N goals drawn at random (a different one each time)");
  app.add_option("--seed", a.seed, "Seed of --random")->capture_default_str();
  app.add_option("--local", a.local, "Local obstacle avoidance: nd (Nearness Diagram) or vfh")->check(CLI::IsMember({"nd", "vfh"}))->capture_default_str();
  app.add_option("--footprint", a.footprint, "Robot footprint x,y;x,y;... (m, base_link); default 0.6 x 0.5 m");
  app.add_option("--max-speed", a.max_speed, "m/s")->capture_default_str()->check(CLI::Range(0.05, 2.0));
  app.add_option("--max-yaw-rate", a.max_yaw_rate, "rad/s")->capture_default_str()->check(CLI::Range(0.1, 3.0));
  app.add_option("--safety", a.safety, "ND safety distance around the hull (m)")->capture_default_str()->check(CLI::Range(0.05, 2.0));
  app.add_option("--wide-valley", a.wide_valley, "ND wide-valley angle (deg)")->capture_default_str()->check(CLI::Range(10.0, 360.0));
  app.add_option("--mission-timeout", a.mission_timeout, "s of data time per goal")->capture_default_str()->check(CLI::Range(1.0, 1e5));
  app.add_option("--wait", a.wait, "s to wait for polylocd")->capture_default_str()->check(CLI::Range(0.0, 3600.0));
  app.add_option("--trace", a.trace, "CSV of every decision: t, pose, phase, v, w, status");
  app.add_flag("--exit-when-done", a.exit_when_done, "Exit once every goal is reached or failed");
  app.add_flag("--json", a.json, "Summary of the missions as JSON on stdout at the end");
  app.add_flag("--quiet", a.quiet, "No status line");
  CLI11_PARSE(app, argc, argv);
  std::signal(SIGINT, onSignal);
  std::signal(SIGTERM, onSignal);

  polynav::ControllerConfig cfg;
  if (!a.footprint.empty()) cfg.footprint = parseFootprint(a.footprint);
  cfg.max_speed = a.max_speed, cfg.max_yaw_rate = a.max_yaw_rate, cfg.mission_timeout = a.mission_timeout;
  polynav::LocalPlanner local;
  const polynav::RectHull hull = polynav::RectHull::fromFootprint(cfg.footprint);
  const polynav::NdLimits limits{a.max_speed, a.max_yaw_rate};
  if (a.local == "nd") {
    const polynav::NdConfig nd{a.safety, a.wide_valley};
    local = [=](const polynav::PolarScan& s, const Eigen::Vector2d& goal) {
      const polynav::NdCommand c = polynav::nearnessDiagram(s, goal, hull, nd, limits);
      return polynav::LocalStep{c.v, c.w, polynav::situationName(c.situation), c.min_clearance};
    };
  } else {
    local = [=](const polynav::PolarScan& s, const Eigen::Vector2d& goal) {
      const polynav::LocalCommand c = polynav::vfh(s, goal, hull, {}, limits);
      return polynav::LocalStep{c.v, c.w, c.blocked ? "vfh blocked" : "vfh", c.min_clearance};
    };
  }
  polynav::Zones zones;
  std::vector<polynav::GoalSpot> goals;
  std::unique_ptr<polynav::Controller> ctrl;
  try {
    zones = polynav::loadZones(a.zones);
    goals = pickGoals(a, zones);
    ctrl = std::make_unique<polynav::Controller>(polynav::loadNavGrid(a.grid), zones, cfg, local);
    ctrl->setGoals(goals);
  } catch (const std::exception& e) {
    die(e.what());
  }

  polyloc_client* c = nullptr;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(a.wait);
  for (int s; (s = polyloc_attach(a.shm.c_str(), &c)) != POLYLOC_OK;) {
    if (std::chrono::steady_clock::now() > deadline || g_stop) die(polyloc_last_error());
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  // The channels by name, the command writer claimed: at the start and after each restart of
  // polylocd (a new segment may list its channels in another order, docs/interface.md).
  int vrs_ch = -1, cmd_ch = -1, odom_ch = -1;
  std::vector<uint8_t> buf;
  auto channels = [&]() -> std::string {
    vrs_ch = polyloc_channel(c, "vrs"), cmd_ch = polyloc_channel(c, "cmd_vel"), odom_ch = polyloc_channel(c, "odom");
    if (vrs_ch < 0 || cmd_ch < 0) return "polylocd '" + a.shm + "' has no vrs or cmd_vel channel (an older polylocd?)";
    if (polyloc_claim_writer(c, cmd_ch, 0) != POLYLOC_OK) return polyloc_last_error();
    polyloc_channel_desc vd;
    polyloc_channel_info(c, vrs_ch, &vd);
    buf.resize(vd.payload_max);
    return "";
  };
  if (const std::string e = channels(); !e.empty()) die(e);
  bool ready = true;  // the channels of the segment attached are known and cmd_vel is ours

  struct Event { size_t goal; int state; double t; std::string status; std::string phase; };
  std::vector<Event> events;
  int64_t t0 = 0, last_stamp = 0;
  uint64_t decisions = 0, lost = 0;
  int last_state = -1;
  polynav::Phase last_phase = polynav::Phase::Done;
  size_t last_goal = SIZE_MAX;
  FILE* trace = a.trace.empty() ? nullptr : std::fopen(a.trace.c_str(), "w");
  if (!a.trace.empty() && !trace) die("--trace: cannot write " + a.trace);
  if (trace) std::fprintf(trace, "t,x,y,yaw,goal,state,phase,v,w,clearance,status\n");
  const bool tty = isatty(fileno(stderr));
  auto last_print = std::chrono::steady_clock::now();
  while (!g_stop) {
    if (polyloc_stale(c) == 1) {
      ready = false;
      if (polyloc_reattach(c) != POLYLOC_OK) std::this_thread::sleep_for(std::chrono::milliseconds(100));
      continue;
    }
    if (!ready) {
      const std::string e = channels();
      if (!(ready = e.empty())) {
        std::fprintf(stderr, "polynav: after polylocd's restart: %s\n", e.c_str());
        std::this_thread::sleep_for(std::chrono::milliseconds(500));
        continue;
      }
    }
    const int w = polyloc_wait(c, vrs_ch, 200'000'000);
    if (w == POLYLOC_ERR_STALE) continue;  // the next turn re-attaches
    if (w != POLYLOC_OK) continue;
    polyloc_frame_info info;
    if (polyloc_read_next(c, vrs_ch, buf.data(), uint32_t(buf.size()), &info) != POLYLOC_OK) continue;
    std::string why;
    auto frame = polynav::decodeVrs(buf.data(), std::min<size_t>(info.size, buf.size()), &why);
    if (!frame) {
      std::fprintf(stderr, "polynav: %s; skipped\n", why.c_str());
      continue;
    }
    last_stamp = frame->stamp_ns;
    polynav::NavInput in;
    if (!t0) t0 = frame->stamp_ns;
    in.t = polynav::secondsBetween(t0, frame->stamp_ns);
    in.scan = std::move(frame->scan);
    const polynav::PoseRead pose = polynav::readPoseNow(c, odom_ch);
    in.localised = pose.localised;
    if (!in.localised) ++lost;
    in.pose = pose.pose;
    polyloc_tracks tracks;
    if (polyloc_read_tracks(c, &tracks, nullptr) == POLYLOC_OK)
      for (uint32_t k = 0; k < tracks.count && k < POLYLOC_MAX_TRACKS; ++k)
        if (tracks.tracks[k].status == 1)
          in.people.push_back({{tracks.tracks[k].x, tracks.tracks[k].y}, {tracks.tracks[k].vx, tracks.tracks[k].vy}});
    polynav::NavOutput o;
    try {
      o = ctrl->update(in);
    } catch (const std::exception& e) {
      o = {};  // a bad input must not drive the robot: stand still and say why
      o.status = std::string("error: ") + e.what();
    }
    ++decisions;
    if (polyloc_write_command(c, cmd_ch, last_stamp, o.v, 0.0, o.w, uint32_t(o.state), uint32_t(o.goal), o.status.c_str()) != POLYLOC_OK)
      std::fprintf(stderr, "polynav: %s\n", polyloc_last_error());
    if (trace)
      std::fprintf(trace, "%.3f,%.4f,%.4f,%.4f,%zu,%d,%s,%.4f,%.4f,%.3f,\"%s\"\n", in.t, in.pose.x(), in.pose.y(), in.pose.z(),
                   o.goal, o.state, polynav::phaseName(o.phase), o.v, o.w, o.clearance, o.status.c_str());
    if (o.state != last_state || o.goal != last_goal || o.phase != last_phase)
      events.push_back({o.goal, o.state, in.t, o.status, polynav::phaseName(o.phase)});
    last_state = o.state, last_goal = o.goal, last_phase = o.phase;
    if (!a.quiet && std::chrono::steady_clock::now() - last_print > std::chrono::milliseconds(tty ? 250 : 5000)) {
      last_print = std::chrono::steady_clock::now();
      std::fprintf(stderr, "%spolynav %.1f s  goal %zu/%zu  v %.2f w %.2f  %s%s", tty ? "\r" : "", in.t,
                   std::min(o.goal + 1, goals.size()), goals.size(), o.v, o.w, o.status.c_str(), tty ? "\033[K" : "\n");
    }
    if (ctrl->done() && a.exit_when_done) break;
  }
  // Leave the base standing: one zero command (the base's timeout would stop it anyway), stamped
  // just after the last one so that the base takes it (a stamp of 0 is no time: refused).
  timespec now{};
  clock_gettime(CLOCK_REALTIME, &now);
  const int64_t stop_stamp = polynav::stopStamp(last_stamp, int64_t(now.tv_sec) * 1'000'000'000 + now.tv_nsec);
  if (polyloc_write_command(c, cmd_ch, stop_stamp, 0, 0, 0, POLYLOC_NAV_IDLE, uint32_t(goals.size()), "polynav stopped") != POLYLOC_OK)
    std::fprintf(stderr, "polynav: the stop command was not written: %s\n", polyloc_last_error());
  if (!a.quiet && tty) std::fprintf(stderr, "\n");
  if (a.json) {
    std::printf("{\"decisions\": %llu, \"not_localised\": %llu, \"goals\": %zu, \"events\": [", (unsigned long long)decisions,
                (unsigned long long)lost, goals.size());
    for (size_t i = 0; i < events.size(); ++i) {
      std::string s;
      for (char ch : events[i].status) s += ch == '"' || ch == '\\' ? '\'' : ch;
      std::printf("%s{\"goal\": %zu, \"state\": %d, \"t\": %.3f, \"phase\": \"%s\", \"status\": \"%s\"}", i ? ", " : "",
                  events[i].goal, events[i].state, events[i].t, events[i].phase.c_str(), s.c_str());
    }
    std::printf("]}\n");
  }
  if (trace) std::fclose(trace);
  polyloc_detach(c);
  return 0;
}
