// MCAP records (https://mcap.dev/spec) as the writer and the reader share them: opcodes, the
// record structs polyloc uses, little-endian encoding, and a bounds-checked parser whose
// errors say which field ran past the end. Private to kernels/io.
#pragma once

#include <cstdint>
#include <map>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace polyloc::mcap {

inline constexpr uint8_t kMagic[8] = {0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'};
inline constexpr size_t kRecordPrefix = 9;               // opcode (1) + content length (8)
inline constexpr size_t kFooterRecord = kRecordPrefix + 20;
// Decompressed chunks larger than this are taken as a corrupt length, not allocated.
inline constexpr uint64_t kMaxChunkBytes = uint64_t{1} << 32;

enum Op : uint8_t {
  kHeader = 0x01,
  kFooter = 0x02,
  kSchema = 0x03,
  kChannel = 0x04,
  kMessage = 0x05,
  kChunk = 0x06,
  kMessageIndex = 0x07,
  kChunkIndex = 0x08,
  kAttachment = 0x09,
  kAttachmentIndex = 0x0A,
  kStatistics = 0x0B,
  kMetadata = 0x0C,
  kMetadataIndex = 0x0D,
  kSummaryOffset = 0x0E,
  kDataEnd = 0x0F,
};

// A record's content did not parse; the reader adds the file and offset.
struct FormatError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct Schema {
  uint16_t id = 0;
  std::string name, encoding;
  std::vector<uint8_t> data;
};
struct Channel {
  uint16_t id = 0, schema_id = 0;
  std::string topic, message_encoding;
  std::map<std::string, std::string> metadata;
};
struct MessageHeader {  // the Message record without its payload
  uint16_t channel_id = 0;
  uint32_t sequence = 0;
  uint64_t log_time = 0, publish_time = 0;
};
struct ChunkHeader {  // the Chunk record up to its compressed records
  uint64_t start_time = 0, end_time = 0, uncompressed_size = 0;
  uint32_t uncompressed_crc = 0;
  std::string compression;
  uint64_t records_size = 0;
};
struct ChunkIndex {
  uint64_t start_time = 0, end_time = 0, chunk_offset = 0, chunk_length = 0;
  std::map<uint16_t, uint64_t> message_index_offsets;
  uint64_t message_index_length = 0;
  std::string compression;
  uint64_t compressed_size = 0, uncompressed_size = 0;
};
struct Statistics {
  uint64_t message_count = 0;
  uint16_t schema_count = 0;
  uint32_t channel_count = 0, attachment_count = 0, metadata_count = 0, chunk_count = 0;
  uint64_t start_time = 0, end_time = 0;
  std::map<uint16_t, uint64_t> channel_message_counts;
};
struct Footer {
  uint64_t summary_start = 0, summary_offset_start = 0;
  uint32_t summary_crc = 0;
};

// ---- encoding: appends to a byte vector -------------------------------------------------

class Out {
 public:
  explicit Out(std::vector<uint8_t>& b) : b_(b) {}
  Out& u8(uint8_t v) { return le(v, 1); }
  Out& u16(uint16_t v) { return le(v, 2); }
  Out& u32(uint32_t v) { return le(v, 4); }
  Out& u64(uint64_t v) { return le(v, 8); }
  Out& raw(const void* p, size_t n) {
    auto* c = static_cast<const uint8_t*>(p);
    b_.insert(b_.end(), c, c + n);
    return *this;
  }
  Out& str(const std::string& s) { return u32(static_cast<uint32_t>(s.size())).raw(s.data(), s.size()); }
  // Opens a record; close() fills in its length.
  size_t open(uint8_t op) {
    u8(op).u64(0);
    return b_.size();
  }
  void close(size_t content_start) {
    uint64_t n = b_.size() - content_start;
    for (int i = 0; i < 8; ++i) b_[content_start - 8 + i] = static_cast<uint8_t>(n >> (8 * i));
  }

 private:
  Out& le(uint64_t v, int n) {
    for (int i = 0; i < n; ++i) b_.push_back(static_cast<uint8_t>(v >> (8 * i)));
    return *this;
  }
  std::vector<uint8_t>& b_;
};

void putSchema(Out& o, const Schema& s);
void putChannel(Out& o, const Channel& c);
void putChunkIndex(Out& o, const ChunkIndex& c);
void putStatistics(Out& o, const Statistics& s);

// ---- parsing: a bounded view of one record's content ------------------------------------

inline uint64_t loadLe(const uint8_t* p, int n) {
  uint64_t v = 0;
  for (int i = 0; i < n; ++i) v |= uint64_t{p[i]} << (8 * i);
  return v;
}

class In {
 public:
  In(std::span<const uint8_t> b, const char* record) : b_(b), record_(record) {}
  uint8_t u8(const char* f) { return static_cast<uint8_t>(le(f, 1)); }
  uint16_t u16(const char* f) { return static_cast<uint16_t>(le(f, 2)); }
  uint32_t u32(const char* f) { return static_cast<uint32_t>(le(f, 4)); }
  uint64_t u64(const char* f) { return le(f, 8); }
  std::span<const uint8_t> bytes(const char* f, uint64_t n) {
    need(f, n);
    auto s = b_.subspan(pos_, n);
    pos_ += n;
    return s;
  }
  std::string str(const char* f) {
    auto s = bytes(f, u32(f));
    return {s.begin(), s.end()};
  }
  std::span<const uint8_t> rest() { return bytes("data", left()); }
  size_t left() const { return b_.size() - pos_; }
  size_t pos() const { return pos_; }

 private:
  void need(const char* f, uint64_t n) {
    if (n > left())
      throw FormatError(std::string(record_) + " record: field " + f + " needs " +
                        std::to_string(n) + " bytes, only " + std::to_string(left()) + " left");
  }
  uint64_t le(const char* f, int n) {
    need(f, n);
    uint64_t v = loadLe(b_.data() + pos_, n);
    pos_ += n;
    return v;
  }
  std::span<const uint8_t> b_;
  size_t pos_ = 0;
  const char* record_;
};

Schema parseSchema(std::span<const uint8_t> content);
Channel parseChannel(std::span<const uint8_t> content);
// Returns the header; `payload` is set to the message data inside `content`.
MessageHeader parseMessage(std::span<const uint8_t> content, std::span<const uint8_t>& payload);
// Parses only the fixed part; `content` may be just the first bytes of the record.
ChunkHeader parseChunkHeader(std::span<const uint8_t> content);
ChunkIndex parseChunkIndex(std::span<const uint8_t> content);
Statistics parseStatistics(std::span<const uint8_t> content);
Footer parseFooter(std::span<const uint8_t> content);
// (log_time, offset) pairs of a MessageIndex record.
std::vector<std::pair<uint64_t, uint64_t>> parseMessageIndex(std::span<const uint8_t> content);

// ---- chunk compression (mcap_compression.cpp) -------------------------------------------

// Compresses chunk records; "" stores them as they are. Throws FormatError for other names.
std::vector<uint8_t> compress(const std::string& compression, std::span<const uint8_t> in);
// Decompresses to exactly `size` bytes; throws FormatError when the data is corrupt, declares or
// has another size (checked before anything is allocated), or the compression is unknown.
std::vector<uint8_t> decompress(const std::string& compression, std::span<const uint8_t> in,
                                uint64_t size);
// CRC-32 (zlib's, as the MCAP spec asks), continued from `crc`.
uint32_t crc32(uint32_t crc, std::span<const uint8_t> bytes);

}  // namespace polyloc::mcap
