// The raw message stream of an MCAP file, in log-time order, without decoding payloads: the
// part of the reader that knows the file layout. It holds at most the chunks whose time ranges
// overlap (one at a time for files whose chunks are in order), never the whole file.
// Private to kernels/io.
#pragma once

#include "mcap_records.hpp"

#include <polyloc/io/recording.hpp>

#include <memory>
#include <optional>

namespace polyloc::mcap {

// A file read with pread: no shared position, so a second pass can run beside the first.
class File {
 public:
  explicit File(const std::string& path);
  ~File();
  File(const File&) = delete;
  File& operator=(const File&) = delete;
  uint64_t size() const { return size_; }
  const std::string& path() const { return path_; }
  // Reads [offset, offset + n); false if the file ends before.
  bool read(uint64_t offset, uint64_t n, std::vector<uint8_t>& out) const;

 private:
  std::string path_;
  int fd_ = -1;
  uint64_t size_ = 0;
};

struct RawMessage {
  uint16_t channel_id = 0;
  uint64_t log_time = 0, publish_time = 0;
  std::span<const uint8_t> payload;  // valid until the next call to next()
};

class MessageSource {
 public:
  // Throws IoError when the file is not MCAP at all (bad magic, no Header). With use_summary
  // false the file is read front to back even when it has a summary.
  MessageSource(const std::string& path, bool use_summary, ReadStats& stats);
  ~MessageSource();
  bool next(RawMessage& m);

  const std::map<uint16_t, Schema>& schemas() const { return schemas_; }
  const std::map<uint16_t, Channel>& channels() const { return channels_; }
  // Set when the file's summary was read and checked.
  const std::optional<Statistics>& statistics() const { return statistics_; }
  bool indexed() const { return indexed_; }
  // First and last log time of a channel, from the chunk and message indexes (indexed only).
  std::optional<std::pair<uint64_t, uint64_t>> channelSpan(uint16_t channel_id);
  const std::string& path() const { return file_.path(); }

 private:
  struct Chunk;  // a decompressed chunk and its messages in log-time order
  void readHeader();
  bool readSummary();
  void registerRecord(uint8_t op, std::span<const uint8_t> content, uint64_t offset);
  std::unique_ptr<Chunk> loadChunk(std::span<const uint8_t> content, uint64_t offset);
  std::unique_ptr<Chunk> loadIndexedChunk(const ChunkIndex& ci);
  bool nextIndexed(RawMessage& m);
  bool nextStreaming(RawMessage& m);
  void warn(uint64_t offset, const std::string& what);

  File file_;
  ReadStats& stats_;
  std::map<uint16_t, Schema> schemas_;
  std::map<uint16_t, Channel> channels_;
  std::optional<Statistics> statistics_;
  std::vector<ChunkIndex> chunk_indexes_;  // by start time, then file offset
  uint64_t data_end_ = 0;                  // where the summary starts (indexed mode)
  bool indexed_ = false;
  bool footer_seen_ = false;              // a Footer record is where the spec puts it

  size_t next_chunk_ = 0;                      // indexed: next chunk index to load
  std::vector<std::unique_ptr<Chunk>> open_;   // loaded chunks with messages left
  uint64_t pos_ = 0;                           // streaming: offset of the next record
  bool done_ = false;
  std::vector<uint8_t> record_;                // streaming: the current un-chunked record
};

}  // namespace polyloc::mcap
