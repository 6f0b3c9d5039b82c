// ROS 2 bag writer: the layout rosbag2 on Humble writes (sqlite schema version 3 with the schema
// and metadata tables, metadata.yaml version 5), which Humble, Iron and Jazzy all read; newer
// layouts (schema 4, metadata 8/9) are not readable by Humble. Messages go in through one
// prepared INSERT inside transactions of a few thousand rows (sqlite commits are the cost).
#include <polyloc/io/cdr.hpp>
#include <polyloc/io/recording.hpp>

#include <sqlite3.h>
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <fstream>
#include <limits>
#include <map>

namespace polyloc {
namespace {

namespace fs = std::filesystem;

constexpr int kSchemaVersion = 3;    // rosbag2 sqlite schema, as Humble writes it
constexpr int kMetadataVersion = 5;  // metadata.yaml, as Humble writes it
constexpr uint64_t kRowsPerTransaction = 4096;

// /tf_static is latched: players must offer it transient_local, or tf2 listeners (which ask for
// transient_local) never get it. rosbag2's pre-Jazzy QoS encoding: reliability 1 = reliable,
// durability 1 = transient_local, history 3 = unknown (player default), durations "infinite".
constexpr const char* kLatchedQos =
    "- history: 3\n  depth: 0\n  reliability: 1\n  durability: 1\n"
    "  deadline:\n    sec: 2147483647\n    nsec: 4294967295\n"
    "  lifespan:\n    sec: 2147483647\n    nsec: 4294967295\n  liveliness: 1\n"
    "  liveliness_lease_duration:\n    sec: 2147483647\n    nsec: 4294967295\n"
    "  avoid_ros_namespace_conventions: false\n";

std::string qosFor(const std::string& topic) { return topic == "/tf_static" ? kLatchedQos : ""; }

struct DbClose {
  void operator()(sqlite3* db) const { sqlite3_close(db); }
};
struct StmtFinalize {
  void operator()(sqlite3_stmt* s) const { sqlite3_finalize(s); }
};

class Ros2BagWriter final : public RecordingWriter {
 public:
  explicit Ros2BagWriter(const std::string& directory) : dir_(directory) {
    std::error_code ec;
    if (fs::exists(dir_, ec) && !(fs::is_directory(dir_, ec) && fs::is_empty(dir_, ec)))
      throw IoError(directory + ": already exists and is not an empty directory; not overwriting");
    fs::create_directories(dir_, ec);
    if (ec) throw IoError(directory + ": cannot create directory: " + ec.message());
    std::string name = fs::path(directory).lexically_normal().filename().string();
    if (name.empty() || name == ".") name = fs::path(directory).lexically_normal().parent_path().filename().string();
    db_name_ = (name.empty() ? std::string("bag") : name) + "_0.db3";
    db_path_ = (fs::path(dir_) / db_name_).string();

    sqlite3* db = nullptr;
    const int rc = sqlite3_open_v2(db_path_.c_str(), &db, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, nullptr);
    db_.reset(db);
    if (rc != SQLITE_OK) fail("cannot create");
    // As rosbag2's default (write-optimised) profile: no journal file, no fsync per commit.
    exec("PRAGMA journal_mode=MEMORY; PRAGMA synchronous=OFF;"
         "CREATE TABLE schema(schema_version INTEGER PRIMARY KEY, ros_distro TEXT NOT NULL);"
         "CREATE TABLE metadata(id INTEGER PRIMARY KEY, metadata_version INTEGER NOT NULL, metadata TEXT NOT NULL);"
         "CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL,"
         " serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL);"
         "CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL,"
         " timestamp INTEGER NOT NULL, data BLOB NOT NULL);"
         "CREATE INDEX timestamp_idx ON messages (timestamp ASC);"
         "INSERT INTO schema (schema_version, ros_distro) VALUES (" + std::to_string(kSchemaVersion) + ", 'humble');");
    insert_message_ = prepare("INSERT INTO messages (timestamp, topic_id, data) VALUES (?, ?, ?)");
    insert_topic_ = prepare(
        "INSERT INTO topics (name, type, serialization_format, offered_qos_profiles) VALUES (?, ?, 'cdr', ?)");
  }

  ~Ros2BagWriter() override {
    try {
      close();
    } catch (...) {  // a destructor must not throw; call close() to see the error
    }
  }

  void write(const std::string& topic, int64_t log_time_ns, const msg::Message& m) override {
    if (closed_) throw IoError(db_path_ + ": write after close");
    const std::string type = msg::typeName(m);
    auto it = topics_.find(topic);
    if (it == topics_.end()) {
      const std::string qos = qosFor(topic);
      sqlite3_stmt* s = insert_topic_.get();
      sqlite3_bind_text(s, 1, topic.c_str(), -1, SQLITE_TRANSIENT);
      sqlite3_bind_text(s, 2, type.c_str(), -1, SQLITE_TRANSIENT);
      sqlite3_bind_text(s, 3, qos.c_str(), -1, SQLITE_TRANSIENT);
      step(s, "adding topic " + topic);
      it = topics_.emplace(topic, Topic{sqlite3_last_insert_rowid(db_.get()), type}).first;
      order_.push_back(topic);
    } else if (it->second.type != type) {
      throw IoError(db_path_ + ": topic " + topic + " has type " + it->second.type + ", not " + type);
    }
    const std::vector<uint8_t> data = msg::encodeCdr(m);
    if (rows_in_transaction_ == 0) exec("BEGIN TRANSACTION");
    sqlite3_stmt* s = insert_message_.get();
    sqlite3_bind_int64(s, 1, log_time_ns);
    sqlite3_bind_int64(s, 2, it->second.id);
    sqlite3_bind_blob64(s, 3, data.data(), data.size(), SQLITE_STATIC);
    step(s, "writing a message on " + topic);
    ++it->second.count;
    ++count_;
    first_ = std::min(first_, log_time_ns);
    last_ = std::max(last_, log_time_ns);
    if (++rows_in_transaction_ == kRowsPerTransaction) commit();
  }

  void close() override {
    if (closed_) return;
    closed_ = true;
    commit();
    Stmt meta = prepare("INSERT INTO metadata (metadata_version, metadata) VALUES (?, ?)");
    const std::string inner = metadataYaml(false);
    sqlite3_bind_int(meta.get(), 1, kMetadataVersion);
    sqlite3_bind_text(meta.get(), 2, inner.c_str(), -1, SQLITE_TRANSIENT);
    step(meta.get(), "writing the metadata table");
    meta.reset();
    insert_message_.reset();
    insert_topic_.reset();
    if (sqlite3_close(db_.release()) != SQLITE_OK) throw IoError(db_path_ + ": closing failed");

    const std::string yaml_path = (fs::path(dir_) / "metadata.yaml").string();
    std::ofstream out(yaml_path);
    out << metadataYaml(true) << "\n";
    if (!out) throw IoError(yaml_path + ": cannot write");
  }

 private:
  using Stmt = std::unique_ptr<sqlite3_stmt, StmtFinalize>;
  struct Topic {
    int64_t id = 0;
    std::string type;
    uint64_t count = 0;
  };

  [[noreturn]] void fail(const std::string& what) const {
    throw IoError(db_path_ + ": " + what + ": " + (db_ ? sqlite3_errmsg(db_.get()) : "out of memory"));
  }
  void exec(const std::string& sql) {
    char* err = nullptr;
    if (sqlite3_exec(db_.get(), sql.c_str(), nullptr, nullptr, &err) != SQLITE_OK) {
      const std::string what = err ? err : "sqlite error";
      sqlite3_free(err);
      throw IoError(db_path_ + ": " + what);
    }
  }
  Stmt prepare(const char* sql) {
    sqlite3_stmt* s = nullptr;
    if (sqlite3_prepare_v2(db_.get(), sql, -1, &s, nullptr) != SQLITE_OK) fail("preparing a statement");
    return Stmt(s);
  }
  void step(sqlite3_stmt* s, const std::string& what) {
    const int rc = sqlite3_step(s);
    sqlite3_reset(s);
    sqlite3_clear_bindings(s);
    if (rc != SQLITE_DONE) fail(what);
  }
  void commit() {
    if (rows_in_transaction_ == 0) return;
    rows_in_transaction_ = 0;
    exec("COMMIT");
  }

  // rosbag2_bagfile_information as Humble writes it; `wrapped` false gives the inner mapping,
  // which is what rosbag2 stores in the metadata table.
  std::string metadataYaml(bool wrapped) const {
    const int64_t start = count_ ? first_ : 0, duration = count_ ? last_ - first_ : 0;
    YAML::Emitter e;
    e << YAML::BeginMap;
    if (wrapped) e << YAML::Key << "rosbag2_bagfile_information" << YAML::Value << YAML::BeginMap;
    e << YAML::Key << "version" << YAML::Value << kMetadataVersion;
    e << YAML::Key << "storage_identifier" << YAML::Value << "sqlite3";
    e << YAML::Key << "duration" << YAML::Value << YAML::BeginMap << YAML::Key << "nanoseconds"
      << YAML::Value << duration << YAML::EndMap;
    e << YAML::Key << "starting_time" << YAML::Value << YAML::BeginMap << YAML::Key
      << "nanoseconds_since_epoch" << YAML::Value << start << YAML::EndMap;
    e << YAML::Key << "message_count" << YAML::Value << count_;
    e << YAML::Key << "topics_with_message_count" << YAML::Value << YAML::BeginSeq;
    for (const std::string& name : order_) {
      const Topic& t = topics_.at(name);
      e << YAML::BeginMap << YAML::Key << "topic_metadata" << YAML::Value << YAML::BeginMap;
      e << YAML::Key << "name" << YAML::Value << name;
      e << YAML::Key << "type" << YAML::Value << t.type;
      e << YAML::Key << "serialization_format" << YAML::Value << "cdr";
      e << YAML::Key << "offered_qos_profiles" << YAML::Value << YAML::DoubleQuoted << qosFor(name);
      e << YAML::EndMap << YAML::Key << "message_count" << YAML::Value << t.count << YAML::EndMap;
    }
    e << YAML::EndSeq;
    e << YAML::Key << "compression_format" << YAML::Value << YAML::DoubleQuoted << "";
    e << YAML::Key << "compression_mode" << YAML::Value << YAML::DoubleQuoted << "";
    e << YAML::Key << "relative_file_paths" << YAML::Value << YAML::BeginSeq << db_name_ << YAML::EndSeq;
    e << YAML::Key << "files" << YAML::Value << YAML::BeginSeq << YAML::BeginMap;
    e << YAML::Key << "path" << YAML::Value << db_name_;
    e << YAML::Key << "starting_time" << YAML::Value << YAML::BeginMap << YAML::Key
      << "nanoseconds_since_epoch" << YAML::Value << start << YAML::EndMap;
    e << YAML::Key << "duration" << YAML::Value << YAML::BeginMap << YAML::Key << "nanoseconds"
      << YAML::Value << duration << YAML::EndMap;
    e << YAML::Key << "message_count" << YAML::Value << count_;
    e << YAML::EndMap << YAML::EndSeq;
    if (wrapped) e << YAML::EndMap;
    e << YAML::EndMap;
    return e.c_str();
  }

  std::string dir_, db_name_, db_path_;
  std::unique_ptr<sqlite3, DbClose> db_;
  Stmt insert_message_, insert_topic_;  // after db_: finalised first
  std::map<std::string, Topic> topics_;
  std::vector<std::string> order_;
  uint64_t count_ = 0, rows_in_transaction_ = 0;
  int64_t first_ = std::numeric_limits<int64_t>::max(), last_ = std::numeric_limits<int64_t>::min();
  bool closed_ = false;
};

}  // namespace

std::unique_ptr<RecordingWriter> createRos2Bag(const std::string& directory) {
  return std::make_unique<Ros2BagWriter>(directory);
}

}  // namespace polyloc
