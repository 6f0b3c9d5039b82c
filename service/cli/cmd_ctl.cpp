// polyloc ctl --port P [--host H] COMMAND [ARGS]: one request to a running polylocd over the
// TCP control protocol (docs/protocol.md), its reply printed as text or, with --json, as one
// JSON object. A reply with an error status is an error (exit 1); a warning is printed with it.
#include "cli/commands.hpp"
#include "cli/parse_number.hpp"

#include <polyloc/geometry/pose.hpp>
#include <protocol/client.hpp>
#include <protocol/messages.hpp>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <functional>
#include <map>
#include <memory>
#include <stdexcept>

namespace polyloc::cli {
namespace cmd_ctl_impl {  // named, not anonymous: the CLI is compiled in batches (unity build)

using nlohmann::json;
using protocol::Frame;
using protocol::Words;

struct CtlArgs {
  std::string host = "127.0.0.1";
  int port = 0;
  int timeout_ms = 2000;
  bool json = false;
  std::string command;
  std::vector<std::string> args;
};

json poseJson(const Pose& p) {
  return {{"x_m", p.x()},
          {"y_m", p.y()},
          {"z_m", p.z()},
          {"roll_rad", p.roll()},
          {"pitch_rad", p.pitch()},
          {"yaw_rad", p.yaw()},
          {"yaw_deg", rad2deg(p.yaw())}};
}

const char* poseStatusName(protocol::PoseStatus s) {
  static const char* names[] = {"initialising", "tracking", "uncertain", "lost"};
  return names[static_cast<uint32_t>(s) & 3];
}

// One request: what to send, and how its reply's data turns into JSON.
struct Request {
  uint32_t command;
  Words data;
  std::function<std::optional<json>(protocol::WordSpan)> decode;
};

std::optional<json> noData(protocol::WordSpan d) {
  return d.empty() ? std::optional<json>(json::object()) : std::nullopt;
}

Request makeRequest(const CtlArgs& a) {
  namespace cmd = protocol::cmd;
  const auto& v = a.args;
  const auto want = [&](size_t lo, size_t hi, const char* usage) {
    if (v.size() < lo || v.size() > hi) throw std::runtime_error(fmt::format("usage: polyloc ctl {}", usage));
  };
  const std::string& c = a.command;
  if (c == "ping") {
    want(0, 0, "ping");
    return {cmd::PING, {}, noData};
  }
  if (c == "getpose") {
    want(0, 0, "getpose");
    return {cmd::GETPOSECOVARIANCE, {}, [](protocol::WordSpan d) -> std::optional<json> {
              const auto p = protocol::decodePoseCovariance(d);
              if (!p) return std::nullopt;
              std::vector<double> cov;  // row-major, x y z roll pitch yaw
              for (int i = 0; i < 36; ++i) cov.push_back(p->covariance(i / 6, i % 6));
              return json{{"pose", poseJson(p->pose)},
                          {"pose_status", poseStatusName(p->status)},
                          {"stamp_ns", p->stamp_ns},
                          {"covariance", cov},
                          {"ess", p->ess},
                          {"particles", p->particles}};
            }};
  }
  if (c == "setpose") {
    want(3, 5, "setpose X Y YAW_DEG [SIGMA_XY SIGMA_YAW_DEG]");
    if (v.size() == 4) throw std::runtime_error("setpose: give both spreads (SIGMA_XY SIGMA_YAW_DEG) or neither");
    protocol::PoseSeed seed{parseNumber(v[0], "X"), parseNumber(v[1], "Y"), deg2rad(parseNumber(v[2], "YAW_DEG")), {}, {}};
    if (v.size() == 5)
      seed.sigma_xy_m = parseNumber(v[3], "SIGMA_XY"), seed.sigma_yaw_rad = deg2rad(parseNumber(v[4], "SIGMA_YAW_DEG"));
    return {cmd::SETPOSE, protocol::encodeSeed(seed), noData};
  }
  if (c == "global") {
    want(0, 0, "global");
    return {cmd::GLOBALLOCALIZATION, {}, noData};
  }
  if (c == "scanners") {
    want(0, 0, "scanners");
    return {cmd::GETSCANNERS, {}, [](protocol::WordSpan d) -> std::optional<json> {
              const auto list = protocol::decodeScanners(d);
              if (!list) return std::nullopt;
              json out = json::array();
              for (size_t i = 0; i < list->size(); ++i)
                out.push_back({{"index", i},
                               {"name", (*list)[i].name},
                               {"beams", (*list)[i].beams},
                               {"mount", poseJson((*list)[i].mount)}});
              return json{{"scanners", out}};
            }};
  }
  if (c == "scan") {
    want(1, 1, "scan INDEX   (0: the VRS, 1..: the raw scanners)");
    const double index = parseNumber(v[0], "INDEX");
    if (index < 0 || index != std::floor(index) || index > 0xffffffffu)
      throw std::runtime_error("scan: INDEX must be 0, 1, 2, ...");
    return {cmd::GETSCANRADIALSCANNER, {static_cast<uint32_t>(index)}, [](protocol::WordSpan d) -> std::optional<json> {
              const auto s = protocol::decodeScan(d);
              if (!s) return std::nullopt;
              // +inf (no return) prints as null in JSON.
              return json{{"stamp_ns", s->stamp_ns},
                          {"beams", s->ranges.size()},
                          {"angles_rad", s->angles},
                          {"ranges_m", s->ranges}};
            }};
  }
  if (c == "getca") {
    want(0, 0, "getca");
    return {cmd::GETCOLLISIONAVOIDANCE, {}, [](protocol::WordSpan d) -> std::optional<json> {
              if (d.size() != 1) return std::nullopt;
              return json{{"collision_avoidance", d[0] != 0}};
            }};
  }
  if (c == "setca") {
    want(1, 1, "setca 0|1");
    if (v[0] != "0" && v[0] != "1") throw std::runtime_error(fmt::format("setca: '{}' is not 0 or 1", v[0]));
    return {cmd::SETCOLLISIONAVOIDANCE, {v[0] == "1" ? 1u : 0u}, noData};
  }
  if (c == "tracks") {
    want(0, 0, "tracks");
    return {cmd::GETTRACKS, {}, [](protocol::WordSpan d) -> std::optional<json> {
              const auto t = protocol::decodeTracks(d);
              if (!t) return std::nullopt;
              json out = json::array();
              for (const auto& k : t->tracks)
                out.push_back({{"id", k.id},
                               {"confirmed", k.confirmed},
                               {"x_m", k.x},
                               {"y_m", k.y},
                               {"vx_mps", k.vx},
                               {"vy_mps", k.vy},
                               {"covariance", k.covariance}});
              return json{{"stamp_ns", t->stamp_ns}, {"tracks", out}};
            }};
  }
  if (c == "status") {
    want(0, 0, "status");
    return {cmd::GETSTATUS, {}, [](protocol::WordSpan d) -> std::optional<json> {
              const auto h = protocol::decodeHealth(d);
              if (!h) return std::nullopt;
              json inputs = json::array();
              for (const auto& in : h->inputs)
                inputs.push_back({{"name", in.name},
                                  {"rate_hz", in.rate_hz},
                                  {"taken", in.taken},
                                  {"rejected", in.rejected},
                                  {"silence_s", in.silence_s},
                                  {"silent", in.silent},
                                  {"map_fit", in.map_fit < 0 ? json(nullptr) : json(in.map_fit)}});
              return json{{"stamp_ns", h->stamp_ns},
                          {"uptime_s", h->uptime_s},
                          {"pose_status", poseStatusName(h->pose_status)},
                          {"unfit", h->unfit},
                          {"cycles", h->cycles},
                          {"poses", h->poses},
                          {"vrs", h->vrs},
                          {"tracks", h->tracks},
                          {"pose_rate_hz", h->pose_rate_hz},
                          {"cycle_p50_ms", h->cycle_p50_ms},
                          {"cycle_p99_ms", h->cycle_p99_ms},
                          {"inputs", inputs}};
            }};
  }
  throw std::runtime_error(fmt::format(
      "unknown ctl command '{}' (ping, getpose, setpose, global, scanners, scan, getca, setca, tracks, status)", c));
}

// Text for people: scalars as "key: value", lists one entry a line.
void printText(const json& j, const std::string& indent = "") {
  for (const auto& [key, value] : j.items()) {
    if (value.is_object()) {
      fmt::print("{}{}:\n", indent, key);
      printText(value, indent + "  ");
    } else if (value.is_array() && !value.empty() && value.front().is_object()) {
      fmt::print("{}{}:\n", indent, key);
      for (const auto& e : value) fmt::print("{}  {}\n", indent, e.dump());
    } else {
      fmt::print("{}{}: {}\n", indent, key, value.is_string() ? value.get<std::string>() : value.dump());
    }
  }
}

void run(const CtlArgs& a) {
  const Request req = makeRequest(a);  // usage errors before any connection
  if (a.port <= 0 || a.port > 65535)
    throw std::runtime_error(fmt::format("--port {} is not a TCP port (1-65535)", a.port));
  protocol::Client client(a.host, static_cast<uint16_t>(a.port), {a.timeout_ms});
  const auto t0 = std::chrono::steady_clock::now();
  const Frame reply = client.call(req.command, req.data);
  const double rtt_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  const char* name = protocol::commandName(req.command);
  const protocol::Status status = protocol::replyStatus(reply);
  const int32_t code = static_cast<int32_t>(status);
  if (protocol::isError(status))
    throw std::runtime_error(fmt::format("{}: {}: {} ({})", client.server(),
                                         reply.command == protocol::cmd::FRAME_ERROR ? "FRAME_ERROR" : name,
                                         protocol::toString(status), code));
  const auto data = req.decode(protocol::replyData(reply));
  if (!data)
    throw std::runtime_error(
        fmt::format("{}: {} reply of {} data words does not decode", client.server(), name, reply.data.size()));
  json out = {{"server", client.server()},
              {"command", name},
              {"status", protocol::toString(status)},
              {"status_code", code},
              {"rtt_ms", rtt_ms}};
  out.update(*data);
  if (a.json)
    fmt::print("{}\n", out.dump(-1, ' ', false, json::error_handler_t::replace));
  else
    printText(out);
}

}  // namespace cmd_ctl_impl

void registerCtl(CLI::App& app) {
  using namespace cmd_ctl_impl;
  auto args = std::make_shared<CtlArgs>();
  CLI::App* cmd = app.add_subcommand("ctl", "Query or command a running polylocd over its TCP control port");
  cmd->add_option("--port", args->port, "Control port of polylocd")->required();
  cmd->add_option("--host", args->host, "Host of polylocd")->capture_default_str();
  cmd->add_option("--timeout", args->timeout_ms, "Milliseconds to wait for the connection and the reply")
      ->capture_default_str();
  cmd->add_flag("--json", args->json, "Print one JSON object on stdout");
  cmd->add_option("command", args->command,
                  "ping, getpose, setpose X Y YAW_DEG [SIGMA_XY SIGMA_YAW_DEG], global, scanners, scan I, getca, setca "
                  "0|1, tracks, status")
      ->required();
  cmd->add_option("args", args->args, "Arguments of the command");
  cmd->callback([args] { run(*args); });
}

}  // namespace polyloc::cli
