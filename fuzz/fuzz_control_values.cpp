// libFuzzer target for control commands with values: each input is a list of requests whose
// words are drawn from the values that break software ({0, -0, tiny, 1e19, 1e300, -1e300, inf,
// nan} as float32, or any float), sent through the dispatcher to a handler that applies
// polylocd's SETPOSE rule (pipeline/seed_check.hpp) on a 40 m x 30 m map. Checks: no crash
// (ASan/UBSan); a seed is accepted only when every value is finite and within its domain
// (docs/failure.md); every reply encodes and parses back.
#include "pipeline/seed_check.hpp"
#include "protocol/commands.hpp"
#include "protocol/dispatcher.hpp"
#include "protocol/messages.hpp"
#include "protocol/parser.hpp"
#include "protocol_fake_handler.hpp"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <vector>

using namespace polyloc;
using namespace polyloc::protocol;

namespace {

void check(bool ok, const char* what) {
  if (ok) return;
  std::fprintf(stderr, "fuzz_control_values: %s\n", what);
  std::abort();
}

const Eigen::AlignedBox3f kMap(Eigen::Vector3f(0, 0, 0), Eigen::Vector3f(40, 30, 3));

// The fake's answers, but SETPOSE judged by polylocd's own rule.
class Handler : public fake::FakeHandler {
 public:
  Status setPose(const PoseSeed& s) override {
    const double sxy = s.sigma_xy_m.value_or(0.1), syaw = s.sigma_yaw_rad.value_or(0.1);
    if (pipeline::seedProblem(s, sxy, syaw, kMap)) return Status::BadArgument;
    check(std::isfinite(s.x) && std::isfinite(s.y) && std::isfinite(s.yaw), "a non-finite seed accepted");
    check(s.x >= -10 && s.x <= 50 && s.y >= -10 && s.y <= 40, "a seed off the map accepted");
    check(std::fabs(s.yaw) <= 100 && sxy <= 1000 && syaw <= 100, "a seed beyond its domain accepted");
    return Status::Ok;
  }
};

float valueOf(const uint8_t*& p, const uint8_t* end) {
  static const float kSpecial[] = {0.f, -0.f, 1e-38f, 1e19f, std::numeric_limits<float>::infinity(),
                                   -std::numeric_limits<float>::infinity(), std::numeric_limits<float>::quiet_NaN(),
                                   2.f, 1000.f, -1e30f};
  if (p >= end) return 0.f;
  const uint8_t k = *p++;
  if (k < 200) return kSpecial[k % 10];
  float v = 0;
  const size_t n = std::min<size_t>(4, size_t(end - p));
  std::memcpy(&v, p, n);
  p += n;
  return v;
}

const uint32_t kCommands[] = {cmd::SETPOSE, cmd::SETPOSE, cmd::GETSCANRADIALSCANNER, cmd::GETSCANNERPOSE,
                              cmd::SETCOLLISIONAVOIDANCE, cmd::CHECKPROTOCOL, cmd::GETPOSE, cmd::PING};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  Handler h;
  h.scan_beams = 8;
  const uint8_t* p = data;
  const uint8_t* end = data + size;
  while (p + 2 <= end) {
    const uint32_t command = kCommands[*p++ % 8];
    const size_t words = *p++ % 6;  // SETPOSE takes 3 or 5; others 0 or 1: wrong sizes too
    std::vector<uint32_t> w;
    for (size_t i = 0; i < words; ++i) {
      if (command == cmd::SETPOSE) {
        const float v = valueOf(p, end);
        uint32_t u;
        std::memcpy(&u, &v, 4);
        w.push_back(u);
      } else {
        w.push_back(p < end ? uint32_t(*p++) * 0x01010101u : 0u);
      }
    }
    const Frame req{command, w};
    const Dispatched d = dispatch(req, h);
    check(d.reply.command == replyId(command), "reply id is not the request's with bit 31");
    const auto bytes = encodeFrame(d.reply);
    FrameParser back(uint32_t(bytes.size()));
    back.push(bytes);
    const ParseResult r = back.next();
    check(r.kind == ParseResult::Kind::Frame && r.frame == d.reply, "reply does not parse back to itself");
  }
  return 0;
}
