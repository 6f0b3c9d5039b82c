// libpolyloc_client: the C ABI (polyloc_client.h) over polyloc::shm. Every entry point catches
// everything: no C++ exception crosses into C; a failure becomes a status and a message.
#include "polyloc_client.h"

#include "shm/channel.hpp"

#include <polyloc/geometry/pose.hpp>
#include "shm/segment.hpp"
#include "shm/validate.hpp"

#include <cmath>
#include <cstring>
#include <memory>
#include <new>
#include <stdexcept>
#include <string>
#include <vector>

using polyloc::shm::FrameInfo;
using polyloc::shm::Reader;
using polyloc::shm::Segment;
using polyloc::shm::ShmError;
using polyloc::shm::Writer;

struct polyloc_client {
  std::string instance;
  std::unique_ptr<Segment> seg;
  std::vector<std::unique_ptr<Reader>> readers;  // one per channel, from attach on
  std::vector<std::unique_ptr<Writer>> writers;  // one per input channel written, on first write
  std::vector<uint8_t> buf;

  void makeReaders(Reader::Start start) {
    readers.clear();
    for (int i = 0; i < seg->channelCount(); ++i) readers.push_back(std::make_unique<Reader>(*seg, i, start));
    writers.clear();
    writers.resize(readers.size());
  }
};

namespace {

thread_local std::string g_error;

// An error status with its message.
struct Failure {
  int status;
  std::string what;
};

int fail(int status, std::string what) {
  g_error = std::move(what);
  return status;
}

int statusOf(ShmError::Errc e) {
  switch (e) {
    case ShmError::Errc::NotFound: return POLYLOC_ERR_NOT_FOUND;
    case ShmError::Errc::Abi: return POLYLOC_ERR_ABI;
    case ShmError::Errc::NotReady: return POLYLOC_ERR_NOT_READY;
    case ShmError::Errc::Bad: return POLYLOC_ERR_BAD_SEGMENT;
    case ShmError::Errc::Busy: return POLYLOC_ERR_BUSY;
    case ShmError::Errc::System: return POLYLOC_ERR_SYSTEM;
    case ShmError::Errc::Argument: return POLYLOC_ERR_ARGUMENT;
    case ShmError::Errc::Other: break;
  }
  return POLYLOC_ERR_BAD_SEGMENT;
}

// Runs f (returning a status) with every exception turned into a status and a message.
template <class F> int guarded(F&& f) {
  try {
    return f();
  } catch (const Failure& e) {
    return fail(e.status, e.what);
  } catch (const ShmError& e) {
    return fail(statusOf(e.code()), e.what());
  } catch (const std::length_error& e) {
    return fail(POLYLOC_ERR_SIZE, e.what());
  } catch (const std::out_of_range& e) {
    return fail(POLYLOC_ERR_ARGUMENT, e.what());
  } catch (const std::bad_alloc&) {
    return fail(POLYLOC_ERR_SYSTEM, "out of memory");
  } catch (const std::exception& e) {
    return fail(POLYLOC_ERR_INTERNAL, e.what());
  } catch (...) {
    return fail(POLYLOC_ERR_INTERNAL, "unknown exception");
  }
}

[[noreturn]] void raise(int status, std::string what) { throw Failure{status, std::move(what)}; }

void need(const void* p, const char* what, const char* fn) {
  if (!p) raise(POLYLOC_ERR_ARGUMENT, std::string(fn) + ": " + what + " is NULL");
}

std::string channelName(const polyloc_channel_desc& d) { return std::string(d.name, strnlen(d.name, POLYLOC_NAME_LEN)); }

const polyloc_channel_desc& channelOf(const polyloc_client* c, int channel, const char* fn) {
  need(c, "the client", fn);
  if (channel < 0 || channel >= c->seg->channelCount())
    raise(POLYLOC_ERR_ARGUMENT, std::string(fn) + ": no channel " + std::to_string(channel) + " in " + c->seg->name() +
                                    " (it has " + std::to_string(c->seg->channelCount()) + ")");
  return c->seg->channel(channel);
}

int findNamed(const polyloc_client* c, const char* name, const char* fn) {
  need(c, "the client", fn);
  const int ch = c->seg->find(name);
  if (ch < 0) raise(POLYLOC_ERR_NOT_FOUND, std::string(fn) + ": " + c->seg->name() + " has no channel '" + name + "'");
  return ch;
}

// The writer of an input channel of the expected kind, claimed on first use.
Writer& writerOf(polyloc_client* c, int channel, uint32_t kind, const char* fn) {
  const polyloc_channel_desc& d = channelOf(c, channel, fn);
  if (d.direction != POLYLOC_DIR_INPUT)
    raise(POLYLOC_ERR_KIND, std::string(fn) + ": channel '" + channelName(d) + "' is an output of polylocd");
  if (kind && d.kind != kind)
    raise(POLYLOC_ERR_KIND, std::string(fn) + ": channel '" + channelName(d) + "' has kind " + std::to_string(d.kind) +
                                ", not " + std::to_string(kind));
  auto& w = c->writers[channel];
  if (!w) w = std::make_unique<Writer>(*c->seg, channel, false);
  return *w;
}

void fillInfo(polyloc_frame_info* info, const FrameInfo& f) {
  if (info) *info = {f.frame, f.size, f.kind, f.stamp_ns, f.publish_ns};
}

// Reads the newest or next frame of a channel into the handle's buffer.
int readInto(polyloc_client* c, int channel, bool newest, polyloc_frame_info* info, const char* fn) {
  channelOf(c, channel, fn);
  Reader& r = *c->readers[channel];
  const auto f = newest ? r.newest(c->buf) : r.next(c->buf);
  if (!f) return POLYLOC_NO_DATA;
  fillInfo(info, *f);
  return POLYLOC_OK;
}

// A fixed-size struct payload (pose, tracks, health) from the named channel.
template <class T> int readStruct(polyloc_client* c, const char* name, uint32_t kind, bool newest, T* out,
                                  polyloc_frame_info* info, const char* fn) {
  need(out, "out", fn);
  const int ch = findNamed(c, name, fn);
  if (c->seg->channel(ch).kind != kind)
    raise(POLYLOC_ERR_KIND, std::string(fn) + ": channel '" + name + "' has kind " +
                                std::to_string(c->seg->channel(ch).kind));
  const int s = readInto(c, ch, newest, info, fn);
  if (s != POLYLOC_OK) return s;
  if (c->buf.size() < sizeof(T))
    raise(POLYLOC_ERR_SIZE, std::string(fn) + ": frame of " + std::to_string(c->buf.size()) + " bytes, expected " +
                                std::to_string(sizeof(T)));
  std::memcpy(out, c->buf.data(), sizeof(T));
  return POLYLOC_OK;
}

int readRaw(polyloc_client* c, int channel, void* buf, uint32_t capacity, polyloc_frame_info* info,
                   bool newest, const char* fn) {
  if (capacity && !buf) need(buf, "buf", fn);
  const int s = readInto(c, channel, newest, info, fn);
  if (s != POLYLOC_OK) return s;
  if (c->buf.size() > capacity)
    raise(POLYLOC_ERR_SIZE, std::string(fn) + ": frame of " + std::to_string(c->buf.size()) + " bytes, room for " +
                                std::to_string(capacity));
  if (!c->buf.empty()) std::memcpy(buf, c->buf.data(), c->buf.size());
  return POLYLOC_OK;
}

}  // namespace

extern "C" {

const char* polyloc_last_error(void) { return g_error.c_str(); }
uint32_t polyloc_abi_version(void) { return POLYLOC_SHM_ABI_VERSION; }

double polyloc_quaternion_yaw(double qw, double qx, double qy, double qz) {
  return polyloc::yawOfQuaternion(qw, qx, qy, qz);
}

const char* polyloc_status_name(int status) {
  switch (status) {
    case POLYLOC_OK: return "ok";
    case POLYLOC_NO_DATA: return "no data";
    case POLYLOC_TIMEOUT: return "timeout";
    case POLYLOC_ERR_ARGUMENT: return "bad argument";
    case POLYLOC_ERR_NOT_FOUND: return "not found";
    case POLYLOC_ERR_ABI: return "ABI version mismatch";
    case POLYLOC_ERR_NOT_READY: return "not ready";
    case POLYLOC_ERR_BAD_SEGMENT: return "bad segment";
    case POLYLOC_ERR_STALE: return "stale segment";
    case POLYLOC_ERR_BUSY: return "busy";
    case POLYLOC_ERR_KIND: return "wrong channel kind";
    case POLYLOC_ERR_SIZE: return "wrong size";
    case POLYLOC_ERR_SYSTEM: return "system error";
    case POLYLOC_ERR_INTERNAL: return "internal error";
  }
  return "unknown status";
}

int polyloc_attach(const char* instance, polyloc_client** out) {
  return guarded([&]() -> int {
    need(instance, "instance", "polyloc_attach");
    need(out, "out", "polyloc_attach");
    auto c = std::make_unique<polyloc_client>();
    c->instance = instance;
    c->seg = std::make_unique<Segment>(Segment::attach(instance));
    c->makeReaders(Reader::Start::Next);
    *out = c.release();
    return POLYLOC_OK;
  });
}

void polyloc_detach(polyloc_client* c) {
  guarded([&]() -> int {
    delete c;  // writers release their roles first (members go in reverse order)
    return POLYLOC_OK;
  });
}

uint32_t polyloc_generation(const polyloc_client* c) { return c ? c->seg->generation() : 0; }

int polyloc_stale(const polyloc_client* c) {
  return guarded([&]() -> int {
    need(c, "the client", "polyloc_stale");
    return c->seg->stale() ? 1 : 0;
  });
}

int polyloc_reattach(polyloc_client* c) {
  return guarded([&]() -> int {
    need(c, "the client", "polyloc_reattach");
    Segment fresh = Segment::attach(c->instance);
    const bool same = fresh.generation() == c->seg->generation();
    c->writers.clear();  // release the roles on the old segment
    c->writers.resize(c->readers.size());
    *c->seg = std::move(fresh);
    // The same generation: the readers follow the new mapping where they were. A new one:
    // every frame in it is new, read from its oldest.
    if (!same) c->makeReaders(Reader::Start::Oldest);
    return POLYLOC_OK;
  });
}

int polyloc_channel(const polyloc_client* c, const char* name) {
  return guarded([&]() -> int {
    need(name, "name", "polyloc_channel");
    return findNamed(c, name, "polyloc_channel");
  });
}

int polyloc_channel_count(const polyloc_client* c) {
  return guarded([&]() -> int {
    need(c, "the client", "polyloc_channel_count");
    return c->seg->channelCount();
  });
}

int polyloc_channel_info(const polyloc_client* c, int channel, polyloc_channel_desc* out) {
  return guarded([&]() -> int {
    need(out, "out", "polyloc_channel_info");
    *out = channelOf(c, channel, "polyloc_channel_info");
    return POLYLOC_OK;
  });
}

int polyloc_claim_writer(polyloc_client* c, int channel, int take_over) {
  return guarded([&]() -> int {
    channelOf(c, channel, "polyloc_claim_writer");
    if (c->seg->channel(channel).direction != POLYLOC_DIR_INPUT)
      raise(POLYLOC_ERR_KIND, "polyloc_claim_writer: channel '" + channelName(c->seg->channel(channel)) +
                                  "' is an output of polylocd");
    c->writers[channel].reset();
    c->writers[channel] = std::make_unique<Writer>(*c->seg, channel, take_over != 0);
    return POLYLOC_OK;
  });
}

int polyloc_write_ranges(polyloc_client* c, int channel, int64_t stamp_ns, const float* ranges, uint32_t count) {
  return guarded([&]() -> int {
    const char* fn = "polyloc_write_ranges";
    Writer& w = writerOf(c, channel, POLYLOC_KIND_RANGES, fn);
    const polyloc_channel_desc& d = w.channel();
    if (count && !ranges) need(ranges, "ranges", fn);
    if (d.count && count != d.count)
      raise(POLYLOC_ERR_SIZE, std::string(fn) + ": " + std::to_string(count) + " ranges, channel '" + channelName(d) +
                                  "' has " + std::to_string(d.count) + " beams");
    const uint64_t bytes = offsetof(polyloc_ranges, ranges) + uint64_t{count} * sizeof(float);
    if (bytes > d.payload_max)
      raise(POLYLOC_ERR_SIZE, std::string(fn) + ": " + std::to_string(count) + " ranges do not fit channel '" +
                                  channelName(d) + "'");
    auto* p = reinterpret_cast<polyloc_ranges*>(w.begin());
    p->stamp_ns = stamp_ns;
    p->count = count;
    p->reserved = 0;
    if (count) std::memcpy(p->ranges, ranges, count * sizeof(float));
    w.commit(static_cast<uint32_t>(bytes), stamp_ns);
    return POLYLOC_OK;
  });
}

int polyloc_write_depth(polyloc_client* c, int channel, int64_t stamp_ns, const float* depth, const float* amplitude,
                        uint32_t width, uint32_t height) {
  return guarded([&]() -> int {
    const char* fn = "polyloc_write_depth";
    Writer& w = writerOf(c, channel, POLYLOC_KIND_DEPTH, fn);
    const polyloc_channel_desc& d = w.channel();
    need(depth, "depth", fn);
    if (width != d.width || height != d.height)
      raise(POLYLOC_ERR_SIZE, std::string(fn) + ": " + std::to_string(width) + "x" + std::to_string(height) +
                                  " pixels, channel '" + channelName(d) + "' has " + std::to_string(d.width) + "x" +
                                  std::to_string(d.height));
    const uint64_t pixels = uint64_t{width} * height;
    const uint64_t bytes = offsetof(polyloc_depth, data) + pixels * sizeof(float) * (amplitude ? 2 : 1);
    if (bytes > d.payload_max)
      raise(POLYLOC_ERR_SIZE, std::string(fn) + ": the frame does not fit channel '" + channelName(d) + "'");
    auto* p = reinterpret_cast<polyloc_depth*>(w.begin());
    p->stamp_ns = stamp_ns;
    p->width = width;
    p->height = height;
    p->has_amplitude = amplitude ? 1 : 0;
    p->reserved = 0;
    std::memcpy(p->data, depth, pixels * sizeof(float));
    if (amplitude) std::memcpy(p->data + pixels, amplitude, pixels * sizeof(float));
    w.commit(static_cast<uint32_t>(bytes), stamp_ns);
    return POLYLOC_OK;
  });
}

int polyloc_write_odometry(polyloc_client* c, int channel, int64_t stamp_ns, const double pose[7],
                           const double twist[3]) {
  return guarded([&]() -> int {
    const char* fn = "polyloc_write_odometry";
    need(pose, "pose", fn);
    Writer& w = writerOf(c, channel, POLYLOC_KIND_ODOMETRY, fn);
    polyloc_odometry o{};
    o.stamp_ns = stamp_ns;
    o.x = pose[0], o.y = pose[1], o.z = pose[2];
    o.qw = pose[3], o.qx = pose[4], o.qy = pose[5], o.qz = pose[6];
    if (twist) o.vx = twist[0], o.vy = twist[1], o.wz = twist[2];
    w.write(&o, sizeof o, stamp_ns);
    return POLYLOC_OK;
  });
}

int polyloc_write_command(polyloc_client* c, int channel, int64_t stamp_ns, double vx, double vy, double wz,
                          uint32_t nav_state, uint32_t goal, const char* status) {
  return guarded([&]() -> int {
    const char* fn = "polyloc_write_command";
    if (std::string why = polyloc::shm::commandProblem(vx, vy, wz, nav_state); !why.empty())
      raise(POLYLOC_ERR_ARGUMENT, std::string(fn) + ": " + why);
    Writer& w = writerOf(c, channel, POLYLOC_KIND_COMMAND, fn);
    polyloc_command m{};
    m.stamp_ns = stamp_ns;
    m.vx = vx, m.vy = vy, m.wz = wz;
    m.nav_state = nav_state;
    m.goal = goal;
    if (status) std::strncpy(m.status, status, sizeof m.status - 1);
    w.write(&m, sizeof m, stamp_ns);
    return POLYLOC_OK;
  });
}

int polyloc_read_command(polyloc_client* c, polyloc_command* out, polyloc_frame_info* info) {
  return guarded([&]() -> int { return readStruct(c, "cmd_vel", POLYLOC_KIND_COMMAND, true, out, info, "polyloc_read_command"); });
}

int polyloc_read_pose(polyloc_client* c, polyloc_pose* out, polyloc_frame_info* info) {
  return guarded([&]() -> int { return readStruct(c, "pose", POLYLOC_KIND_POSE, true, out, info, "polyloc_read_pose"); });
}

int polyloc_next_pose(polyloc_client* c, polyloc_pose* out, polyloc_frame_info* info) {
  return guarded([&]() -> int { return readStruct(c, "pose", POLYLOC_KIND_POSE, false, out, info, "polyloc_next_pose"); });
}

int polyloc_read_tracks(polyloc_client* c, polyloc_tracks* out, polyloc_frame_info* info) {
  return guarded([&]() -> int { return readStruct(c, "tracks", POLYLOC_KIND_TRACKS, true, out, info, "polyloc_read_tracks"); });
}

int polyloc_read_health(polyloc_client* c, polyloc_health* out, polyloc_frame_info* info) {
  return guarded([&]() -> int { return readStruct(c, "health", POLYLOC_KIND_HEALTH, true, out, info, "polyloc_read_health"); });
}

int polyloc_read_vrs(polyloc_client* c, polyloc_vrs* out, float* ranges, uint32_t capacity, uint32_t* count,
                     polyloc_frame_info* info) {
  return guarded([&]() -> int {
    const char* fn = "polyloc_read_vrs";
    need(out, "out", fn);
    need(count, "count", fn);
    if (capacity && !ranges) need(ranges, "ranges", fn);
    const int ch = findNamed(c, "vrs", fn);
    const int s = readInto(c, ch, true, info, fn);
    if (s != POLYLOC_OK) return s;
    constexpr size_t head = offsetof(polyloc_vrs, ranges);
    if (c->buf.size() < head) raise(POLYLOC_ERR_SIZE, std::string(fn) + ": a frame shorter than its header");
    std::memcpy(out, c->buf.data(), head);
    const uint64_t n = std::min<uint64_t>(out->count, (c->buf.size() - head) / sizeof(float));
    *count = static_cast<uint32_t>(n);
    if (n > capacity)
      raise(POLYLOC_ERR_SIZE, std::string(fn) + ": " + std::to_string(n) + " segments, room for " + std::to_string(capacity));
    if (n) std::memcpy(ranges, c->buf.data() + head, n * sizeof(float));
    return POLYLOC_OK;
  });
}

int polyloc_read_newest(polyloc_client* c, int channel, void* buf, uint32_t capacity, polyloc_frame_info* info) {
  return guarded([&]() -> int { return readRaw(c, channel, buf, capacity, info, true, "polyloc_read_newest"); });
}

int polyloc_read_next(polyloc_client* c, int channel, void* buf, uint32_t capacity, polyloc_frame_info* info) {
  return guarded([&]() -> int { return readRaw(c, channel, buf, capacity, info, false, "polyloc_read_next"); });
}

int polyloc_wait(polyloc_client* c, int channel, int64_t timeout_ns) {
  return polyloc_wait_spin(c, channel, timeout_ns, polyloc::shm::kDefaultSpinNs);
}

int polyloc_wait_spin(polyloc_client* c, int channel, int64_t timeout_ns, int64_t spin_ns) {
  return guarded([&]() -> int {
    channelOf(c, channel, "polyloc_wait");
    if (c->readers[channel]->wait(timeout_ns, spin_ns)) return POLYLOC_OK;
    if (timeout_ns != 0 && c->seg->stale())
      raise(POLYLOC_ERR_STALE, "polyloc_wait: " + c->seg->name() + " is stale (polylocd stopped or restarted): re-attach");
    return POLYLOC_TIMEOUT;
  });
}

}  // extern "C"
