// ROS 2 bags in sqlite3 storage, as rosbag2 (Foxy to Jazzy) writes them: a directory with
// metadata.yaml and one or more .db3 files. Every file is checked when the bag is opened (a
// corrupt or truncated one throws IoError naming it); messages are then streamed file by file
// with one prepared SELECT ordered by time, so memory stays flat. rosbag2 splits a bag in time
// order, so reading the files one after the other keeps log-time order.
#include <polyloc/io/cdr.hpp>
#include <polyloc/io/recording.hpp>

#include "decimal_seconds.hpp"

#include <sqlite3.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <set>

namespace polyloc {
namespace {

namespace fs = std::filesystem;

struct DbClose {
  void operator()(sqlite3* db) const { sqlite3_close(db); }
};
struct StmtFinalize {
  void operator()(sqlite3_stmt* s) const { sqlite3_finalize(s); }
};
using Db = std::unique_ptr<sqlite3, DbClose>;
using Stmt = std::unique_ptr<sqlite3_stmt, StmtFinalize>;

std::string text(sqlite3_stmt* s, int col) {
  const unsigned char* p = sqlite3_column_text(s, col);
  return p ? std::string(reinterpret_cast<const char*>(p), sqlite3_column_bytes(s, col)) : std::string();
}

uint32_t bigEndian32(const unsigned char* p) {
  return uint32_t{p[0]} << 24 | uint32_t{p[1]} << 16 | uint32_t{p[2]} << 8 | p[3];
}

// The 100-byte sqlite header says how large the file must be; sqlite itself would only notice
// a cut file when a query reaches a missing page, so check it here, before anything is read.
void checkSqliteHeader(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path + ": cannot open");
  unsigned char h[100] = {};
  in.read(reinterpret_cast<char*>(h), sizeof h);
  if (in.gcount() < 100 || std::memcmp(h, "SQLite format 3", 16) != 0)
    throw IoError(path + ": not an sqlite3 database (corrupt, or not a ROS 2 bag file)");
  uint64_t page_size = uint32_t{h[16]} << 8 | h[17];
  if (page_size == 1) page_size = 65536;
  const uint32_t pages = bigEndian32(h + 28);
  const bool size_valid = pages != 0 && bigEndian32(h + 24) == bigEndian32(h + 92);
  std::error_code ec;
  const uint64_t size = fs::file_size(path, ec);
  if (size_valid && !ec && size < pages * page_size)
    throw IoError(path + ": truncated: " + std::to_string(size) + " of " +
                  std::to_string(pages * page_size) + " bytes");
}

struct BagTopic {
  std::string name, type, serialization_format;
  bool supported() const {
    const auto& types = msg::supportedTypes();
    return serialization_format == "cdr" && std::find(types.begin(), types.end(), type) != types.end();
  }
};

// One .db3 file, open for reading; its topics table read (topic ids are per file).
class Db3File {
 public:
  explicit Db3File(std::string path) : path_(std::move(path)) {
    checkSqliteHeader(path_);
    sqlite3* db = nullptr;
    const int rc = sqlite3_open_v2(path_.c_str(), &db, SQLITE_OPEN_READONLY, nullptr);
    db_.reset(db);
    if (rc != SQLITE_OK) throw IoError(path_ + ": cannot open: " + error());
    Stmt s = prepare("SELECT id, name, type, serialization_format FROM topics");
    int step;
    while ((step = sqlite3_step(s.get())) == SQLITE_ROW)
      topics_[sqlite3_column_int64(s.get(), 0)] = {text(s.get(), 1), text(s.get(), 2), text(s.get(), 3)};
    if (step != SQLITE_DONE) throw IoError(path_ + ": reading the topics table: " + error());
  }
  Stmt prepare(const char* sql) const {
    sqlite3_stmt* s = nullptr;
    if (sqlite3_prepare_v2(db_.get(), sql, -1, &s, nullptr) != SQLITE_OK) {
      sqlite3_finalize(s);
      throw IoError(path_ + ": not a rosbag2 database: " + error());
    }
    return Stmt(s);
  }
  std::string error() const { return db_ ? sqlite3_errmsg(db_.get()) : "out of memory"; }
  const std::string& path() const { return path_; }
  const std::map<int64_t, BagTopic>& topics() const { return topics_; }

 private:
  std::string path_;
  Db db_;
  std::map<int64_t, BagTopic> topics_;
};

// What metadata.yaml says; missing keys are tolerated (the .db3 files are the truth).
struct BagMetadata {
  std::string storage = "sqlite3", compression;
  std::vector<std::string> files;
  std::vector<TopicInfo> topics;
  bool has_topics = false;
};

YAML::Node child(const YAML::Node& n, const char* key) {
  if (!n.IsMap()) return YAML::Node();
  const YAML::Node c = n[key];
  return c.IsDefined() ? c : YAML::Node();
}

BagMetadata readMetadata(const std::string& path) {
  BagMetadata m;
  try {
    const YAML::Node root = YAML::LoadFile(path);
    const YAML::Node info = child(root, "rosbag2_bagfile_information");
    if (!info.IsMap()) throw IoError(path + ": no rosbag2_bagfile_information mapping; not a rosbag2 metadata file");
    m.storage = child(info, "storage_identifier").as<std::string>("sqlite3");
    m.compression = child(info, "compression_format").as<std::string>("");
    const int64_t start = child(child(info, "starting_time"), "nanoseconds_since_epoch").as<int64_t>(0);
    const int64_t duration = child(child(info, "duration"), "nanoseconds").as<int64_t>(0);
    for (const YAML::Node& f : child(info, "relative_file_paths")) m.files.push_back(f.as<std::string>());
    const YAML::Node topics = child(info, "topics_with_message_count");
    m.has_topics = topics.IsSequence();
    for (const YAML::Node& t : topics) {
      const YAML::Node meta = child(t, "topic_metadata");
      // rosbag2 keeps no per-topic time span: the bag's span stands in for it.
      m.topics.push_back({child(meta, "name").as<std::string>(), child(meta, "type").as<std::string>(""),
                          child(t, "message_count").as<uint64_t>(0), start, start + duration});
    }
  } catch (const YAML::Exception& e) {
    throw IoError(path + (e.mark.is_null() ? "" : ":" + std::to_string(e.mark.line + 1)) + ": " + e.msg);
  }
  return m;
}

// A listed file, found the ways rosbag2 versions have written the path: relative to the bag
// directory, as a bare name, or (Foxy) relative to the directory's parent.
std::optional<std::string> locate(const fs::path& dir, const std::string& rel) {
  for (const fs::path& p : {dir / rel, dir / fs::path(rel).filename(), dir.parent_path() / rel}) {
    std::error_code ec;
    if (fs::is_regular_file(p, ec)) return p.string();
  }
  return std::nullopt;
}

class Ros2BagReader final : public RecordingReader {
 public:
  Ros2BagReader(std::vector<Db3File> files, std::optional<std::vector<TopicInfo>> meta_topics, ReadStats stats)
      : files_(std::move(files)), meta_topics_(std::move(meta_topics)), stats_(std::move(stats)) {}

  std::vector<TopicInfo> topics() override {
    if (meta_topics_) return *meta_topics_;
    std::vector<TopicInfo> out;
    std::map<std::string, size_t> index;
    for (const Db3File& f : files_) {
      for (const auto& [id, t] : f.topics())
        if (index.try_emplace(t.name, out.size()).second) out.push_back({t.name, t.type, 0, 0, 0});
      Stmt s = f.prepare("SELECT topic_id, COUNT(*), MIN(timestamp), MAX(timestamp) FROM messages GROUP BY topic_id");
      int rc;
      while ((rc = sqlite3_step(s.get())) == SQLITE_ROW) {
        const auto t = f.topics().find(sqlite3_column_int64(s.get(), 0));
        if (t == f.topics().end()) continue;  // next() warns about these
        TopicInfo& info = out[index[t->second.name]];
        const auto n = static_cast<uint64_t>(sqlite3_column_int64(s.get(), 1));
        const int64_t lo = sqlite3_column_int64(s.get(), 2), hi = sqlite3_column_int64(s.get(), 3);
        info.first_ns = info.count ? std::min(info.first_ns, lo) : lo;
        info.last_ns = info.count ? std::max(info.last_ns, hi) : hi;
        info.count += n;
      }
      if (rc != SQLITE_DONE) stats_.warn(f.path() + ": counting messages: " + f.error());
    }
    meta_topics_ = out;
    return out;
  }

  bool next(RecordedMessage& out) override {
    while (file_ < files_.size()) {
      const Db3File& f = files_[file_];
      if (!select_) {
        select_ = f.prepare("SELECT topic_id, timestamp, data FROM messages ORDER BY timestamp, id");
        read_in_file_ = 0;
      }
      const int rc = sqlite3_step(select_.get());
      if (rc != SQLITE_ROW) {
        if (rc != SQLITE_DONE)
          stats_.warn(f.path() + ": database error after " + std::to_string(read_in_file_) +
                      " messages (" + f.error() + "); the rest of this file is skipped");
        select_.reset();
        ++file_;
        continue;
      }
      ++read_in_file_;
      sqlite3_stmt* s = select_.get();
      const int64_t id = sqlite3_column_int64(s, 0), ns = sqlite3_column_int64(s, 1);
      const std::string at = " at t=" + io_detail::formatSecondsNs(ns);
      const auto topic = f.topics().find(id);
      if (topic == f.topics().end()) {
        if (warned_.insert(f.path() + "#" + std::to_string(id)).second)
          stats_.warn(f.path() + ": message" + at + " has topic_id " + std::to_string(id) +
                      ", which is not in the topics table; such messages are skipped (warned once)");
        continue;
      }
      const BagTopic& t = topic->second;
      if (!t.supported()) {
        if (warned_.insert(t.name).second)
          stats_.warn(f.path() + ": topic " + t.name + ": type " + t.type + " (" + t.serialization_format +
                      ") is not supported; its messages are skipped (warned once)");
        continue;
      }
      const auto* data = static_cast<const uint8_t*>(sqlite3_column_blob(s, 2));
      const auto size = static_cast<size_t>(sqlite3_column_bytes(s, 2));
      try {
        out.message = msg::decodeCdr(t.type, std::span<const uint8_t>(data, data ? size : 0));
      } catch (const std::exception& e) {
        stats_.warn(f.path() + ": topic " + t.name + at + ": " + e.what());
        continue;
      }
      out.topic = t.name;
      out.log_time_ns = out.publish_time_ns = ns;  // rosbag2 sqlite keeps the receive time only
      ++stats_.messages;
      return true;
    }
    return false;
  }

  const ReadStats& stats() const override { return stats_; }
  std::string format() const override { return "ros2bag"; }

 private:
  std::vector<Db3File> files_;
  std::optional<std::vector<TopicInfo>> meta_topics_;
  ReadStats stats_;
  size_t file_ = 0;
  uint64_t read_in_file_ = 0;
  Stmt select_;  // declared after files_: finalised before its database is closed
  std::set<std::string> warned_;
};

bool hasSqliteMagic(const std::string& path) {
  char magic[16] = {};
  std::ifstream(path, std::ios::binary).read(magic, sizeof magic);
  return std::memcmp(magic, "SQLite format 3", 16) == 0;
}

// Split files sort by their index: bag_2.db3 before bag_10.db3.
bool byIndex(const std::string& a, const std::string& b) {
  return a.size() != b.size() ? a.size() < b.size() : a < b;
}

}  // namespace

std::unique_ptr<RecordingReader> openRos2Bag(const std::string& path) {
  std::error_code ec;
  const fs::path p(path);
  if (!fs::exists(p, ec)) throw IoError(path + ": does not exist");
  ReadStats stats;
  std::vector<std::string> paths;
  std::optional<std::vector<TopicInfo>> meta_topics;

  const bool is_dir = fs::is_directory(p, ec);
  const fs::path dir = is_dir ? p : p.parent_path().empty() ? fs::path(".") : p.parent_path();
  const fs::path meta_path = is_dir ? p / "metadata.yaml" : p;
  if (p.extension() == ".db3" || (!is_dir && hasSqliteMagic(path))) {
    paths.push_back(path);  // one file: its own tables are the truth
  } else if (fs::is_regular_file(meta_path, ec)) {
    const BagMetadata m = readMetadata(meta_path.string());
    if (m.storage == "mcap" && m.files.size() == 1)
      if (auto f = locate(dir, m.files[0])) return openMcap(*f);
    if (m.storage != "sqlite3")
      throw IoError(meta_path.string() + ": storage_identifier '" + m.storage + "' is not supported (sqlite3 is; " +
                    "a single-file mcap bag is opened as MCAP)");
    if (!m.compression.empty())
      throw IoError(meta_path.string() + ": compressed bags (" + m.compression + ") are not supported; " +
                    "decompress first, e.g. with `ros2 bag convert`");
    for (const std::string& rel : m.files) {
      if (auto f = locate(dir, rel))
        paths.push_back(*f);
      else
        stats.warn(meta_path.string() + ": lists " + rel + ", which does not exist; the rest of the bag is read");
    }
    // Counts from metadata.yaml, unless a file is missing: then they would overstate.
    if (m.has_topics && paths.size() == m.files.size()) meta_topics = m.topics;
  } else if (is_dir) {
    for (const auto& e : fs::directory_iterator(p, ec))
      if (e.path().extension() == ".db3") paths.push_back(e.path().string());
    std::sort(paths.begin(), paths.end(), byIndex);
  } else {
    throw IoError(path + ": not a ROS 2 bag (expected a bag directory, its metadata.yaml or a .db3 file)");
  }
  if (paths.empty()) throw IoError(path + ": the bag has no .db3 file to read");

  std::vector<Db3File> files;
  for (const std::string& f : paths) files.emplace_back(f);
  return std::make_unique<Ros2BagReader>(std::move(files), std::move(meta_topics), std::move(stats));
}

}  // namespace polyloc
