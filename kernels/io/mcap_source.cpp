// Reading MCAP records front to back (streaming) or through the summary's chunk index
// (indexed, which also merges overlapping chunks by log time). Every length read from the file
// is checked against the bytes that are really there before it is used or allocated.
#include "mcap_source.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <limits>

namespace polyloc::mcap {
namespace {

// Records larger than this are taken as a corrupt length: real chunks are megabytes.
constexpr uint64_t kMaxRecordBytes = uint64_t{1} << 30;
constexpr uint64_t kMaxSummaryBytes = uint64_t{256} << 20;

std::string hex(uint32_t v) {
  char b[16];
  std::snprintf(b, sizeof b, "0x%08x", v);
  return b;
}

}  // namespace

// ---- File ----------------------------------------------------------------------------

File::File(const std::string& path) : path_(path) {
  fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd_ < 0) throw IoError(path + ": cannot open: " + std::strerror(errno));
  struct stat st {};
  if (::fstat(fd_, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd_);
    throw IoError(path + ": not a regular file");
  }
  size_ = static_cast<uint64_t>(st.st_size);
}

File::~File() {
  if (fd_ >= 0) ::close(fd_);
}

bool File::read(uint64_t offset, uint64_t n, std::vector<uint8_t>& out) const {
  if (offset > size_ || n > size_ - offset) return false;
  out.resize(n);
  uint64_t done = 0;
  while (done < n) {
    ssize_t r = ::pread(fd_, out.data() + done, n - done, static_cast<off_t>(offset + done));
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) throw IoError(path_ + ": read failed at byte " + std::to_string(offset + done));
    done += static_cast<uint64_t>(r);
  }
  return true;
}

// ---- MessageSource ---------------------------------------------------------------------

struct MessageSource::Chunk {
  struct Entry {
    uint64_t log_time, offset, length;  // offset/length of the Message record's content
  };
  std::vector<uint8_t> data;
  std::vector<Entry> entries;  // by log time, then position
  size_t cursor = 0;
  uint64_t file_offset = 0;  // breaks ties between chunks
  bool empty() const { return cursor >= entries.size(); }
};

MessageSource::MessageSource(const std::string& path, bool use_summary, ReadStats& stats)
    : file_(path), stats_(stats) {
  readHeader();
  if (!use_summary) footer_seen_ = true;  // not looked for, not missed
  else if (readSummary())
    indexed_ = !chunk_indexes_.empty() || (statistics_ && statistics_->message_count == 0);
}

MessageSource::~MessageSource() = default;

void MessageSource::warn(uint64_t offset, const std::string& what) {
  stats_.warn(path() + ": byte " + std::to_string(offset) + ": " + what);
}

void MessageSource::readHeader() {
  std::vector<uint8_t> b;
  if (!file_.read(0, sizeof kMagic, b) || !std::equal(b.begin(), b.end(), kMagic))
    throw IoError(path() + ": byte 0: not an MCAP file (no MCAP magic)");
  if (!file_.read(sizeof kMagic, kRecordPrefix, b))
    throw IoError(path() + ": byte 8: truncated, the file ends before the Header record");
  uint64_t len = loadLe(b.data() + 1, 8);
  if (b[0] != kHeader)
    throw IoError(path() + ": byte 8: expected the Header record (opcode 0x01), found opcode " +
                  std::to_string(b[0]));
  if (len > file_.size() - sizeof kMagic - kRecordPrefix)
    throw IoError(path() + ": byte 8: truncated Header record (" + std::to_string(len) + " bytes)");
  pos_ = sizeof kMagic + kRecordPrefix + len;
}

bool MessageSource::readSummary() {
  const uint64_t size = file_.size();
  if (size < 2 * sizeof kMagic + kRecordPrefix + kFooterRecord) return false;
  const uint64_t footer_at = size - sizeof kMagic - kFooterRecord;
  std::vector<uint8_t> b;
  file_.read(footer_at, kFooterRecord + sizeof kMagic, b);
  if (!std::equal(kMagic, kMagic + 8, b.begin() + kFooterRecord) || b[0] != kFooter ||
      loadLe(b.data() + 1, 8) != 20)
    return false;  // no footer: the streaming pass reports the truncation
  footer_seen_ = true;
  Footer f = parseFooter(std::span(b).subspan(kRecordPrefix, 20));
  if (f.summary_start == 0) return false;
  uint64_t end = f.summary_offset_start ? f.summary_offset_start : footer_at;
  if (f.summary_start < pos_ || f.summary_start > end || end > footer_at ||
      footer_at - f.summary_start > kMaxSummaryBytes) {
    warn(footer_at, "footer points the summary outside the file; reading it front to back");
    return false;
  }
  file_.read(f.summary_start, footer_at + kRecordPrefix + 16 - f.summary_start, b);
  if (f.summary_crc != 0 && crc32(0, b) != f.summary_crc) {
    warn(f.summary_start, "summary CRC mismatch (stored " + hex(f.summary_crc) + ", computed " +
                              hex(crc32(0, b)) + "); reading the file front to back");
    return false;
  }
  std::map<uint16_t, Schema> schemas;
  std::map<uint16_t, Channel> channels;
  std::optional<Statistics> statistics;
  std::vector<ChunkIndex> chunks;
  uint64_t at = 0;
  const uint64_t n = end - f.summary_start;
  try {
    while (at < n) {
      if (n - at < kRecordPrefix || loadLe(&b[at + 1], 8) > n - at - kRecordPrefix)
        throw FormatError("summary record runs past the summary section");
      uint8_t op = b[at];
      auto content = std::span(b).subspan(at + kRecordPrefix, loadLe(&b[at + 1], 8));
      if (op == kSchema) {
        Schema s = parseSchema(content);
        schemas[s.id] = std::move(s);
      } else if (op == kChannel) {
        Channel c = parseChannel(content);
        channels[c.id] = std::move(c);
      } else if (op == kStatistics) {
        statistics = parseStatistics(content);
      } else if (op == kChunkIndex) {
        chunks.push_back(parseChunkIndex(content));
      }
      at += kRecordPrefix + content.size();
    }
  } catch (const FormatError& e) {
    warn(f.summary_start + at, std::string(e.what()) + "; reading the file front to back");
    return false;
  }
  std::sort(chunks.begin(), chunks.end(), [](const ChunkIndex& a, const ChunkIndex& c) {
    return std::tie(a.start_time, a.chunk_offset) < std::tie(c.start_time, c.chunk_offset);
  });
  schemas_ = std::move(schemas);
  channels_ = std::move(channels);
  statistics_ = std::move(statistics);
  chunk_indexes_ = std::move(chunks);
  data_end_ = f.summary_start;
  return true;
}

void MessageSource::registerRecord(uint8_t op, std::span<const uint8_t> content, uint64_t offset) {
  try {
    if (op == kSchema) {
      Schema s = parseSchema(content);
      if (s.id != 0) schemas_[s.id] = std::move(s);
    } else if (op == kChannel) {
      Channel c = parseChannel(content);
      channels_[c.id] = std::move(c);
    }
  } catch (const FormatError& e) {
    warn(offset, e.what());
  }
}

std::unique_ptr<MessageSource::Chunk> MessageSource::loadChunk(std::span<const uint8_t> content,
                                                               uint64_t offset) {
  auto chunk = std::make_unique<Chunk>();
  chunk->file_offset = offset;
  try {
    ChunkHeader h = parseChunkHeader(content);
    const size_t header_bytes = 8 * 3 + 4 + 4 + h.compression.size() + 8;
    if (h.records_size > content.size() - header_bytes)
      throw FormatError("Chunk record: records claim " + std::to_string(h.records_size) +
                        " bytes, only " + std::to_string(content.size() - header_bytes) + " left");
    chunk->data = decompress(h.compression, content.subspan(header_bytes, h.records_size),
                             h.uncompressed_size);
    if (h.uncompressed_crc != 0 && crc32(0, chunk->data) != h.uncompressed_crc)
      throw FormatError("CRC mismatch (stored " + hex(h.uncompressed_crc) + ", computed " +
                        hex(crc32(0, chunk->data)) + ")");
  } catch (const FormatError& e) {
    warn(offset, std::string("chunk skipped: ") + e.what());
    return nullptr;
  }
  const std::vector<uint8_t>& d = chunk->data;
  uint64_t at = 0;
  while (at < d.size()) {
    uint64_t len = d.size() - at >= kRecordPrefix ? loadLe(&d[at + 1], 8) : 0;
    if (d.size() - at < kRecordPrefix || len > d.size() - at - kRecordPrefix) {
      warn(offset, "record at byte " + std::to_string(at) +
                       " of the chunk runs past its end; rest of the chunk skipped");
      break;
    }
    uint8_t op = d[at];
    auto content = std::span(d).subspan(at + kRecordPrefix, len);
    if (op == kMessage) {
      if (len < 22)
        warn(offset, "Message record at byte " + std::to_string(at) + " of the chunk is too short");
      else
        chunk->entries.push_back({loadLe(content.data() + 6, 8), at + kRecordPrefix, len});
    } else {
      registerRecord(op, content, offset);
    }
    at += kRecordPrefix + len;
  }
  std::sort(chunk->entries.begin(), chunk->entries.end(), [](const auto& a, const auto& b) {
    return std::tie(a.log_time, a.offset) < std::tie(b.log_time, b.offset);
  });
  return chunk;
}

std::unique_ptr<MessageSource::Chunk> MessageSource::loadIndexedChunk(const ChunkIndex& ci) {
  if (ci.chunk_offset < pos_ || ci.chunk_length < kRecordPrefix ||
      ci.chunk_length > kMaxRecordBytes || ci.chunk_offset > data_end_ ||
      ci.chunk_length > data_end_ - ci.chunk_offset) {
    warn(ci.chunk_offset, "chunk index entry points outside the data section; chunk skipped");
    return nullptr;
  }
  std::vector<uint8_t> b;
  file_.read(ci.chunk_offset, ci.chunk_length, b);
  if (b[0] != kChunk || loadLe(b.data() + 1, 8) != ci.chunk_length - kRecordPrefix) {
    warn(ci.chunk_offset, "no Chunk record of the indexed length here; chunk skipped");
    return nullptr;
  }
  return loadChunk(std::span(b).subspan(kRecordPrefix), ci.chunk_offset);
}

static void fill(RawMessage& m, std::span<const uint8_t> content) {
  MessageHeader h = parseMessage(content, m.payload);
  m.channel_id = h.channel_id;
  m.log_time = h.log_time;
  m.publish_time = h.publish_time;
}

bool MessageSource::next(RawMessage& m) {
  std::erase_if(open_, [](const auto& c) { return c->empty(); });
  return indexed_ ? nextIndexed(m) : nextStreaming(m);
}

bool MessageSource::nextIndexed(RawMessage& m) {
  // Load every chunk that may hold a message before the earliest one in the loaded chunks:
  // one chunk at a time when chunks do not overlap.
  while (next_chunk_ < chunk_indexes_.size()) {
    uint64_t earliest = std::numeric_limits<uint64_t>::max();
    for (const auto& c : open_) earliest = std::min(earliest, c->entries[c->cursor].log_time);
    if (!open_.empty() && chunk_indexes_[next_chunk_].start_time > earliest) break;
    auto c = loadIndexedChunk(chunk_indexes_[next_chunk_++]);
    if (c && !c->empty()) open_.push_back(std::move(c));
  }
  if (open_.empty()) return false;
  Chunk* best = nullptr;
  for (const auto& c : open_) {
    const auto& e = c->entries[c->cursor];
    if (!best || std::tie(e.log_time, c->file_offset) <
                     std::tie(best->entries[best->cursor].log_time, best->file_offset))
      best = c.get();
  }
  const auto& e = best->entries[best->cursor++];
  fill(m, std::span(best->data).subspan(e.offset, e.length));
  return true;
}

bool MessageSource::nextStreaming(RawMessage& m) {
  std::vector<uint8_t> prefix;
  while (true) {
    if (!open_.empty()) {
      Chunk& c = *open_.front();
      const auto& e = c.entries[c.cursor++];
      fill(m, std::span(c.data).subspan(e.offset, e.length));
      return true;
    }
    if (done_) return false;
    const uint64_t size = file_.size();
    if (!file_.read(pos_, kRecordPrefix, prefix)) {
      warn(pos_, "truncated: the file ends without DataEnd and Footer records; "
                 "read all complete records before it");
      done_ = true;
      continue;
    }
    uint8_t op = prefix[0];
    uint64_t len = loadLe(prefix.data() + 1, 8);
    uint64_t at = pos_;
    if (len > size - pos_ - kRecordPrefix) {
      warn(at, "truncated: record (opcode " + std::to_string(op) + ") claims " +
                   std::to_string(len) + " bytes, the file has " +
                   std::to_string(size - pos_ - kRecordPrefix) + " left; reading stops here");
      done_ = true;
      continue;
    }
    pos_ += kRecordPrefix + len;
    if (op == kDataEnd || op == kFooter) {
      if (!footer_seen_)
        warn(at, "the file ends without a valid Footer (truncated after the data section?); "
                 "all messages were read");
      done_ = true;
    } else if (op == kMessage || op == kSchema || op == kChannel || op == kChunk) {
      if (len > kMaxRecordBytes) {
        warn(at, "record of " + std::to_string(len) + " bytes skipped as corrupt");
        continue;
      }
      file_.read(at + kRecordPrefix, len, record_);
      if (op == kChunk) {
        auto c = loadChunk(record_, at);
        record_ = {};  // the compressed bytes are not needed any more
        if (c && !c->empty()) open_.push_back(std::move(c));
      } else if (op != kMessage) {
        registerRecord(op, record_, at);
      } else if (len < 22) {
        warn(at, "Message record too short (" + std::to_string(len) + " bytes)");
      } else {
        fill(m, record_);
        return true;
      }
    }
  }
}

std::optional<std::pair<uint64_t, uint64_t>> MessageSource::channelSpan(uint16_t channel_id) {
  auto times = [&](const ChunkIndex& ci) -> std::vector<std::pair<uint64_t, uint64_t>> {
    auto it = ci.message_index_offsets.find(channel_id);
    std::vector<uint8_t> b;
    if (it == ci.message_index_offsets.end() || !file_.read(it->second, kRecordPrefix, b) ||
        b[0] != kMessageIndex || loadLe(b.data() + 1, 8) > ci.message_index_length ||
        !file_.read(it->second + kRecordPrefix, loadLe(b.data() + 1, 8), b))
      return {};
    try {
      return parseMessageIndex(b);
    } catch (const FormatError&) {
      return {};
    }
  };
  // The first time is in the earliest-starting chunks that hold the channel, the last in the
  // latest-ending ones: stop as soon as no further chunk can improve on what was found.
  std::vector<const ChunkIndex*> by_end;
  for (const auto& ci : chunk_indexes_)
    if (ci.message_index_offsets.count(channel_id)) by_end.push_back(&ci);
  if (by_end.empty()) return std::nullopt;
  uint64_t first = std::numeric_limits<uint64_t>::max(), last = 0;
  bool found_first = false, found_last = false;
  for (const ChunkIndex* ci : by_end) {  // by_end is still in start-time order here
    if (found_first && ci->start_time > first) break;
    for (const auto& [t, off] : times(*ci)) first = std::min(first, t), found_first = true;
  }
  std::sort(by_end.begin(), by_end.end(),
            [](const ChunkIndex* a, const ChunkIndex* b) { return a->end_time > b->end_time; });
  for (const ChunkIndex* ci : by_end) {
    if (found_last && ci->end_time < last) break;
    for (const auto& [t, off] : times(*ci)) last = std::max(last, t), found_last = true;
  }
  if (!found_first || !found_last) {  // unreadable message indexes: the chunks' time ranges
    first = std::numeric_limits<uint64_t>::max(), last = 0;
    for (const ChunkIndex* ci : by_end)
      first = std::min(first, ci->start_time), last = std::max(last, ci->end_time);
  }
  return std::make_pair(first, last);
}

}  // namespace polyloc::mcap
