// libFuzzer target for the control protocol's frame parser and command dispatcher.
// Input: byte 0 seeds how the rest is cut into pushes; the rest is a byte stream from a client.
// Checks: the parser never reads out of bounds (ASan), gives the same events however the
// stream is cut, and every frame it yields, dispatched to the fake handler, makes a reply that
// encodes and parses back to itself; the message decoders take any request's words.
#include "protocol_fake_handler.hpp"

#include "protocol/dispatcher.hpp"
#include "protocol/messages.hpp"
#include "protocol/parser.hpp"

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <vector>

using namespace polyloc::protocol;

namespace {

constexpr uint32_t kMax = 4096;  // small, so oversize frames are reachable

void check(bool ok, const char* what) {
  if (ok) return;
  std::fprintf(stderr, "fuzz_protocol_frame: %s\n", what);
  std::abort();
}

// Frames and errors of the stream, pushed in pieces whose sizes come from `seed` (0: whole).
std::vector<ParseResult> parse(const uint8_t* data, size_t size, uint32_t seed) {
  FrameParser p(kMax);
  std::vector<ParseResult> out;
  uint64_t x = seed * 0x9e3779b97f4a7c15ull + 1;
  for (size_t i = 0; i < size;) {
    x ^= x << 13, x ^= x >> 7, x ^= x << 17;  // xorshift
    const size_t n = seed == 0 ? size : std::min<size_t>(1 + x % 67, size - i);
    p.push({data + i, n});
    i += n;
    for (ParseResult r = p.next(); r.kind != ParseResult::Kind::NeedMore; r = p.next()) {
      check(p.buffered() <= kMax + size, "parser holds more than a frame and a push");
      out.push_back(std::move(r));
    }
  }
  return out;
}

bool sameEvent(const ParseResult& a, const ParseResult& b) {
  return a.kind == b.kind && a.error == b.error && a.offset == b.offset && a.size == b.size &&
         a.command == b.command && a.frame == b.frame;
}

void decodeAll(WordSpan w) {
  (void)decodeSeed(w), (void)decodePlanarPose(w), (void)decodePoseCovariance(w), (void)decodeMount(w);
  (void)decodeScanners(w), (void)decodeScan(w), (void)decodeTracks(w), (void)decodeHealth(w);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const uint32_t seed = data[0];
  const auto whole = parse(data + 1, size - 1, 0);
  const auto cut = parse(data + 1, size - 1, seed | 1);
  check(whole.size() == cut.size(), "event count depends on how the stream is cut");
  for (size_t i = 0; i < whole.size(); ++i) check(sameEvent(whole[i], cut[i]), "events depend on the cut");

  fake::FakeHandler handler;
  handler.scan_beams = 16;
  for (const auto& e : whole) {
    if (e.kind != ParseResult::Kind::Frame) {
      check(toStatus(e.error) != Status::Ok && !e.message().empty(), "an error without a status");
      continue;
    }
    decodeAll(e.frame.data);
    const Dispatched d = dispatch(e.frame, handler);
    check(d.reply.command == replyId(e.frame.command), "reply id is not the request's with bit 31");
    check(!d.reply.data.empty(), "reply without a status");
    const auto bytes = encodeFrame(d.reply);
    FrameParser back(static_cast<uint32_t>(bytes.size()));
    back.push(bytes);
    const ParseResult r = back.next();
    check(r.kind == ParseResult::Kind::Frame && r.frame == d.reply, "reply does not parse back to itself");
    if (!isError(replyStatus(d.reply))) decodeAll(replyData(d.reply));
  }
  return 0;
}
