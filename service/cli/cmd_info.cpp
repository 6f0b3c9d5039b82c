// polyloc info FILE: what a recording holds (format, time span, topics with types, counts and
// rates) and what was wrong in it. Reads every message once, so the rejected count and the
// warnings are those of a full read; --quick reports from the file's index/summary only.
#include "cli/commands.hpp"

#include <polyloc/io/recording.hpp>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdlib>
#include <ctime>
#include <limits>
#include <memory>

namespace polyloc::cli {
namespace {

struct InfoArgs {
  std::string file;
  bool json = false;
  bool quick = false;
};

struct Summary {
  std::string format;
  std::vector<TopicInfo> topics;
  int64_t start_ns = 0, end_ns = 0;
  uint64_t messages = 0;
  ReadStats stats;
  double durationS() const { return double(end_ns - start_ns) * 1e-9; }
};

Summary summarise(const InfoArgs& args) {
  auto reader = openRecording(args.file);
  Summary s;
  s.format = reader->format();
  s.topics = reader->topics();
  if (!args.quick) {
    RecordedMessage m;
    while (reader->next(m)) {
    }
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
  fmt::print("file:      {}\nformat:    {}\n", args.file, s.format);
  fmt::print("duration:  {:.3f} s\nstart:     {}\nend:       {}\nmessages:  {}\n", s.durationS(),
             timeText(s.start_ns), timeText(s.end_ns), s.messages);
  size_t name_w = 5, type_w = 4;
  for (const auto& t : s.topics) name_w = std::max(name_w, t.name.size()), type_w = std::max(type_w, t.type.size());
  fmt::print("\n{:<{}}  {:<{}}  {:>10}  {:>9}\n", "topic", name_w, "type", type_w, "count", "rate Hz");
  for (const auto& t : s.topics)
    fmt::print("{:<{}}  {:<{}}  {:>10}  {:>9.2f}\n", t.name, name_w, t.type, type_w, t.count, t.rateHz());
  fmt::print("\nrejected:  {}{}\n", s.stats.rejected, args.quick ? " (index only; run without --quick for a full read)" : "");
  const size_t shown = std::min<size_t>(s.stats.warnings.size(), 20);
  if (shown) fmt::print("warnings:\n");
  for (size_t i = 0; i < shown; ++i) fmt::print("  {}\n", s.stats.warnings[i]);
  if (s.stats.rejected > shown) fmt::print("  ... and {} more\n", s.stats.rejected - shown);
}

void printJson(const InfoArgs& args, const Summary& s) {
  nlohmann::json topics = nlohmann::json::object();
  for (const auto& t : s.topics) topics[t.name] = {{"type", t.type}, {"count", t.count}, {"rate_hz", t.rateHz()}};
  const nlohmann::json j = {{"format", s.format},       {"path", args.file},
                            {"duration_s", s.durationS()}, {"start_ns", s.start_ns},
                            {"end_ns", s.end_ns},       {"messages", s.messages},
                            {"topics", topics},         {"rejected", s.stats.rejected},
                            {"warnings", s.stats.warnings}};
  // Paths and warnings come from files: replace bytes that are not UTF-8 rather than throw.
  fmt::print("{}\n", j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
}

}  // namespace

void registerInfo(CLI::App& app) {
  auto args = std::make_shared<InfoArgs>();
  CLI::App* cmd = app.add_subcommand(
      "info", "Show what a recording holds: MCAP, ROS 2 bag (directory, metadata.yaml or .db3), CARMEN log");
  cmd->add_option("file", args->file, "Recording")->required();
  cmd->add_flag("--json", args->json, "Print one JSON object on stdout");
  cmd->add_flag("--quick", args->quick, "Use the file's index or summary only; skip the full read that counts bad records");
  cmd->callback([args] {
    const Summary s = summarise(*args);
    if (args->json)
      printJson(*args, s);
    else
      printText(*args, s);
  });
}

}  // namespace polyloc::cli
