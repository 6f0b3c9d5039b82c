// libFuzzer target: what polylocd reads from shared memory that clients write, as arbitrary
// bytes. The first byte picks the mode:
//   0  validateInput on a frame against one of a few channels, with an arbitrary size field;
//   1  a Reader on a ring whose control block and slot headers are the input;
//   2  attach to a segment image with the input's patches applied, then read every channel.
// Nothing may crash, hang or read outside the slot (ASan, UBSan).
#include "shm/channel.hpp"
#include "shm/layout.hpp"
#include "shm/segment.hpp"
#include "shm/validate.hpp"

#include <fcntl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace {

using namespace polyloc::shm;

const std::vector<ChannelSpec>& specs() {
  static const std::vector<ChannelSpec> s = {
      {.name = "scan/front", .kind = POLYLOC_KIND_RANGES, .slot_count = 4, .count = 5},
      {.name = "scan/any", .kind = POLYLOC_KIND_RANGES, .slot_count = 2},   // any beam count
      {.name = "depth/tof", .kind = POLYLOC_KIND_DEPTH, .slot_count = 1, .width = 3, .height = 2},
      {.name = "odom", .kind = POLYLOC_KIND_ODOMETRY, .slot_count = 2},
      {.name = "pose", .kind = POLYLOC_KIND_POSE, .direction = POLYLOC_DIR_OUTPUT, .slot_count = 1}};
  return s;
}

// One segment for the whole run, under a name of this process (removed from the namespace at
// once: only this process maps it).
Segment& segment() {
  static Segment seg = [] {
    const std::string name = "fz" + std::to_string(getpid());
    Segment s = Segment::create(name, specs());
    s.ready();
    Segment::unlink(name);
    return s;
  }();
  return seg;
}

struct Input {
  const uint8_t* p;
  size_t n;
  template <class T> T take() {
    T v{};
    const size_t k = std::min(sizeof v, n);
    if (k) std::memcpy(&v, p, k);
    p += k;
    n -= k;
    return v;
  }
};

StampRules rules(Input& in) {
  StampRules r;
  r.now_ns = 1'700'000'000'000'000'000;
  r.last_ns = in.take<int64_t>();
  if (in.take<uint8_t>() & 1) r.max_age_ns = in.take<int64_t>();
  return r;
}

// Reads whatever the reader finds and validates it, as polylocd does.
void drain(Reader& r, const polyloc_channel_desc& d, Input& rest) {
  std::vector<uint8_t> buf;
  StampRules rl = rules(rest);
  for (int i = 0; i < 8; ++i) {
    auto f = (i & 1) ? r.newest(buf) : r.next(buf);
    if (!f) break;
    if (d.direction == POLYLOC_DIR_INPUT) validateInput(d, f->frame, buf.data(), f->size, rl);
  }
  r.readInPlace([&](const FrameInfo& f, const uint8_t* p) { validateInput(d, f.frame, p, f.size, rl); });
  r.wait(0);
  (void)r.available();
}

void validateMode(Input in) {
  const Segment& seg = segment();
  const polyloc_channel_desc& d = seg.channel(in.take<uint8_t>() % seg.channelCount());
  const uint32_t claimed = in.take<uint32_t>();
  const uint16_t frame = in.take<uint16_t>();
  StampRules r = rules(in);
  // The bytes as a slot holds them: payload_max readable, the size field arbitrary.
  std::vector<uint8_t> slot(d.payload_max);
  if (in.n) std::memcpy(slot.data(), in.p, std::min<size_t>(in.n, slot.size()));
  const uint32_t bytes = (claimed & 0x80000000u) ? static_cast<uint32_t>(std::min<size_t>(in.n, slot.size())) : claimed;
  validateInput(d, frame, slot.data(), bytes, r);
}

void ringMode(Input in) {
  Segment& seg = segment();
  const int ch = in.take<uint8_t>() % seg.channelCount();
  const polyloc_channel_desc& d = seg.channel(ch);
  const uint64_t ring_bytes = ringBytes(d.slot_count, d.slot_size);
  const size_t k = std::min<size_t>(in.n, ring_bytes);
  if (k) std::memcpy(seg.ring(ch), in.p, k);
  Input rest{in.p + k, in.n - k};
  Reader r(seg, ch, static_cast<Reader::Start>(rest.take<uint8_t>() % 3));
  drain(r, d, rest);
}

// A valid segment's bytes, patched: (offset, length <= 8, bytes) triples.
void attachMode(Input in) {
  static std::vector<uint8_t> image = [] {
    const Segment& seg = segment();
    return std::vector<uint8_t>(seg.base(), seg.base() + seg.size());
  }();
  // One fixed name: a fuzzer stopped by a finding leaves this one object, not one per run.
  static const std::string name = "fuzz-attach";
  static const int fd = [] {
    const std::string path = segmentName(name);
    const int f = shm_open(path.c_str(), O_CREAT | O_RDWR, 0600);
    if (f < 0 || ftruncate(f, static_cast<off_t>(image.size())) != 0) abort();
    std::atexit([] { shm_unlink(segmentName(name).c_str()); });  // on a clean end
    return f;
  }();
  std::vector<uint8_t> patched = image;
  while (in.n >= 3) {
    const size_t off = in.take<uint16_t>() % patched.size();
    const size_t len = std::min<size_t>({in.take<uint8_t>() % 9u, in.n, patched.size() - off});
    if (len) std::memcpy(patched.data() + off, in.p, len);
    in.p += len;
    in.n -= len;
  }
  if (pwrite(fd, patched.data(), patched.size(), 0) != static_cast<ssize_t>(patched.size())) abort();
  try {
    Segment seg = Segment::attach(name);
    Input none{nullptr, 0};
    for (int i = 0; i < seg.channelCount(); ++i) {
      Reader r(seg, i, Reader::Start::Oldest);
      drain(r, seg.channel(i), none);
    }
    (void)seg.stale();
  } catch (const ShmError&) {
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  Input in{data + 1, size - 1};
  switch (data[0] % 3) {
    case 0: validateMode(in); break;
    case 1: ringMode(in); break;
    case 2: attachMode(in); break;
  }
  return 0;
}
