// Recordings: a stream of timestamped messages on named topics, read from or written to a file
// (MCAP, ROS 2 bag in sqlite3 storage, CARMEN log). Readers stream: memory stays flat however
// long the recording. Bad records are counted and reported (file, topic, time) and reading goes
// on where the format allows; a file that cannot be read at all throws IoError.
#pragma once

#include <polyloc/io/error.hpp>
#include <polyloc/io/messages.hpp>

#include <map>
#include <memory>
#include <string>
#include <vector>

namespace polyloc {

struct RecordedMessage {
  std::string topic;
  int64_t log_time_ns = 0;      // when it was recorded
  int64_t publish_time_ns = 0;  // when it was sent (= log time where the format has one only)
  msg::Message message;
};

struct TopicInfo {
  std::string name;
  std::string type;  // ROS 2 type name, e.g. "sensor_msgs/msg/LaserScan"
  uint64_t count = 0;
  int64_t first_ns = 0, last_ns = 0;
  double rateHz() const {
    return count > 1 && last_ns > first_ns ? (count - 1) * 1e9 / double(last_ns - first_ns) : 0.0;
  }
};

// Topics of a stream of messages, in order of first appearance: for readers that have no index
// and count their topics in a pass of their own.
class TopicTally {
 public:
  void add(const RecordedMessage& m);
  const std::vector<TopicInfo>& topics() const { return topics_; }

 private:
  std::vector<TopicInfo> topics_;
  std::map<std::string, size_t> index_;
};

struct ReadStats {
  uint64_t messages = 0;        // delivered by next()
  uint64_t rejected = 0;        // records skipped as bad (warnings says why)
  std::vector<std::string> warnings;  // "FILE: topic T at t=...: what was wrong", first 100 kept
  // How the reader read what the file left open (a field of an old format taken in another
  // unit, odometry taken from the scans' fields), once each; nothing was rejected.
  std::vector<std::string> notes;
  void warn(std::string w) {
    ++rejected;
    if (warnings.size() < 100) warnings.push_back(std::move(w));
  }
  void note(std::string n) {
    if (notes.size() < 100) notes.push_back(std::move(n));
  }
};

class RecordingReader {
 public:
  virtual ~RecordingReader() = default;
  // Topics with types, counts and time span (from the file's index or summary where it has
  // one; otherwise by a streaming pass over the file, which does not disturb next()).
  virtual std::vector<TopicInfo> topics() = 0;
  // Next message in log-time order; false at the end.
  virtual bool next(RecordedMessage& out) = 0;
  virtual const ReadStats& stats() const = 0;
  virtual std::string format() const = 0;  // "mcap", "ros2bag", "carmen", "tum-rgbd", "7scenes"
};

class RecordingWriter {
 public:
  virtual ~RecordingWriter() = default;
  // Messages may come in any topic order; a topic's type is fixed by its first message.
  virtual void write(const std::string& topic, int64_t log_time_ns, const msg::Message& m) = 0;
  virtual void close() = 0;  // writes indexes/summary; also called by the destructor
};

// By content and name: MCAP magic, a ROS 2 bag directory (or its metadata.yaml / .db3), a
// CARMEN log (.log, .clf, .gz), a depth data set folder (TUM RGB-D, 7-Scenes:
// io/rgbd_dataset.hpp). Throws IoError naming the path when it is none of them.
std::unique_ptr<RecordingReader> openRecording(const std::string& path);

// Format-specific entry points (each in its own file in kernels/io).
std::unique_ptr<RecordingReader> openMcap(const std::string& path);
std::unique_ptr<RecordingReader> openRos2Bag(const std::string& path);
std::unique_ptr<RecordingReader> openCarmen(const std::string& path);

struct McapWriteOptions {
  std::string compression = "zstd";  // "zstd", "lz4" or "" (none)
  uint64_t chunk_size = 1 << 20;     // bytes of uncompressed records per chunk
  std::string profile = "ros2";
};
std::unique_ptr<RecordingWriter> createMcap(const std::string& path, const McapWriteOptions& o = {});
// Discards every message: for simulations whose frames are taken from hooks, not from a file.
class NullRecordingWriter final : public RecordingWriter {
 public:
  void write(const std::string&, int64_t, const msg::Message&) override {}
  void close() override {}
};

// Messages and time span of a recording, from its topics (for progress and relative times).
struct RecordingSpan {
  uint64_t messages = 0;
  int64_t first_ns = 0, last_ns = 0;
};
RecordingSpan spanOf(const std::vector<TopicInfo>& topics);

// ROS 2 bag directory (metadata.yaml + NAME_0.db3), as `ros2 bag record` writes it.
std::unique_ptr<RecordingWriter> createRos2Bag(const std::string& directory);

}  // namespace polyloc
