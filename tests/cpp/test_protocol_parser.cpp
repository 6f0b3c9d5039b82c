// The incremental frame parser: split and concatenated streams, garbage, wrong magic, bad CRC,
// oversize and malformed sizes, and that it resynchronises on the next good frame.
#include "protocol/parser.hpp"

#include <gtest/gtest.h>

#include <random>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_protocol_parser {

using namespace polyloc::protocol;
using Kind = ParseResult::Kind;


std::vector<uint8_t> cat(std::initializer_list<std::vector<uint8_t>> parts) {
  std::vector<uint8_t> out;
  for (const auto& p : parts) out.insert(out.end(), p.begin(), p.end());
  return out;
}

const std::vector<uint8_t> kPing = encodeFrame(cmd::PING);
const std::vector<uint8_t> kGetPose = encodeFrame(cmd::GETPOSE);
const std::vector<uint8_t> kScan = encodeFrame(cmd::GETSCANRADIALSCANNER, std::vector<uint32_t>{2});

// Every event (frame or error) the parser gives for `stream` pushed in pieces of `chunk` bytes.
std::vector<ParseResult> parseAll(const std::vector<uint8_t>& stream, size_t chunk,
                                  uint32_t max = kDefaultMaxFrameBytes) {
  FrameParser p(max);
  std::vector<ParseResult> events;
  for (size_t i = 0; i < stream.size(); i += chunk) {
    p.push({stream.data() + i, std::min(chunk, stream.size() - i)});
    for (ParseResult r = p.next(); r.kind != Kind::NeedMore; r = p.next()) events.push_back(std::move(r));
  }
  return events;
}

std::vector<std::string> summary(const std::vector<ParseResult>& events) {
  std::vector<std::string> s;
  for (const auto& e : events)
    s.push_back(e.kind == Kind::Frame ? "frame " + std::to_string(e.frame.command) : toString(e.error));
  return s;
}


TEST(ProtocolParser, OneByteAtATimeAndConcatenated) {
  const auto stream = cat({kPing, kScan, kGetPose});
  for (size_t chunk : {size_t(1), size_t(3), size_t(7), size_t(16), stream.size()}) {
    const auto events = parseAll(stream, chunk);
    ASSERT_EQ(events.size(), 3u) << "chunk " << chunk;
    EXPECT_EQ(events[0].frame.command, cmd::PING);
    EXPECT_EQ(events[1].frame, (Frame{cmd::GETSCANRADIALSCANNER, {2}}));
    EXPECT_EQ(events[1].offset, kPing.size());
    EXPECT_EQ(events[2].frame.command, cmd::GETPOSE);
  }
}

TEST(ProtocolParser, NeedsTheWholeFrame) {
  FrameParser p;
  p.push({kScan.data(), kScan.size() - 1});
  EXPECT_EQ(p.next().kind, Kind::NeedMore);
  EXPECT_TRUE(p.midFrame());
  EXPECT_EQ(p.buffered(), kScan.size() - 1);
  p.push({kScan.data() + kScan.size() - 1, 1});
  EXPECT_EQ(p.next().kind, Kind::Frame);
  EXPECT_FALSE(p.midFrame());
  EXPECT_EQ(p.buffered(), 0u);
}

TEST(ProtocolParser, GarbageBeforeAFrameIsOneErrorThenTheFrame) {
  const std::vector<uint8_t> garbage{'x', 'H', 'E', 'L', 'L', 'O', 0, 0xff, 'H', 'E'};
  const auto stream = cat({garbage, kPing});
  for (size_t chunk : {size_t(1), size_t(2), size_t(5), stream.size()}) {
    const auto events = parseAll(stream, chunk);
    EXPECT_EQ(summary(events), (std::vector<std::string>{"bad_magic", "frame 0"})) << "chunk " << chunk;
    EXPECT_EQ(events[0].offset, 0u);
    EXPECT_EQ(events[1].offset, garbage.size());
  }
  FrameParser p;
  p.push(stream);
  while (p.next().kind != Kind::NeedMore) {
  }
  EXPECT_EQ(p.discarded(), garbage.size());
}

TEST(ProtocolParser, WrongMagic) {
  auto bad = kPing;
  bad[3] = 'P';  // "HELP"
  const auto events = parseAll(cat({bad, kGetPose}), 1);
  EXPECT_EQ(summary(events), (std::vector<std::string>{"bad_magic", "frame 131072"}));
  EXPECT_NE(events[0].message().find("magic"), std::string::npos);
}

TEST(ProtocolParser, BadCrcDropsTheFrameAndGoesOn) {
  auto bad = kScan;
  bad[12] ^= 0x01;  // one bit of the data
  const auto events = parseAll(cat({kPing, bad, kGetPose}), 1);
  ASSERT_EQ(summary(events), (std::vector<std::string>{"frame 0", "bad_crc", "frame 131072"}));
  EXPECT_EQ(events[1].command, cmd::GETSCANRADIALSCANNER);
  EXPECT_EQ(events[1].size, kScan.size());
  EXPECT_EQ(events[1].offset, kPing.size());
  EXPECT_NE(events[1].message().find("CRC"), std::string::npos);
  EXPECT_NE(events[1].message().find("0x00040002"), std::string::npos);
}

TEST(ProtocolParser, OversizeIsReportedFromTheHeaderAlone) {
  const auto big = encodeFrame(cmd::PING, std::vector<uint32_t>(100));  // 416 bytes
  FrameParser p(256);
  p.push({big.data(), 8});  // only magic and size arrived
  const ParseResult r = p.next();
  ASSERT_EQ(r.kind, Kind::Error);
  EXPECT_EQ(r.error, FrameError::TooLarge);
  EXPECT_EQ(r.size, 416u);
  EXPECT_NE(r.message().find("416"), std::string::npos);
  // The rest of it is skipped without further errors; the next frame is found.
  p.push({big.data() + 8, big.size() - 8});
  p.push(kPing);
  EXPECT_EQ(p.next().kind, Kind::Frame);
  EXPECT_EQ(p.next().kind, Kind::NeedMore);
  EXPECT_EQ(p.discarded(), big.size());
}

TEST(ProtocolParser, SizeTooSmallOrNotAMultipleOfFour) {
  for (uint32_t size : {0u, 4u, 12u, 17u, 18u, 19u, 30u}) {
    auto f = kPing;
    storeLE32(f.data() + 4, size);
    const auto events = parseAll(cat({f, kGetPose}), 1);
    EXPECT_EQ(summary(events), (std::vector<std::string>{"bad_size", "frame 131072"})) << "size " << size;
    EXPECT_EQ(events[0].size, size);
  }
}

TEST(ProtocolParser, GarbageRunIsOneErrorHoweverItArrives) {
  std::vector<uint8_t> garbage(10000);
  std::mt19937 rng(7);
  for (auto& b : garbage) b = uint8_t(rng() % 64);  // no 'H' (0x48): no magic candidates
  const auto stream = cat({garbage, kPing, garbage, kGetPose});
  for (size_t chunk : {size_t(1), size_t(100), stream.size()})
    EXPECT_EQ(summary(parseAll(stream, chunk)),
              (std::vector<std::string>{"bad_magic", "frame 0", "bad_magic", "frame 131072"}));
}

TEST(ProtocolParser, RandomChunkingGivesTheSameEvents) {
  // Frames, garbage and broken frames mixed; every cut of the stream parses the same.
  auto crc = kScan;
  crc.back() ^= 0xff;
  auto size = kGetPose;
  storeLE32(size.data() + 4, 15);
  const auto stream = cat(
      {kPing, {'H', 'E', 'L'}, kScan, crc, size, kPing, {1, 2, 3}, encodeFrame(cmd::PING, std::vector<uint32_t>(70))});
  const auto whole = summary(parseAll(stream, stream.size(), 256));
  EXPECT_EQ(whole, (std::vector<std::string>{"frame 0", "bad_magic", "frame 262146", "bad_crc", "bad_size", "frame 0",
                                             "bad_magic", "too_large"}));
  std::mt19937 rng(1);
  for (int trial = 0; trial < 200; ++trial) {
    FrameParser p(256);
    std::vector<ParseResult> events;
    for (size_t i = 0; i < stream.size();) {
      const size_t n = std::min<size_t>(1 + rng() % 40, stream.size() - i);
      p.push({stream.data() + i, n});
      i += n;
      for (ParseResult r = p.next(); r.kind != Kind::NeedMore; r = p.next()) events.push_back(std::move(r));
    }
    ASSERT_EQ(summary(events), whole) << "trial " << trial;
  }
}

TEST(ProtocolParser, BufferStaysBounded) {
  FrameParser p;
  for (int i = 0; i < 10000; ++i) {
    p.push(kPing);
    ASSERT_EQ(p.next().kind, Kind::Frame);
  }
  EXPECT_EQ(p.buffered(), 0u);
}

}  // namespace polyloc::t_protocol_parser
