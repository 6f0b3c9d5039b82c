// Encoding and parsing of the MCAP records polyloc writes and reads (field order as in the
// spec's record tables). Parsing is bounds-checked field by field: a corrupt length gives a
// FormatError naming the record and field, never a read past the record.
#include "mcap_records.hpp"

namespace polyloc::mcap {
namespace {

// Map<uint16, uint64> and Map<string, string>: a uint32 byte length, then the entries.
template <class Put>
void putPrefixed(Out& o, std::vector<uint8_t>& scratch, Put put) {
  scratch.clear();
  Out inner(scratch);
  put(inner);
  o.u32(static_cast<uint32_t>(scratch.size())).raw(scratch.data(), scratch.size());
}

std::map<uint16_t, uint64_t> parseIdMap(In& in, const char* field) {
  In m(in.bytes(field, in.u32(field)), field);
  std::map<uint16_t, uint64_t> out;
  while (m.left() > 0) {
    uint16_t k = m.u16(field);
    out[k] = m.u64(field);
  }
  return out;
}

}  // namespace

void putSchema(Out& o, const Schema& s) {
  size_t at = o.open(kSchema);
  o.u16(s.id).str(s.name).str(s.encoding).u32(static_cast<uint32_t>(s.data.size()));
  o.raw(s.data.data(), s.data.size());
  o.close(at);
}

void putChannel(Out& o, const Channel& c) {
  size_t at = o.open(kChannel);
  o.u16(c.id).u16(c.schema_id).str(c.topic).str(c.message_encoding);
  std::vector<uint8_t> scratch;
  putPrefixed(o, scratch, [&](Out& m) {
    for (const auto& [k, v] : c.metadata) m.str(k).str(v);
  });
  o.close(at);
}

void putChunkIndex(Out& o, const ChunkIndex& c) {
  size_t at = o.open(kChunkIndex);
  o.u64(c.start_time).u64(c.end_time).u64(c.chunk_offset).u64(c.chunk_length);
  std::vector<uint8_t> scratch;
  putPrefixed(o, scratch, [&](Out& m) {
    for (const auto& [k, v] : c.message_index_offsets) m.u16(k).u64(v);
  });
  o.u64(c.message_index_length).str(c.compression).u64(c.compressed_size).u64(c.uncompressed_size);
  o.close(at);
}

void putStatistics(Out& o, const Statistics& s) {
  size_t at = o.open(kStatistics);
  o.u64(s.message_count).u16(s.schema_count).u32(s.channel_count).u32(s.attachment_count);
  o.u32(s.metadata_count).u32(s.chunk_count).u64(s.start_time).u64(s.end_time);
  std::vector<uint8_t> scratch;
  putPrefixed(o, scratch, [&](Out& m) {
    for (const auto& [k, v] : s.channel_message_counts) m.u16(k).u64(v);
  });
  o.close(at);
}

Schema parseSchema(std::span<const uint8_t> content) {
  In in(content, "Schema");
  Schema s;
  s.id = in.u16("id");
  s.name = in.str("name");
  s.encoding = in.str("encoding");
  auto data = in.bytes("data", in.u32("data"));
  s.data.assign(data.begin(), data.end());
  return s;
}

Channel parseChannel(std::span<const uint8_t> content) {
  In in(content, "Channel");
  Channel c;
  c.id = in.u16("id");
  c.schema_id = in.u16("schema_id");
  c.topic = in.str("topic");
  c.message_encoding = in.str("message_encoding");
  In m(in.bytes("metadata", in.u32("metadata")), "Channel");
  while (m.left() > 0) {
    std::string k = m.str("metadata");
    c.metadata[k] = m.str("metadata");
  }
  return c;
}

MessageHeader parseMessage(std::span<const uint8_t> content, std::span<const uint8_t>& payload) {
  In in(content, "Message");
  MessageHeader h;
  h.channel_id = in.u16("channel_id");
  h.sequence = in.u32("sequence");
  h.log_time = in.u64("log_time");
  h.publish_time = in.u64("publish_time");
  payload = in.rest();
  return h;
}

ChunkHeader parseChunkHeader(std::span<const uint8_t> content) {
  In in(content, "Chunk");
  ChunkHeader c;
  c.start_time = in.u64("message_start_time");
  c.end_time = in.u64("message_end_time");
  c.uncompressed_size = in.u64("uncompressed_size");
  c.uncompressed_crc = in.u32("uncompressed_crc");
  c.compression = in.str("compression");
  c.records_size = in.u64("records");
  return c;
}

ChunkIndex parseChunkIndex(std::span<const uint8_t> content) {
  In in(content, "ChunkIndex");
  ChunkIndex c;
  c.start_time = in.u64("message_start_time");
  c.end_time = in.u64("message_end_time");
  c.chunk_offset = in.u64("chunk_start_offset");
  c.chunk_length = in.u64("chunk_length");
  c.message_index_offsets = parseIdMap(in, "message_index_offsets");
  c.message_index_length = in.u64("message_index_length");
  c.compression = in.str("compression");
  c.compressed_size = in.u64("compressed_size");
  c.uncompressed_size = in.u64("uncompressed_size");
  return c;
}

Statistics parseStatistics(std::span<const uint8_t> content) {
  In in(content, "Statistics");
  Statistics s;
  s.message_count = in.u64("message_count");
  s.schema_count = in.u16("schema_count");
  s.channel_count = in.u32("channel_count");
  s.attachment_count = in.u32("attachment_count");
  s.metadata_count = in.u32("metadata_count");
  s.chunk_count = in.u32("chunk_count");
  s.start_time = in.u64("message_start_time");
  s.end_time = in.u64("message_end_time");
  s.channel_message_counts = parseIdMap(in, "channel_message_counts");
  return s;
}

Footer parseFooter(std::span<const uint8_t> content) {
  In in(content, "Footer");
  Footer f;
  f.summary_start = in.u64("summary_start");
  f.summary_offset_start = in.u64("summary_offset_start");
  f.summary_crc = in.u32("summary_crc");
  return f;
}

std::vector<std::pair<uint64_t, uint64_t>> parseMessageIndex(std::span<const uint8_t> content) {
  In in(content, "MessageIndex");
  in.u16("channel_id");
  In r(in.bytes("records", in.u32("records")), "MessageIndex");
  std::vector<std::pair<uint64_t, uint64_t>> out;
  out.reserve(r.left() / 16);
  while (r.left() > 0) {
    uint64_t t = r.u64("records");
    out.emplace_back(t, r.u64("records"));
  }
  return out;
}

}  // namespace polyloc::mcap
