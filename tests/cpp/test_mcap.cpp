// MCAP writer and reader: round trips with each compression, the byte layout of a tiny file
// checked record by record (opcodes, lengths, CRCs) by a parser written here independently of
// kernels/io, out-of-order chunks merged by log time, determinism, and malformed files (hand-made
// ones with each kind of fault, truncations at every offset, random corruption).
#include "io_samples.hpp"
#include "temp_dir.hpp"

#include <polyloc/io/recording.hpp>

#include <gtest/gtest.h>
#include <zlib.h>

#include <fstream>
#include <iterator>
#include <random>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_mcap {

using namespace polyloc;
using polyloc::test::sampleMessages;
using polyloc::test::sameMessage;


struct Written {
  std::string topic;
  int64_t t;
  msg::Message m;
};

// Every sample type on its own topic, `rounds` times, 10 ms apart.
std::vector<Written> sampleRun(int rounds) {
  static const char* topics[] = {"/scan_front", "/points", "/tof/depth", "/tof/camera_info",
                                 "/odom", "/tf", "/ground_truth", "/tracks", "/amcl_pose"};
  std::vector<Written> out;
  for (int k = 0; k < rounds; ++k) {
    auto msgs = sampleMessages(k);
    for (size_t i = 0; i < msgs.size(); ++i)
      out.push_back({topics[i], 1000000000LL + k * 10000000LL + static_cast<int64_t>(i) * 1000, msgs[i]});
  }
  return out;
}

void writeAll(const std::string& path, const std::vector<Written>& run, McapWriteOptions o) {
  auto w = createMcap(path, o);
  for (const auto& x : run) w->write(x.topic, x.t, x.m);
  w->close();
}

std::vector<RecordedMessage> readAll(const std::string& path, ReadStats* stats = nullptr) {
  auto r = openMcap(path);
  std::vector<RecordedMessage> out;
  RecordedMessage m;
  while (r->next(m)) out.push_back(m);
  if (stats) *stats = r->stats();
  return out;
}

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

std::string joined(const ReadStats& s) {
  std::string all;
  for (const auto& w : s.warnings) all += w + "\n";
  return all;
}

// ---- a minimal MCAP builder, independent of kernels/io, for hand-made files ----------------

struct Bytes {
  std::string b;
  Bytes& u8(uint8_t v) { return le(v, 1); }
  Bytes& u16(uint16_t v) { return le(v, 2); }
  Bytes& u32(uint32_t v) { return le(v, 4); }
  Bytes& u64(uint64_t v) { return le(v, 8); }
  Bytes& str(const std::string& s) { return u32(static_cast<uint32_t>(s.size())).raw(s); }
  Bytes& raw(const std::string& s) { b += s; return *this; }
  Bytes& le(uint64_t v, int n) {
    for (int i = 0; i < n; ++i) b.push_back(static_cast<char>(v >> (8 * i)));
    return *this;
  }
};
std::string record(uint8_t op, const Bytes& content) {
  return Bytes().u8(op).u64(content.b.size()).raw(content.b).b;
}
std::string messageRecord(uint16_t ch, uint64_t t, const std::string& payload) {
  return record(0x05, Bytes().u16(ch).u32(0).u64(t).u64(t).raw(payload));
}
std::string chunkRecord(const std::string& records, const std::string& compression, uint32_t crc) {
  return record(0x06, Bytes().u64(0).u64(0).u64(records.size()).u32(crc).str(compression)
                          .u64(records.size()).raw(records));
}
uint32_t crcOf(const std::string& s) {
  return static_cast<uint32_t>(::crc32(0, reinterpret_cast<const Bytef*>(s.data()), s.size()));
}
const std::string kMagic("\x89MCAP0\r\n", 8);
uint64_t le(const std::string& s, size_t at, int n) {
  uint64_t v = 0;
  for (int i = 0; i < n; ++i) v |= uint64_t{static_cast<uint8_t>(s[at + i])} << (8 * i);
  return v;
}


TEST(Mcap, RoundTripEachCompression) {
  test::TempDir dir;
  const auto run = sampleRun(40);
  for (std::string c : {"zstd", "lz4", ""}) {
    SCOPED_TRACE("compression \"" + c + "\"");
    std::string path = dir.file("run_" + c + ".mcap");
    writeAll(path, run, {c, 4096});
    ReadStats stats;
    auto got = readAll(path, &stats);
    EXPECT_TRUE(stats.warnings.empty()) << joined(stats);
    EXPECT_EQ(stats.messages, run.size());
    ASSERT_EQ(got.size(), run.size());
    for (size_t i = 0; i < run.size(); ++i) {
      EXPECT_EQ(got[i].topic, run[i].topic);
      EXPECT_EQ(got[i].log_time_ns, run[i].t);
      EXPECT_EQ(got[i].publish_time_ns, run[i].t);
      EXPECT_TRUE(sameMessage(got[i].message, run[i].m)) << i;
    }
    auto r = openMcap(path);
    EXPECT_EQ(r->format(), "mcap");
    auto topics = r->topics();
    ASSERT_EQ(topics.size(), 9u);  // one per message type
    EXPECT_EQ(topics[0].name, "/scan_front");
    EXPECT_EQ(topics[0].type, "sensor_msgs/msg/LaserScan");
    EXPECT_EQ(topics[0].count, 40u);
    EXPECT_EQ(topics[0].first_ns, 1000000000LL);
    EXPECT_EQ(topics[0].last_ns, 1000000000LL + 39 * 10000000LL);
    EXPECT_NEAR(topics[0].rateHz(), 100.0, 1e-9);
    EXPECT_EQ(topics[6].name, "/ground_truth");
    EXPECT_EQ(topics[6].type, "geometry_msgs/msg/PoseStamped");
  }
}

TEST(Mcap, DeterministicBytes) {
  test::TempDir dir;
  const auto run = sampleRun(30);
  for (std::string c : {"zstd", "lz4", ""}) {
    writeAll(dir.file("a.mcap"), run, {c, 2048});
    writeAll(dir.file("b.mcap"), run, {c, 2048});
    EXPECT_EQ(slurp(dir.file("a.mcap")), slurp(dir.file("b.mcap"))) << c;
  }
}

TEST(Mcap, OverlappingChunksComeOutInLogTimeOrder) {
  test::TempDir dir;
  // Two sensors whose messages reach the writer late by up to 80 ms: chunks overlap in time.
  std::vector<Written> run;
  auto scan = sampleMessages()[0], pose = sampleMessages()[6];
  for (int i = 0; i < 300; ++i) {
    run.push_back({"/scan", 5000000000LL + i * 10000000LL, scan});
    run.push_back({"/late", 5000000000LL + i * 10000000LL - (i % 9) * 10000000LL - 1, pose});
  }
  writeAll(dir.file("late.mcap"), run, {"zstd", 1024});
  ReadStats stats;
  auto got = readAll(dir.file("late.mcap"), &stats);
  EXPECT_TRUE(stats.warnings.empty()) << joined(stats);
  ASSERT_EQ(got.size(), run.size());
  for (size_t i = 1; i < got.size(); ++i) ASSERT_LE(got[i - 1].log_time_ns, got[i].log_time_ns) << i;
  auto topics = openMcap(dir.file("late.mcap"))->topics();
  ASSERT_EQ(topics.size(), 2u);
  EXPECT_EQ(topics[1].name, "/late");
  EXPECT_EQ(topics[1].count, 300u);
  EXPECT_EQ(topics[1].first_ns, 5000000000LL - 1);
  EXPECT_EQ(topics[1].last_ns, 5000000000LL + 299 * 10000000LL - (299 % 9) * 10000000LL - 1);
}

TEST(Mcap, TinyFileLayoutByHand) {
  test::TempDir dir;
  msg::PoseStamped p{{{1, 2}, "map"}, {{1, 2, 3}, {0, 0, 0, 1}}};
  {
    auto w = createMcap(dir.file("tiny.mcap"), {"", 1 << 20});
    w->write("/ground_truth", 1000, p);
    w->close();
  }
  const std::string f = slurp(dir.file("tiny.mcap"));
  ASSERT_GT(f.size(), 16u);
  EXPECT_EQ(f.substr(0, 8), kMagic);
  EXPECT_EQ(f.substr(f.size() - 8), kMagic);
  // Walk the records: opcode (1 byte) + content length (uint64 LE) + content.
  std::vector<std::pair<uint8_t, size_t>> recs;  // opcode, offset
  for (size_t at = 8; at < f.size() - 8; at += 9 + le(f, at + 1, 8)) recs.emplace_back(f[at], at);
  std::vector<uint8_t> ops;
  for (auto& r : recs) ops.push_back(r.first);
  const std::vector<uint8_t> want = {0x01, 0x03, 0x04, 0x06, 0x07, 0x0F,   // data section
                                     0x03, 0x04, 0x0B, 0x08,               // summary
                                     0x0E, 0x0E, 0x0E, 0x0E, 0x02};        // offsets, footer
  ASSERT_EQ(ops, want);
  auto content = [&](size_t i) { return f.substr(recs[i].second + 9, le(f, recs[i].second + 1, 8)); };

  // Header: profile "ros2", library "polyloc".
  EXPECT_EQ(content(0), Bytes().str("ros2").str("polyloc").b);
  // Schema 1: name, encoding "ros2msg", the text.
  const std::string& text = msg::ros2msgSchema("geometry_msgs/msg/PoseStamped");
  EXPECT_EQ(content(1), Bytes().u16(1).str("geometry_msgs/msg/PoseStamped").str("ros2msg").str(text).b);
  // Channel 1 on schema 1, "cdr", empty metadata map.
  EXPECT_EQ(content(2), Bytes().u16(1).u16(1).str("/ground_truth").str("cdr").u32(0).b);
  // Chunk: times, sizes, CRC of the uncompressed records, no compression, the Message record.
  auto payload = msg::encodeCdr(p);
  std::string message = messageRecord(1, 1000, std::string(payload.begin(), payload.end()));
  EXPECT_EQ(content(3), Bytes().u64(1000).u64(1000).u64(message.size()).u32(crcOf(message)).str("")
                            .u64(message.size()).raw(message).b);
  // MessageIndex: channel 1, one (log time, offset in the chunk's records) entry.
  EXPECT_EQ(content(4), Bytes().u16(1).u32(16).u64(1000).u64(0).b);
  // DataEnd: CRC of everything before it.
  EXPECT_EQ(le(f, recs[5].second + 9, 4), crcOf(f.substr(0, recs[5].second)));
  // Statistics: 1 message, 1 schema, 1 channel, 0 attachments, 0 metadata, 1 chunk, times, counts.
  EXPECT_EQ(content(8), Bytes().u64(1).u16(1).u32(1).u32(0).u32(0).u32(1).u64(1000).u64(1000)
                            .u32(10).u16(1).u64(1).b);
  // ChunkIndex: points at the chunk and its message index.
  EXPECT_EQ(content(9), Bytes().u64(1000).u64(1000).u64(recs[3].second).u64(recs[4].second - recs[3].second)
                            .u32(10).u16(1).u64(recs[4].second).u64(recs[5].second - recs[4].second)
                            .str("").u64(message.size()).u64(message.size()).b);
  // SummaryOffsets: one per group, in summary order.
  EXPECT_EQ(content(10), Bytes().u8(0x03).u64(recs[6].second).u64(recs[7].second - recs[6].second).b);
  EXPECT_EQ(content(12), Bytes().u8(0x0B).u64(recs[8].second).u64(recs[9].second - recs[8].second).b);
  // Footer: summary start, summary offset start, CRC from summary start through the latter.
  const size_t footer = recs[14].second;
  EXPECT_EQ(le(f, footer + 1, 8), 20u);
  EXPECT_EQ(le(f, footer + 9, 8), recs[6].second);
  EXPECT_EQ(le(f, footer + 17, 8), recs[10].second);
  EXPECT_EQ(le(f, footer + 25, 4), crcOf(f.substr(recs[6].second, footer + 25 - recs[6].second)));
}

TEST(Mcap, HandMadeFileWithEveryKindOfFault) {
  test::TempDir dir;
  const std::string scan_type = "sensor_msgs/msg/LaserScan";
  auto good = msg::encodeCdr(sampleMessages()[0]);
  std::string payload(good.begin(), good.end());
  std::string inner = messageRecord(1, 1, payload) + messageRecord(2, 2, "xx") +
                      messageRecord(2, 3, "yy") + messageRecord(9, 4, payload) +  // unknown channel
                      messageRecord(1, 5, payload.substr(0, 30));                 // cut CDR
  std::string f = kMagic + record(0x01, Bytes().str("ros2").str("hand"));
  f += record(0x03, Bytes().u16(1).str(scan_type).str("ros2msg").str(msg::ros2msgSchema(scan_type)));
  f += record(0x03, Bytes().u16(2).str("foo_msgs/msg/Bar").str("ros2msg").str("int8 x"));
  f += record(0x04, Bytes().u16(1).u16(1).str("/scan").str("cdr").u32(0));
  f += record(0x04, Bytes().u16(2).u16(2).str("/bar").str("cdr").u32(0));
  f += chunkRecord(inner, "", crcOf(inner));
  size_t brotli_at = f.size();
  f += chunkRecord(messageRecord(1, 6, payload), "brotli", 0);
  size_t badcrc_at = f.size();
  f += chunkRecord(messageRecord(1, 7, payload), "", 12345);
  f += messageRecord(1, 9, payload);  // outside any chunk: allowed
  f += record(0x0F, Bytes().u32(0));
  f += record(0x02, Bytes().u64(0).u64(0).u32(0)) + kMagic;
  std::string path = dir.write("faults.mcap", f);

  ReadStats stats;
  auto got = readAll(path, &stats);
  ASSERT_EQ(got.size(), 2u) << joined(stats);
  EXPECT_EQ(got[0].log_time_ns, 1);
  EXPECT_EQ(got[1].log_time_ns, 9);
  EXPECT_EQ(got[1].topic, "/scan");
  const std::string w = joined(stats);
  EXPECT_NE(w.find(path + ": topic /bar (type foo_msgs/msg/Bar) is not supported; 2 messages skipped"), std::string::npos) << w;
  EXPECT_NE(w.find("unknown channel 9"), std::string::npos) << w;
  EXPECT_NE(w.find(path + ": topic /scan at t=0.000000005 s: sensor_msgs/msg/LaserScan"), std::string::npos) << w;
  EXPECT_NE(w.find("byte " + std::to_string(brotli_at) + ": chunk skipped: unknown chunk compression \"brotli\""), std::string::npos) << w;
  EXPECT_NE(w.find("byte " + std::to_string(badcrc_at) + ": chunk skipped: CRC mismatch"), std::string::npos) << w;
  EXPECT_EQ(stats.rejected, 6u);  // 2 on /bar, 1 unknown channel, 1 bad CDR, 2 chunks

  auto topics = openMcap(path)->topics();  // no summary: counted by a pass over the file
  ASSERT_EQ(topics.size(), 2u);
  EXPECT_EQ(topics[0].name, "/scan");
  EXPECT_EQ(topics[0].count, 3u);  // t = 1, 5, 9 (5 does not decode, but is there)
  EXPECT_EQ(topics[1].type, "foo_msgs/msg/Bar");
}

TEST(Mcap, NotMcapAtAll) {
  test::TempDir dir;
  for (const std::string& content : {std::string(), std::string("hello world, not an mcap"),
                                     kMagic, kMagic + std::string("\x01\xff\xff", 3)}) {
    std::string path = dir.write("bad.mcap", content);
    try {
      readAll(path);
      FAIL() << "no error for " << content.size() << " bytes";
    } catch (const IoError& e) {
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("byte"), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(openMcap(dir.file("missing.mcap")), IoError);
}

TEST(Mcap, TruncatedAtEveryOffset) {
  test::TempDir dir;
  const auto run = sampleRun(4);
  for (std::string c : {"zstd", ""}) {
    writeAll(dir.file("full.mcap"), run, {c, 1500});
    const std::string full = slurp(dir.file("full.mcap"));
    // Where the data section's last record ends: cutting after it loses no message.
    size_t last_chunk_end = 0;
    for (size_t at = 8; at < full.size() - 8; at += 9 + le(full, at + 1, 8)) {
      if (full[at] == 0x06) last_chunk_end = at + 9 + le(full, at + 1, 8);
      if (full[at] == 0x0F) break;
    }
    // Every offset through the first records, then a stride that still lands in every record.
    for (size_t n = 0; n < full.size(); n += n < 400 ? 1 : 7) {
      SCOPED_TRACE(c + " cut at " + std::to_string(n));
      std::string path = dir.write("cut.mcap", full.substr(0, n));
      try {
        ReadStats stats;
        auto got = readAll(path, &stats);
        EXPECT_FALSE(stats.warnings.empty());
        ASSERT_LE(got.size(), run.size());
        for (size_t i = 0; i < got.size(); ++i) ASSERT_TRUE(sameMessage(got[i].message, run[i].m));
        if (n >= last_chunk_end) {
          EXPECT_EQ(got.size(), run.size());
        }
      } catch (const IoError& e) {
        EXPECT_LT(n, 36u) << e.what();  // only a file cut inside magic or Header (36 bytes) is unreadable
      }
    }
  }
}

TEST(Mcap, RandomCorruptionNeverCrashes) {
  test::TempDir dir;
  const auto run = sampleRun(8);
  std::mt19937 rng(11);
  for (std::string c : {"zstd", "lz4", ""}) {
    writeAll(dir.file("full.mcap"), run, {c, 1500});
    const std::string full = slurp(dir.file("full.mcap"));
    for (int trial = 0; trial < 400; ++trial) {
      std::string f = full;
      for (int k = 0; k <= trial % 3; ++k) f[rng() % f.size()] ^= static_cast<char>(1 + rng() % 255);
      std::string path = dir.write("flip.mcap", f);
      try {
        auto r = openMcap(path);
        r->topics();
        ReadStats stats;
        auto got = readAll(path, &stats);
        // Corruption the CRCs cannot see (indexes, header strings) may pass unnoticed, but then
        // every message must be there and intact.
        if (stats.warnings.empty()) {
          ASSERT_EQ(got.size(), run.size()) << c << " trial " << trial;
          for (size_t i = 0; i < got.size(); ++i) ASSERT_TRUE(sameMessage(got[i].message, run[i].m));
        }
      } catch (const IoError&) {
      }
    }
  }
}

TEST(Mcap, WriterRejectsBadUse) {
  test::TempDir dir;
  EXPECT_THROW(createMcap(dir.file("x.mcap"), {"brotli"}), IoError);
  EXPECT_THROW(createMcap(dir.file("no/such/dir/x.mcap")), IoError);
  auto w = createMcap(dir.file("x.mcap"));
  w->write("/a", 1, msg::PoseStamped{});
  EXPECT_THROW(w->write("/a", 2, msg::LaserScan{}), IoError);  // a topic keeps its first type
  EXPECT_THROW(w->write("/b", -1, msg::PoseStamped{}), IoError);
  w->close();
  EXPECT_THROW(w->write("/a", 3, msg::PoseStamped{}), IoError);
  EXPECT_EQ(readAll(dir.file("x.mcap")).size(), 1u);
}

}  // namespace polyloc::t_mcap
