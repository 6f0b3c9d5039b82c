// polyloc bench ipc: one-way latency of one message size over a shm channel (reader woken by
// futex), a UNIX domain socket and loopback TCP, in the same run (docs/interface.md, "Latency").
#include "cli/parse_number.hpp"
#include "cli/commands.hpp"
#include "engines/ipc_latency.hpp"

#include "shm/channel.hpp"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <sched.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <map>

namespace polyloc::cli {

using engines::IpcLatencyConfig;
using engines::IpcSamples;
using engines::shmLatency;
using engines::tcpLatency;
using engines::udsLatency;
namespace cmd_bench_ipc_impl {  // named, not anonymous: the CLI is compiled in batches (unity build)

struct BenchIpcArgs {
  IpcLatencyConfig config;
  double spin_us = shm::kDefaultSpinNs / 1000.0;
  size_t turns = 4;
  bool pin = true;
  bool json = false;
};

struct Stats {
  double p50, p99, p999, max, mean;
  size_t count;
};

Stats stats(std::vector<int64_t> v) {
  if (v.empty()) throw std::runtime_error("bench ipc: no message arrived");
  std::sort(v.begin(), v.end());
  const auto at = [&](double q) { return v[std::min(v.size() - 1, static_cast<size_t>(q * static_cast<double>(v.size())))] * 1e-3; };
  double sum = 0;
  for (int64_t x : v) sum += static_cast<double>(x);
  return {at(0.5), at(0.99), at(0.999), v.back() * 1e-3, sum / static_cast<double>(v.size()) * 1e-3, v.size()};
}

// The first two CPUs this process may run on: writer and reader apart, so that the reader's
// CPU is idle (and the reader asleep) when a message comes.
void pickCpus(IpcLatencyConfig& c) {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) != 0) return;
  std::vector<int> cpus;
  for (int i = 0; i < CPU_SETSIZE && cpus.size() < 2; ++i)
    if (CPU_ISSET(i, &set)) cpus.push_back(i);
  if (cpus.size() < 2) return;
  c.writer_cpu = cpus[0];
  c.reader_cpu = cpus[1];
}

// received < messages: the shm reader was lapped (descheduled for longer than the ring lasts)
// and skipped to the newest message; the lost ones are not in the percentiles.
nlohmann::json statsJson(const Stats& x, const Stats& send, size_t messages) {
  return {{"p50_us", x.p50},        {"p99_us", x.p99},          {"p999_us", x.p999},
          {"max_us", x.max},        {"mean_us", x.mean},        {"received", x.count},
          {"lost", messages - x.count}, {"send_p50_us", send.p50}, {"send_p99_us", send.p99}};
}

void runBenchIpc(BenchIpcArgs a) {
  IpcLatencyConfig& c = a.config;
  if (a.pin) pickCpus(c);
  const bool tty = isatty(fileno(stderr));
  // shm twice: the reader woken from FUTEX_WAIT (spinning --spin-us first), and a reader that
  // spins through the whole gap between messages and so never sleeps.
  const int64_t spin_ns = static_cast<int64_t>(a.spin_us * 1000);
  const int64_t always_spin_ns = std::max<int64_t>(spin_ns, static_cast<int64_t>(4 * c.period_us * 1000));
  using Run = IpcSamples (*)(const IpcLatencyConfig&, const std::function<void(double)>&);
  struct Transport {
    const char* name;
    Run run;
    int64_t spin_ns;
  };
  const Transport transports[] = {{"shm", shmLatency, spin_ns},
                                  {"uds", udsLatency, 0},
                                  {"tcp", tcpLatency, 0},
                                  {"shm_spin", shmLatency, always_spin_ns}};
  // In turns, one transport after another: a change in the machine's load hits them alike.
  std::map<std::string, IpcSamples> all;
  const size_t turns = std::max<size_t>(1, std::min(a.turns, c.messages));
  IpcLatencyConfig rc = c;
  for (size_t r = 0; r < turns; ++r) {
    rc.messages = c.messages / turns + (r + 1 == turns ? c.messages % turns : 0);
    for (const Transport& x : transports) {
      fmt::print(stderr, "bench ipc: turn {}/{}: {} ({} messages of {} bytes, one per {} us)\n", r + 1, turns, x.name,
                 rc.messages, rc.bytes, rc.period_us);
      auto progress = [&, name = x.name](double f) {
        if (tty) fmt::print(stderr, "\r  {} {:3.0f} %", name, 100 * f);
      };
      rc.spin_ns = x.spin_ns;
      IpcSamples got = x.run(rc, progress);
      if (tty) fmt::print(stderr, "\r");
      IpcSamples& acc = all[x.name];
      acc.latency_ns.insert(acc.latency_ns.end(), got.latency_ns.begin(), got.latency_ns.end());
      acc.send_ns.insert(acc.send_ns.end(), got.send_ns.begin(), got.send_ns.end());
    }
  }
  nlohmann::json t = nlohmann::json::object();
  std::map<std::string, Stats> s;
  for (const Transport& x : transports) {
    s[x.name] = stats(all[x.name].latency_ns);
    t[x.name] = statsJson(s[x.name], stats(all[x.name].send_ns), c.messages);
  }
  t["shm_spin"]["spin_us"] = always_spin_ns * 1e-3;
  const double ratio = s["shm"].p99 / s["uds"].p99, ratio_spin = s["shm_spin"].p99 / s["uds"].p99;
  nlohmann::json j;
  j["message_bytes"] = c.bytes;
  j["messages"] = c.messages;
  j["turns"] = turns;
  j["period_us"] = c.period_us;
  j["spin_us"] = a.spin_us;
  j["writer_cpu"] = c.writer_cpu;
  j["reader_cpu"] = c.reader_cpu;
  j["rt_priority"] = c.rt_priority;
  j["transports"] = t;
  j["ratio_shm_p99_to_uds_p99"] = ratio;
  j["ratio_shm_spin_p99_to_uds_p99"] = ratio_spin;
  // A lost message is a latency beyond measure: a run that lost any does not meet the target.
  j["target_met"] = s["shm"].p99 <= 10.0 && ratio <= 0.1 && s["shm"].count == c.messages;
  j["target_met_spinning"] = s["shm_spin"].p99 <= 10.0 && ratio_spin <= 0.1 && s["shm_spin"].count == c.messages;
  if (a.json) {
    fmt::print("{}\n", j.dump());
    return;
  }
  fmt::print("one-way latency, {} messages of {} bytes, one per {} us, CPUs {} -> {}, rt priority {}\n", c.messages,
             c.bytes, c.period_us, c.writer_cpu, c.reader_cpu, c.rt_priority);
  fmt::print("{:>9} {:>9} {:>9} {:>9} {:>9}  (us; lost: lapped by the writer)\n", "", "p50", "p99", "p99.9", "max");
  for (const Transport& x : transports)
    fmt::print("{:>9} {:9.2f} {:9.2f} {:9.2f} {:9.2f}  {} lost\n", x.name, s[x.name].p50, s[x.name].p99, s[x.name].p999,
               s[x.name].max, c.messages - s[x.name].count);
  fmt::print("shm (spin {} us, then futex): p99 / uds p99 = {:.3f}; shm_spin (spin {} us): {:.3f}; target: p99 <= 10 us "
             "and ratio <= 0.1\n",
             a.spin_us, ratio, always_spin_ns * 1e-3, ratio_spin);
}

}  // namespace cmd_bench_ipc_impl

void registerBenchIpc(CLI::App& bench) {
  using namespace cmd_bench_ipc_impl;
  auto a = std::make_shared<BenchIpcArgs>();
  CLI::App& ipc = *bench.add_subcommand(
      "ipc", "One-way latency writer -> sleeping reader: shm channel (futex), UNIX socket, loopback TCP");
  ipc.add_option("--bytes", a->config.bytes, "Message bytes (default: a 541-beam scan)")
      ->capture_default_str()->check(finiteRange(16u, 1u << 26));
  ipc.add_option("--messages", a->config.messages, "Messages per transport")->capture_default_str()->check(positiveFinite());
  ipc.add_option("--warmup", a->config.warmup, "Messages sent first and not counted")->capture_default_str();
  ipc.add_option("--period-us", a->config.period_us, "Time between messages (us)")->capture_default_str()->check(positiveFinite());
  ipc.add_option("--spin-us", a->spin_us, "shm: the reader spins this long before FUTEX_WAIT (Reader::wait)")
      ->capture_default_str()->check(nonNegativeFinite());
  ipc.add_option("--turns", a->turns, "Turns the transports take, one after another (messages split among them)")
      ->capture_default_str()->check(positiveFinite());
  ipc.add_flag("!--no-pin", a->pin, "Do not pin writer and reader to two CPUs");
  ipc.add_option("--rt-priority", a->config.rt_priority, "SCHED_FIFO priority of writer and reader (0: normal threads)")
      ->capture_default_str()->check(finiteRange(0, 99));
  ipc.add_flag("--json", a->json, "Print one JSON object on stdout");
  ipc.callback([a] { runBenchIpc(*a); });
}

}  // namespace polyloc::cli
