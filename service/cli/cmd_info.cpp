// polyloc info FILE: what a recording holds (format, time span, topics with types, counts and
// rates) and what was wrong in it. Reads every message once, so the rejected count and the
// warnings are those of a full read; --quick reports from the file's index/summary only.
#include "cli/parse_number.hpp"
#include "cli/commands.hpp"

#include <polyloc/io/recording.hpp>
#include <polyloc/io/restamp.hpp>
#include <polyloc/io/stamp_check.hpp>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdlib>
#include <ctime>
#include <limits>
#include <memory>

namespace polyloc::cli {
namespace cmd_info_impl {  // named, not anonymous: the CLI is compiled in batches (unity build)

struct InfoArgs {
  std::string file;
  bool json = false;
  bool quick = false;
  double restamp_hz = 0;
};

struct Summary {
  std::string format;
  std::vector<TopicInfo> topics;
  int64_t start_ns = 0, end_ns = 0;
  uint64_t messages = 0;
  ReadStats stats;
  StampCheck stamps;  // full read only
  double durationS() const { return double(end_ns - start_ns) * 1e-9; }
  // Stamps that do not increase make the span and the rates meaningless (csail's six digits
  // made a 1,134,870,000 s log at 0.04 Hz of it).
  bool timeUnknown() const { return stamps.bad() > 0; }
  bool rateUnknown(const std::string& topic) const {
    auto it = stamps.topics().find(topic);
    return it != stamps.topics().end() && it->second.bad() > 0;
  }
};

Summary summarise(const InfoArgs& args) {
  auto reader = openRecording(args.file);
  if (args.restamp_hz > 0) reader = restampByOrder(std::move(reader), args.restamp_hz);
  Summary s;
  s.format = reader->format();
  s.topics = reader->topics();
  if (!args.quick) {
    RecordedMessage m;
    for (uint64_t i = 0; reader->next(m); ++i)
      if (isStampedStream(m)) s.stamps.add(m.topic, messageStamp(m), i);
  }
  s.stats = reader->stats();
  int64_t lo = std::numeric_limits<int64_t>::max(), hi = std::numeric_limits<int64_t>::min();
  for (const auto& t : s.topics) {
    s.messages += t.count;
    if (t.count == 0) continue;
    lo = std::min(lo, t.first_ns);
    hi = std::max(hi, t.last_ns);
  }
  if (lo <= hi) s.start_ns = lo, s.end_ns = hi;
  return s;
}

// "1000.250000000 s (2001-09-09 01:46:40 UTC)": the date only where it is plausibly one.
std::string timeText(int64_t ns) {
  std::string text = fmt::format("{}.{:09d} s", ns / 1000000000, std::abs(ns % 1000000000));
  if (ns > int64_t{946684800} * 1000000000) {  // after 2000-01-01: wall-clock time
    const std::time_t t = static_cast<std::time_t>(ns / 1000000000);
    std::tm tm{};
    char buf[64];
    if (gmtime_r(&t, &tm) && std::strftime(buf, sizeof buf, "%Y-%m-%d %H:%M:%S UTC", &tm))
      text += fmt::format(" ({})", buf);
  }
  return text;
}

void printText(const InfoArgs& args, const Summary& s) {
  fmt::print("file:      {}\nformat:    {}{}\n", args.file, s.format,
             args.restamp_hz > 0 ? fmt::format(" (restamped by order at {:g} Hz)", args.restamp_hz) : "");
  if (s.timeUnknown())
    fmt::print("duration:  unknown: {} stamps do not increase (below); --restamp HZ orders messages by their place\n",
               s.stamps.bad());
  else
    fmt::print("duration:  {:.3f} s\n", s.durationS());
  fmt::print("start:     {}\nend:       {}\n", timeText(s.start_ns), timeText(s.end_ns));
  // The index (an MCAP summary, a bag's metadata.yaml) may claim messages that cannot be read.
  if (!args.quick && s.stats.messages != s.messages)
    fmt::print("messages:  {} readable of the {} its index lists ({} records rejected: below)\n", s.stats.messages,
               s.messages, s.stats.rejected);
  else
    fmt::print("messages:  {}\n", s.messages);
  size_t name_w = 5, type_w = 4;
  for (const auto& t : s.topics) name_w = std::max(name_w, t.name.size()), type_w = std::max(type_w, t.type.size());
  fmt::print("\n{:<{}}  {:<{}}  {:>10}  {:>9}\n", "topic", name_w, "type", type_w, "count", "rate Hz");
  for (const auto& t : s.topics)
    fmt::print("{:<{}}  {:<{}}  {:>10}  {:>9}\n", t.name, name_w, t.type, type_w, t.count,
               s.rateUnknown(t.name) ? "?" : fmt::format("{:.2f}", t.rateHz()));
  const auto stamp_warnings = s.stamps.warnings();
  if (!stamp_warnings.empty()) fmt::print("\nstamps that do not increase:\n");
  for (const auto& w : stamp_warnings) fmt::print("  {}\n", w);
  if (!s.stats.notes.empty()) fmt::print("\nnotes:\n");
  for (const auto& n : s.stats.notes) fmt::print("  {}\n", n);
  fmt::print("\nrejected:  {}{}\n", s.stats.rejected, args.quick ? " (index only; run without --quick for a full read)" : "");
  const size_t shown = std::min<size_t>(s.stats.warnings.size(), 20);
  if (shown) fmt::print("warnings:\n");
  for (size_t i = 0; i < shown; ++i) fmt::print("  {}\n", s.stats.warnings[i]);
  if (s.stats.rejected > shown) fmt::print("  ... and {} more\n", s.stats.rejected - shown);
}

void printJson(const InfoArgs& args, const Summary& s) {
  nlohmann::json topics = nlohmann::json::object();
  for (const auto& t : s.topics)
    topics[t.name] = {{"type", t.type}, {"count", t.count},
                      {"rate_hz", s.rateUnknown(t.name) ? nlohmann::json(nullptr) : nlohmann::json(t.rateHz())}};
  nlohmann::json stamps = nlohmann::json::object();
  for (const auto& [name, st] : s.stamps.topics())
    if (st.bad() > 0)
      stamps[name] = {{"messages", st.messages}, {"zero", st.zero}, {"equal", st.equal}, {"backwards", st.backwards},
                      {"first_message", st.first_index}, {"first_stamp_ns", st.first_stamp}};
  const nlohmann::json j = {{"format", s.format},       {"path", args.file},
                            {"duration_s", s.timeUnknown() ? nlohmann::json(nullptr) : nlohmann::json(s.durationS())},
                            {"start_ns", s.start_ns},
                            {"stamps_not_increasing", stamps}, {"notes", s.stats.notes},
                            {"restamp_hz", args.restamp_hz > 0 ? nlohmann::json(args.restamp_hz) : nlohmann::json(nullptr)},
                            {"end_ns", s.end_ns},       {"messages", s.messages},
                            {"messages_readable", args.quick ? nlohmann::json(nullptr) : nlohmann::json(s.stats.messages)},
                            {"topics", topics},         {"rejected", s.stats.rejected},
                            {"warnings", s.stats.warnings}};
  // Paths and warnings come from files: replace bytes that are not UTF-8 rather than throw.
  fmt::print("{}\n", j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
}

}  // namespace cmd_info_impl

void registerInfo(CLI::App& app) {
  using namespace cmd_info_impl;
  auto args = std::make_shared<InfoArgs>();
  CLI::App* cmd = app.add_subcommand(
      "info", "Show what a recording holds: MCAP, ROS 2 bag (directory, metadata.yaml or .db3), CARMEN log");
  cmd->add_option("file", args->file, "Recording")->required();
  cmd->add_flag("--json", args->json, "Print one JSON object on stdout");
  cmd->add_flag("--quick", args->quick, "Use the file's index or summary only; skip the full read that counts bad records and checks stamps");
  cmd->add_option("--restamp", args->restamp_hz, "Restamp every message by its order in the recording at this rate (Hz)")
      ->check(finiteRange(1e-3, 1e9));
  cmd->callback([args] {
    const Summary s = summarise(*args);
    if (args->json)
      printJson(*args, s);
    else
      printText(*args, s);
  });
}

}  // namespace polyloc::cli
