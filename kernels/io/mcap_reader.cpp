// MCAP reader: the raw message stream of mcap_source.hpp, decoded into polyloc's message structs.
// Channels of types polyloc does not know, messages on channels never declared and payloads that
// do not decode are skipped, counted, and reported with file, topic and time.
#include "mcap_source.hpp"

#include <polyloc/io/cdr.hpp>
#include <polyloc/io/recording.hpp>

#include <algorithm>
#include <cstdio>

namespace polyloc {
namespace {

std::string seconds(uint64_t ns) {
  char b[40];
  std::snprintf(b, sizeof b, "%llu.%09llu s", static_cast<unsigned long long>(ns / 1000000000),
                static_cast<unsigned long long>(ns % 1000000000));
  return b;
}

// "sensor_msgs/LaserScan" (the ROS 1 style some writers use) -> "sensor_msgs/msg/LaserScan".
std::string rosTypeName(const std::string& name) {
  if (std::count(name.begin(), name.end(), '/') != 1) return name;
  return name.substr(0, name.find('/')) + "/msg" + name.substr(name.find('/'));
}

class McapReader final : public RecordingReader {
 public:
  explicit McapReader(const std::string& path) : path_(path), source_(path, true, stats_) {}

  std::vector<TopicInfo> topics() override {
    std::vector<TopicInfo> out;
    if (source_.indexed() && source_.statistics()) {
      const auto& counts = source_.statistics()->channel_message_counts;
      for (const auto& [id, c] : source_.channels()) {
        TopicInfo t{c.topic, typeOf(source_, c), 0, 0, 0};
        if (auto it = counts.find(id); it != counts.end()) t.count = it->second;
        if (auto span = source_.channelSpan(id)) {
          t.first_ns = static_cast<int64_t>(span->first);
          t.last_ns = static_cast<int64_t>(span->second);
        }
        out.push_back(std::move(t));
      }
      return out;
    }
    // No usable summary: a pass of its own over the file, leaving next() where it is.
    ReadStats ignored;
    mcap::MessageSource pass(path_, false, ignored);
    std::map<uint16_t, TopicInfo> by_channel;
    mcap::RawMessage m;
    while (pass.next(m)) {
      auto c = pass.channels().find(m.channel_id);
      if (c == pass.channels().end()) continue;
      auto [it, added] = by_channel.try_emplace(m.channel_id);
      TopicInfo& t = it->second;
      auto time = static_cast<int64_t>(m.log_time);
      if (added) t = {c->second.topic, typeOf(pass, c->second), 0, time, time};
      ++t.count;
      t.first_ns = std::min(t.first_ns, time);
      t.last_ns = std::max(t.last_ns, time);
    }
    for (auto& [id, t] : by_channel) out.push_back(std::move(t));
    return out;
  }

  bool next(RecordedMessage& out) override {
    mcap::RawMessage m;
    while (source_.next(m)) {
      Decoding& d = decodingOf(m.channel_id);
      if (d.type.empty()) {
        if (d.skipped++ == 0) d.first_skipped = m.log_time;
        ++stats_.rejected;
        continue;
      }
      try {
        out.message = msg::decodeCdr(d.type, m.payload);
      } catch (const IoError& e) {
        stats_.warn(path_ + ": topic " + d.topic + " at t=" + seconds(m.log_time) + ": " + e.what());
        continue;
      }
      out.topic = d.topic;
      out.log_time_ns = static_cast<int64_t>(m.log_time);
      out.publish_time_ns = static_cast<int64_t>(m.publish_time);
      ++stats_.messages;
      return true;
    }
    reportSkipped();
    return false;
  }

  const ReadStats& stats() const override { return stats_; }
  std::string format() const override { return "mcap"; }

 private:
  // What next() does with a channel's messages; decided once per channel.
  struct Decoding {
    std::string topic, type;  // type empty: skip
    std::string why;          // why skipped
    uint64_t skipped = 0, first_skipped = 0;
  };

  static std::string typeOf(const mcap::MessageSource& s, const mcap::Channel& c) {
    auto it = s.schemas().find(c.schema_id);
    return it == s.schemas().end() ? std::string() : rosTypeName(it->second.name);
  }

  Decoding& decodingOf(uint16_t channel_id) {
    auto [it, added] = decodings_.try_emplace(channel_id);
    Decoding& d = it->second;
    if (!added) return d;
    auto c = source_.channels().find(channel_id);
    if (c == source_.channels().end()) {
      d.why = "message on unknown channel " + std::to_string(channel_id);
      return d;
    }
    d.topic = c->second.topic;
    std::string type = typeOf(source_, c->second);
    const auto& known = msg::supportedTypes();
    if (c->second.message_encoding != "cdr")
      d.why = "topic " + d.topic + " (encoding " + c->second.message_encoding + ") is not supported";
    else if (std::find(known.begin(), known.end(), type) == known.end())
      d.why = "topic " + d.topic + " (type " + (type.empty() ? "without schema" : type) +
              ") is not supported";
    else
      d.type = type;
    return d;
  }

  // One warning per skipped channel, at the end, rather than one per message.
  void reportSkipped() {
    if (reported_) return;
    reported_ = true;
    for (const auto& [id, d] : decodings_) {
      if (d.skipped == 0) continue;
      std::string w = path_ + ": " + d.why + "; " + std::to_string(d.skipped) +
                      " messages skipped (first at t=" + seconds(d.first_skipped) + ")";
      if (stats_.warnings.size() < 100) stats_.warnings.push_back(std::move(w));
    }
  }

  std::string path_;
  ReadStats stats_;
  mcap::MessageSource source_;
  std::map<uint16_t, Decoding> decodings_;
  bool reported_ = false;
};

}  // namespace

std::unique_ptr<RecordingReader> openMcap(const std::string& path) {
  return std::make_unique<McapReader>(path);
}

}  // namespace polyloc
