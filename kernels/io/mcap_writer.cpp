// MCAP writer for ROS 2 messages: the layout rosbag2's MCAP storage plugin produces, so a run
// opens in `ros2 bag`, Foxglove and the mcap CLI as it is.
//   magic, Header("ros2", "polyloc"),
//   per new type/topic: Schema ("ros2msg") and Channel ("cdr") records, before first use,
//   per chunk: Chunk (compressed Message records, CRC of the uncompressed bytes) + MessageIndex,
//   DataEnd (CRC of everything before it),
//   summary: Schemas, Channels, Statistics, ChunkIndexes; SummaryOffsets; Footer; magic.
// Nothing in the output depends on the clock or on addresses: the same calls give the same bytes.
#include "mcap_records.hpp"

#include <polyloc/io/atomic_file.hpp>
#include <polyloc/io/cdr.hpp>
#include <polyloc/io/recording.hpp>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <exception>
#include <limits>

namespace polyloc {
namespace {

class McapWriter final : public RecordingWriter {
 public:
  McapWriter(const std::string& path, const McapWriteOptions& o) : path_(path), opt_(o), out_(path) {
    if (!o.compression.empty() && o.compression != "zstd" && o.compression != "lz4")
      throw IoError(path + ": unknown MCAP chunk compression \"" + o.compression +
                    "\" (use zstd, lz4 or none)");
    file_ = std::fopen(out_.tmp().c_str(), "wb");
    if (!file_) throw IoError(path + ": cannot create: " + std::strerror(errno));
    std::setvbuf(file_, nullptr, _IOFBF, 1 << 20);
    std::vector<uint8_t> b(std::begin(mcap::kMagic), std::end(mcap::kMagic));
    mcap::Out o2(b);
    size_t at = o2.open(mcap::kHeader);
    o2.str(o.profile).str("polyloc");
    o2.close(at);
    emit(b);
  }
  ~McapWriter() override {
    if (file_ && std::uncaught_exceptions() > unwinding_) {  // failed midway: the old file stays
      std::fclose(file_);
      out_.discard();
      return;
    }
    try {
      close();
    } catch (...) {  // a destructor must not throw; close() explicitly to see the error
    }
  }

  void write(const std::string& topic, int64_t log_time_ns, const msg::Message& m) override {
    if (!file_) throw IoError(path_ + ": write on topic " + topic + " after close()");
    if (log_time_ns < 0)
      throw IoError(path_ + ": topic " + topic + ": negative log time " + std::to_string(log_time_ns));
    uint16_t ch = channelFor(topic, msg::typeName(m));
    std::vector<uint8_t> payload = msg::encodeCdr(m);
    auto t = static_cast<uint64_t>(log_time_ns);

    uint64_t offset = chunk_.size();
    mcap::Out o(chunk_);
    size_t at = o.open(mcap::kMessage);
    // publish time = log time: the simulator has one clock, as a recorder on the robot would.
    o.u16(ch).u32(sequences_[ch - 1]++).u64(t).u64(t).raw(payload.data(), payload.size());
    o.close(at);
    index_[ch].emplace_back(t, offset);
    chunk_start_ = std::min(chunk_start_, t);
    chunk_end_ = std::max(chunk_end_, t);

    ++stats_.message_count;
    ++stats_.channel_message_counts[ch];
    if (stats_.message_count == 1) stats_.start_time = t;
    stats_.start_time = std::min(stats_.start_time, t);
    stats_.end_time = std::max(stats_.end_time, t);
    if (chunk_.size() >= opt_.chunk_size) flushChunk();
  }

  void close() override {
    if (!file_) return;
    flushChunk();
    std::vector<uint8_t> b;
    mcap::Out o(b);
    size_t at = o.open(mcap::kDataEnd);
    o.u32(crc_);  // crc_ covers everything up to here: the data section
    o.close(at);
    emit(b);
    writeSummary();
    bool ok = std::fflush(file_) == 0;
    ok = std::fclose(file_) == 0 && ok;
    file_ = nullptr;
    if (!ok) {
      out_.discard();
      throw IoError(path_ + ": write failed: " + std::strerror(errno));
    }
    out_.commit();
  }

 private:
  void emit(std::span<const uint8_t> b) {
    if (std::fwrite(b.data(), 1, b.size(), file_) != b.size()) {
      int e = errno;
      std::fclose(file_);
      file_ = nullptr;
      out_.discard();
      throw IoError(path_ + ": write failed at byte " + std::to_string(pos_) + ": " + std::strerror(e));
    }
    crc_ = mcap::crc32(crc_, b);
    pos_ += b.size();
  }

  // The channel of a topic, writing its Schema and Channel records the first time.
  uint16_t channelFor(const std::string& topic, const std::string& type) {
    if (auto it = channel_ids_.find(topic); it != channel_ids_.end()) {
      const mcap::Channel& c = channels_[it->second - 1];
      const std::string& have = schemas_[c.schema_id - 1].name;
      if (have != type)
        throw IoError(path_ + ": topic " + topic + " has type " + have + ", cannot write a " + type);
      return c.id;
    }
    if (channels_.size() >= std::numeric_limits<uint16_t>::max())
      throw IoError(path_ + ": too many topics for MCAP (65535)");
    std::vector<uint8_t> b;
    mcap::Out o(b);
    auto [sit, new_schema] = schema_ids_.try_emplace(type, static_cast<uint16_t>(schemas_.size() + 1));
    if (new_schema) {
      const std::string& text = msg::ros2msgSchema(type);
      schemas_.push_back({sit->second, type, "ros2msg", {text.begin(), text.end()}});
      mcap::putSchema(o, schemas_.back());
    }
    auto id = static_cast<uint16_t>(channels_.size() + 1);
    channels_.push_back({id, sit->second, topic, "cdr", {}});
    mcap::putChannel(o, channels_.back());
    channel_ids_[topic] = id;
    sequences_.push_back(0);
    emit(b);
    return id;
  }

  void flushChunk() {
    if (chunk_.empty()) return;
    std::vector<uint8_t> compressed;
    try {
      compressed = mcap::compress(opt_.compression, chunk_);
    } catch (const mcap::FormatError& e) {
      throw IoError(path_ + ": " + e.what());
    }
    mcap::ChunkIndex ci;
    ci.start_time = chunk_start_;
    ci.end_time = chunk_end_;
    ci.chunk_offset = pos_;
    ci.compression = opt_.compression;
    ci.compressed_size = compressed.size();
    ci.uncompressed_size = chunk_.size();

    std::vector<uint8_t> b;
    mcap::Out o(b);
    size_t at = o.open(mcap::kChunk);
    o.u64(chunk_start_).u64(chunk_end_).u64(chunk_.size()).u32(mcap::crc32(0, chunk_));
    o.str(opt_.compression).u64(compressed.size());
    o.close(at);
    // The length field must cover the records too, which are emitted straight from their buffer.
    uint64_t len = b.size() - mcap::kRecordPrefix + compressed.size();
    for (int i = 0; i < 8; ++i) b[1 + i] = static_cast<uint8_t>(len >> (8 * i));
    emit(b);
    emit(compressed);
    ci.chunk_length = pos_ - ci.chunk_offset;

    uint64_t index_start = pos_;
    for (auto& [ch, entries] : index_) {  // std::map: channel order, deterministic
      // Readers that binary-search a message index (mcap's C++ reader) need it in time order.
      std::sort(entries.begin(), entries.end());
      b.clear();
      size_t at2 = o.open(mcap::kMessageIndex);
      o.u16(ch).u32(static_cast<uint32_t>(entries.size() * 16));
      for (const auto& [t, off] : entries) o.u64(t).u64(off);
      o.close(at2);
      ci.message_index_offsets[ch] = pos_;
      emit(b);
    }
    ci.message_index_length = pos_ - index_start;
    chunk_indexes_.push_back(std::move(ci));
    ++stats_.chunk_count;

    chunk_.clear();
    index_.clear();
    chunk_start_ = std::numeric_limits<uint64_t>::max();
    chunk_end_ = 0;
  }

  void writeSummary() {
    uint64_t summary_start = pos_;
    std::vector<uint8_t> summary, offsets;
    mcap::Out s(summary), so(offsets);
    auto group = [&](uint8_t op, size_t begin) {
      if (summary.size() == begin) return;
      size_t at = so.open(mcap::kSummaryOffset);
      so.u8(op).u64(summary_start + begin).u64(summary.size() - begin);
      so.close(at);
    };
    size_t begin = summary.size();
    for (const auto& x : schemas_) mcap::putSchema(s, x);
    group(mcap::kSchema, begin);
    begin = summary.size();
    for (const auto& x : channels_) mcap::putChannel(s, x);
    group(mcap::kChannel, begin);
    begin = summary.size();
    stats_.schema_count = static_cast<uint16_t>(schemas_.size());
    stats_.channel_count = static_cast<uint32_t>(channels_.size());
    mcap::putStatistics(s, stats_);
    group(mcap::kStatistics, begin);
    begin = summary.size();
    for (const auto& x : chunk_indexes_) mcap::putChunkIndex(s, x);
    group(mcap::kChunkIndex, begin);

    uint64_t offsets_start = summary_start + summary.size();
    std::vector<uint8_t> footer;
    mcap::Out f(footer);
    f.u8(mcap::kFooter).u64(20).u64(summary_start).u64(offsets_start);
    // The summary CRC runs from the summary's start through summary_offset_start.
    uint32_t crc = mcap::crc32(mcap::crc32(mcap::crc32(0, summary), offsets), footer);
    f.u32(crc);
    f.raw(mcap::kMagic, sizeof mcap::kMagic);
    emit(summary);
    emit(offsets);
    emit(footer);
  }

  std::string path_;
  McapWriteOptions opt_;
  AtomicFile out_;  // written as a temporary, renamed by close()
  int unwinding_ = std::uncaught_exceptions();
  std::FILE* file_ = nullptr;
  uint64_t pos_ = 0;   // bytes written so far
  uint32_t crc_ = 0;   // CRC of those bytes (only the data section's value is used)

  std::vector<mcap::Schema> schemas_;  // id = index + 1
  std::map<std::string, uint16_t> schema_ids_;
  std::vector<mcap::Channel> channels_;  // id = index + 1
  std::map<std::string, uint16_t> channel_ids_;
  std::vector<uint32_t> sequences_;

  std::vector<uint8_t> chunk_;  // uncompressed Message records of the open chunk
  std::map<uint16_t, std::vector<std::pair<uint64_t, uint64_t>>> index_;  // (log time, offset)
  uint64_t chunk_start_ = std::numeric_limits<uint64_t>::max(), chunk_end_ = 0;
  std::vector<mcap::ChunkIndex> chunk_indexes_;
  mcap::Statistics stats_;
};

}  // namespace

std::unique_ptr<RecordingWriter> createMcap(const std::string& path, const McapWriteOptions& o) {
  return std::make_unique<McapWriter>(path, o);
}

}  // namespace polyloc
