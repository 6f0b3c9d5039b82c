#include "pipeline/daemon_config.hpp"

#include <polyloc/geometry/pose.hpp>

#include <arpa/inet.h>

#include <cctype>
#include <cmath>

namespace polyloc::pipeline {

DaemonConfig parseDaemonConfig(ConfigMap m) {
  DaemonConfig c;
  if (m.has("instance")) {
    const ConfigValue v = m.value("instance");
    c.instance = v.asString();
    for (char ch : c.instance)
      if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '_' && ch != '-' && ch != '.')
        v.fail("'" + c.instance + "': letters, digits, '_', '-', '.' only");
    if (c.instance.empty() || c.instance.size() > 24) v.fail("1 to 24 characters");
  }
  c.threads = static_cast<int>(m.getCount("threads", 0, 0, 4096));
  c.slots = static_cast<uint32_t>(m.getCount("slots", c.slots, 2, 4096));
  c.source_clock = m.getChoice("clock", "wall", {"wall", "source"}) == "source";
  auto ns = [&](const char* key, int64_t def, double lo, double hi) {
    return static_cast<int64_t>(std::llround(m.getDouble(key, double(def) * 1e-9, lo, hi) * 1e9));
  };
  c.max_age_ns = ns("max_age", c.max_age_ns, 0.001, 3600);
  // Under clock: source the newest stamp is "now" and the next frame is a frame period, or a
  // pause in the recording, after it: a wider default.
  c.max_future_ns = ns("max_future", c.source_clock ? 2'000'000'000 : c.max_future_ns, 0, 3600);
  c.clock_agree = m.getCount("clock_agree", c.clock_agree, 1, 1000);
  c.input_timeout_ns = ns("input_timeout", c.input_timeout_ns, 0.01, 3600);
  c.odom_wait_ns = ns("odom_wait", c.odom_wait_ns, 0, 10);
  c.search_beside = m.getChoice("global_search", "beside", {"beside", "inline"}) == "beside";
  c.health_rate_hz = m.getDouble("health_rate", c.health_rate_hz, 0.1, 1000);
  if (m.has("init")) {
    const ConfigValue v = m.value("init");
    if (v.isScalar()) {
      if (v.asString() != "global") v.fail("init: 'global' or a pose {x, y, z, yaw, sigma_xy, sigma_yaw}");
    } else {
      ConfigMap p = v.asMap();
      InitPose ip;
      ip.pose = Pose::fromXYZRPY(p.getDouble("x", 0, -1e6, 1e6), p.getDouble("y", 0, -1e6, 1e6), p.getDouble("z", 0, -1e6, 1e6), 0, 0, p.getAngle("yaw", 0));
      ip.sigma_xy = p.getDouble("sigma_xy", ip.sigma_xy, 0, 100);
      ip.sigma_yaw = p.getAngle("sigma_yaw", ip.sigma_yaw);
      p.finish();
      c.init = ip;
    }
  }
  if (m.has("control")) {
    ConfigMap k = m.map("control");
    c.control.enabled = k.getBool("enabled", c.control.enabled);
    if (k.has("bind")) {  // checked here, so --check names it with file:line, not the start
      const ConfigValue v = k.value("bind");
      c.control.bind = v.asString();
      in_addr buf{};
      if (inet_pton(AF_INET, c.control.bind.c_str(), &buf) != 1)
        v.fail("'" + c.control.bind + "' is not an IPv4 address (127.0.0.1: this computer only; 0.0.0.0: every interface)");
    }
    c.control.port = static_cast<uint16_t>(k.getCount("port", c.control.port, 0, 65535));
    k.finish();
  }
  if (m.has("live")) {
    ConfigMap k = m.map("live");
    live::LiveConfig& l = c.live;
    if (k.has("address")) {
      const ConfigValue v = k.value("address");
      l.address = v.asString();
      in6_addr buf{};
      if (inet_pton(AF_INET, l.address.c_str(), &buf) != 1 && inet_pton(AF_INET6, l.address.c_str(), &buf) != 1)
        v.fail("'" + l.address + "' is not an IP address (127.0.0.1: this computer only; 0.0.0.0: every interface)");
    }
    l.port = static_cast<uint16_t>(k.getCount("port", l.port, 0, 65535));
    l.max_clients = static_cast<int>(k.getCount("max_clients", l.max_clients, 1, 1000));
    l.max_queue_mib = k.getDouble("max_queue", l.max_queue_mib, 0.01, 4096);
    l.stall_timeout_s = k.getDouble("stall_timeout", l.stall_timeout_s, 0.1, 3600);
    l.max_pending = static_cast<int>(k.getCount("max_pending", l.max_pending, 1, 1000));
    l.handshake_timeout_s = k.getDouble("handshake_timeout", l.handshake_timeout_s, 0.1, 60);
    l.max_subscriptions = static_cast<int>(k.getCount("max_subscriptions", l.max_subscriptions, 1, 100000));
    l.max_client_rate = k.getDouble("max_client_rate", l.max_client_rate, 1, 100000);
    l.particles = static_cast<size_t>(k.getCount("particles", l.particles, 1, 1'000'000));
    l.rate_hz = k.getDouble("rate", l.rate_hz, 0.01, 1000);
    l.slice_height = float(k.getDouble("slice_height", l.slice_height, -100, 100));
    k.finish();
  }
  c.log_level = m.getChoice("log_level", c.log_level, {"trace", "debug", "info", "warn", "error", "off"});
  m.finish();
  return c;
}

ServiceConfig loadServiceConfig(const std::string& path) {
  ServiceConfig s;
  s.polyloc = loadConfig(path);
  ConfigMap m = ConfigMap::load(path);
  if (m.has("polylocd")) s.daemon = parseDaemonConfig(m.map("polylocd"));
  return s;
}

}  // namespace polyloc::pipeline
