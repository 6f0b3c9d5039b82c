// Segment: create (polylocd), attach (clients), staleness. docs/interface.md, "Segment".
#include "shm/segment.hpp"

#include "shm/atomic.hpp"
#include "shm/layout.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <bit>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <set>
#include <stdexcept>

namespace polyloc::shm {
namespace {

using Errc = ShmError::Errc;

std::string sysText(const std::string& what, int err) { return what + ": " + std::strerror(err); }

std::string hex(uint64_t v) {
  char buf[24];
  std::snprintf(buf, sizeof buf, "0x%016llx", static_cast<unsigned long long>(v));
  return buf;
}

std::string fieldName(const char* field, size_t n) { return std::string(field, strnlen(field, n)); }

bool processGone(int32_t pid) { return pid > 0 && kill(pid, 0) == -1 && errno == ESRCH; }

int64_t realtimeNs() {
  timespec ts{};
  clock_gettime(CLOCK_REALTIME, &ts);
  return int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec;
}

// The channel table and total size of a segment with these channels (offsets filled in).
uint64_t layoutChannels(const std::string& seg, const std::vector<ChannelSpec>& specs,
                        std::vector<polyloc_channel_desc>& out) {
  if (specs.size() > POLYLOC_MAX_CHANNELS)
    throw ShmError(Errc::Argument, seg + ": " + std::to_string(specs.size()) + " channels, at most " +
                                       std::to_string(POLYLOC_MAX_CHANNELS));
  std::set<std::string> names;
  uint32_t inputs = 0;
  uint64_t offset = kFirstRingOffset;
  for (const ChannelSpec& s : specs) {
    const std::string where = seg + " channel '" + s.name + "'";
    if (s.name.empty() || s.name.size() >= POLYLOC_NAME_LEN)
      throw ShmError(Errc::Argument, where + ": a name needs 1 to " + std::to_string(POLYLOC_NAME_LEN - 1) + " characters");
    if (!names.insert(s.name).second) throw ShmError(Errc::Argument, where + ": the name is used twice");
    if (s.direction != POLYLOC_DIR_INPUT && s.direction != POLYLOC_DIR_OUTPUT)
      throw ShmError(Errc::Argument, where + ": direction " + std::to_string(s.direction) + " (0 input, 1 output)");
    if (s.slot_count == 0 || s.slot_count > (1u << 16))
      throw ShmError(Errc::Argument, where + ": slot_count " + std::to_string(s.slot_count) + " (1 to 65536)");
    inputs += s.direction == POLYLOC_DIR_INPUT;
    const uint32_t need = payloadSize(s);
    if (s.payload_max && s.payload_max < need)
      throw ShmError(Errc::Argument, where + ": payload_max " + std::to_string(s.payload_max) +
                                         " is less than a frame of it takes (" + std::to_string(need) + " bytes)");
    polyloc_channel_desc d{};
    std::memcpy(d.name, s.name.data(), s.name.size());
    d.kind = s.kind;
    d.direction = s.direction;
    d.slot_count = std::bit_ceil(s.slot_count);
    d.payload_max = s.payload_max ? s.payload_max : need;
    const uint64_t slot = slotSize(d.payload_max);
    if (slot > UINT32_MAX) throw ShmError(Errc::Argument, where + ": payload_max too large");
    d.slot_size = static_cast<uint32_t>(slot);
    d.payload_max = d.slot_size - sizeof(polyloc_slot_header);  // the padding is usable too
    d.offset = offset;
    d.sensor = s.sensor;
    d.count = s.count;
    d.width = s.width;
    d.height = s.height;
    offset += alignUp(ringBytes(d.slot_count, d.slot_size));
    out.push_back(d);
  }
  if (inputs > POLYLOC_MAX_INPUTS)  // health reports one entry per input
    throw ShmError(Errc::Argument, seg + ": " + std::to_string(inputs) + " input channels, at most " +
                                       std::to_string(POLYLOC_MAX_INPUTS));
  return offset;
}

// An earlier run's segment under this name: its generation (0: none), marked STOPPED so that its
// clients notice at once, then unlinked. Refuses while another live process owns it.
uint32_t retire(const std::string& name) {
  const int fd = shm_open(name.c_str(), O_RDWR, 0);
  if (fd < 0) {
    if (errno == ENOENT) return 0;
    throw ShmError(Errc::System, sysText("cannot open the existing segment " + name + " to replace it", errno));
  }
  uint32_t generation = 0;
  struct stat st {};
  if (fstat(fd, &st) == 0 && static_cast<size_t>(st.st_size) >= sizeof(polyloc_shm_header)) {
    void* p = mmap(nullptr, sizeof(polyloc_shm_header), PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
    if (p != MAP_FAILED) {
      auto* h = static_cast<polyloc_shm_header*>(p);
      // magic and generation keep their offsets in every ABI version (docs/interface.md).
      if (atomic::loadAcquire(&h->magic) == POLYLOC_SHM_MAGIC) {
        generation = atomic::loadAcquire(&h->generation);
        const int32_t owner = atomic::loadRelaxed(&h->owner_pid);
        const uint32_t state = atomic::loadAcquire(&h->state);
        if (state != POLYLOC_STATE_STOPPED && owner > 0 && owner != getpid() && !processGone(owner)) {
          munmap(p, sizeof(polyloc_shm_header));
          close(fd);
          throw ShmError(Errc::Busy, "segment " + name + " is in use by running process " + std::to_string(owner) +
                                         " (generation " + std::to_string(generation) + "); stop it first");
        }
        atomic::storeRelease(&h->state, uint32_t{POLYLOC_STATE_STOPPED});
      }
      munmap(p, sizeof(polyloc_shm_header));
    }
  }
  close(fd);
  if (shm_unlink(name.c_str()) != 0 && errno != ENOENT)
    throw ShmError(Errc::System, sysText("cannot unlink the old segment " + name, errno));
  return generation;
}

// The channel table as attach copies and checks it, before anyone dereferences an offset from it.
std::vector<polyloc_channel_desc> checkedChannels(const std::string& name, const polyloc_shm_header& h, uint64_t size) {
  const uint32_t count = atomic::loadRelaxed(&h.channel_count);
  if (count > POLYLOC_MAX_CHANNELS)
    throw ShmError(Errc::Bad, "segment " + name + ": channel_count " + std::to_string(count) +
                                  " exceeds " + std::to_string(POLYLOC_MAX_CHANNELS));
  std::vector<polyloc_channel_desc> table(h.channels, h.channels + count);
  for (uint32_t i = 0; i < count; ++i) {
    const polyloc_channel_desc& d = table[i];
    const std::string where = "segment " + name + " channel " + std::to_string(i) + " '" +
                              fieldName(d.name, POLYLOC_NAME_LEN) + "'";
    if (d.slot_count == 0 || !std::has_single_bit(d.slot_count))
      throw ShmError(Errc::Bad, where + ": slot_count " + std::to_string(d.slot_count) + " is not a power of two");
    if (d.slot_size < sizeof(polyloc_slot_header) || d.slot_size % kAlign)
      throw ShmError(Errc::Bad, where + ": slot_size " + std::to_string(d.slot_size) + " is not a multiple of 64 above 64");
    if (d.payload_max > d.slot_size - sizeof(polyloc_slot_header))
      throw ShmError(Errc::Bad, where + ": payload_max " + std::to_string(d.payload_max) + " exceeds its slots");
    if (d.offset < kFirstRingOffset || d.offset % kAlign || d.offset > size ||
        ringBytes(d.slot_count, d.slot_size) > size - d.offset)
      throw ShmError(Errc::Bad, where + ": its ring at offset " + std::to_string(d.offset) +
                                    " does not fit the segment's " + std::to_string(size) + " bytes");
  }
  return table;
}

}  // namespace

struct Segment::Impl {
  std::string instance, name;
  uint8_t* base = nullptr;
  size_t size = 0;
  uint32_t generation = 0;
  bool owner = false;
  // A private copy of the checked channel table: offsets are never read again from memory that
  // any client may write.
  std::vector<polyloc_channel_desc> channels;
  dev_t dev = 0;
  ino_t ino = 0;

  ~Impl() {
    if (base) munmap(base, size);
  }
  polyloc_shm_header* header() const { return reinterpret_cast<polyloc_shm_header*>(base); }
  // Maps the whole object of fd (closes fd in any case).
  void map(int fd, const std::string& what) {
    struct stat st {};
    if (fstat(fd, &st) != 0) {
      const int e = errno;
      close(fd);
      throw ShmError(Errc::System, sysText("cannot stat " + what, e));
    }
    dev = st.st_dev;
    ino = st.st_ino;
    size = static_cast<size_t>(st.st_size);
    if (size < sizeof(polyloc_shm_header)) {
      close(fd);
      throw ShmError(size == 0 ? Errc::NotReady : Errc::Bad,
                     "segment " + name + " has " + std::to_string(size) + " bytes, less than its header's " +
                         std::to_string(sizeof(polyloc_shm_header)));
    }
    void* p = mmap(nullptr, size, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
    const int e = errno;
    close(fd);
    if (p == MAP_FAILED) throw ShmError(Errc::System, sysText("cannot map " + what, e));
    base = static_cast<uint8_t*>(p);
  }
};

std::string segmentName(const std::string& instance) {
  if (instance.empty() || instance.size() >= POLYLOC_NAME_LEN)
    throw ShmError(Errc::Argument, "instance name '" + instance + "': 1 to " +
                                       std::to_string(POLYLOC_NAME_LEN - 1) + " characters");
  for (char c : instance)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.'))
      throw ShmError(Errc::Argument, "instance name '" + instance + "': only letters, digits, '_', '-' and '.'");
  return "/polyloc." + instance;
}

Segment Segment::create(const std::string& instance, const std::vector<ChannelSpec>& channels) {
  const std::string name = segmentName(instance);
  std::vector<polyloc_channel_desc> descs;
  const uint64_t total = layoutChannels(name, channels, descs);
  const uint32_t old_generation = retire(name);

  // A new object, not the old one resized: clients of the old run keep a valid mapping.
  const int fd = shm_open(name.c_str(), O_CREAT | O_EXCL | O_RDWR, 0660);
  if (fd < 0) throw ShmError(Errc::System, sysText("cannot create segment " + name, errno));
  // Reserve the pages now: a full /dev/shm is an error here, not a SIGBUS in the first write.
  if (ftruncate(fd, static_cast<off_t>(total)) != 0 || (errno = posix_fallocate(fd, 0, static_cast<off_t>(total))) != 0) {
    const int e = errno;
    close(fd);
    shm_unlink(name.c_str());
    throw ShmError(Errc::System, sysText("cannot size segment " + name + " to " + std::to_string(total) + " bytes", e));
  }
  Segment seg;
  seg.impl_ = std::make_unique<Impl>();
  Impl& m = *seg.impl_;
  m.instance = instance;
  m.name = name;
  m.owner = true;
  try {
    m.map(fd, "segment " + name);
  } catch (...) {
    shm_unlink(name.c_str());
    throw;
  }

  polyloc_shm_header& h = *m.header();
  h.abi_version = POLYLOC_SHM_ABI_VERSION;
  h.header_size = sizeof(polyloc_shm_header);
  h.total_size = total;
  h.generation = old_generation + 1 ? old_generation + 1 : 1;  // 0 reads as "none"
  h.state = POLYLOC_STATE_INITIALISING;
  h.owner_pid = getpid();
  h.channel_count = static_cast<uint32_t>(descs.size());
  h.created_ns = realtimeNs();
  std::memcpy(h.instance, instance.data(), instance.size());
  m.channels = descs;
  for (size_t i = 0; i < descs.size(); ++i) {
    h.channels[i] = descs[i];
    for (uint32_t k = 0; k < descs[i].slot_count; ++k) seg.slot(static_cast<int>(i), k)->kind = descs[i].kind;
  }
  m.generation = h.generation;
  // Last, with release order: a client that sees the magic sees everything above.
  atomic::storeRelease(&h.magic, POLYLOC_SHM_MAGIC);
  return seg;
}

Segment Segment::attach(const std::string& instance) {
  const std::string name = segmentName(instance);
  const int fd = shm_open(name.c_str(), O_RDWR, 0);
  if (fd < 0) {
    if (errno == ENOENT)
      throw ShmError(Errc::NotFound, "segment " + name + " does not exist (is polylocd running for instance '" +
                                         instance + "'?)");
    throw ShmError(Errc::System, sysText("cannot open segment " + name, errno));
  }
  Segment seg;
  seg.impl_ = std::make_unique<Impl>();
  Impl& m = *seg.impl_;
  m.instance = instance;
  m.name = name;
  m.map(fd, "segment " + name);

  const polyloc_shm_header& h = *m.header();
  const uint64_t magic = atomic::loadAcquire(&h.magic);
  if (magic == 0) throw ShmError(Errc::NotReady, "segment " + name + " is being created (no magic yet); retry");
  if (magic != POLYLOC_SHM_MAGIC)
    throw ShmError(Errc::Bad, "segment " + name + " is not a polyloc segment (magic " + hex(magic) + ", expected " +
                                  hex(POLYLOC_SHM_MAGIC) + ")");
  if (h.abi_version != POLYLOC_SHM_ABI_VERSION)
    throw ShmError(Errc::Abi, "segment " + name + " has ABI version " + std::to_string(h.abi_version) +
                                  "; this client speaks " + std::to_string(POLYLOC_SHM_ABI_VERSION));
  if (h.header_size != sizeof(polyloc_shm_header))
    throw ShmError(Errc::Bad, "segment " + name + ": header_size " + std::to_string(h.header_size) + ", expected " +
                                  std::to_string(sizeof(polyloc_shm_header)));
  if (h.total_size != m.size)
    throw ShmError(Errc::Bad, "segment " + name + ": total_size " + std::to_string(h.total_size) +
                                  " but the object has " + std::to_string(m.size) + " bytes");
  const uint32_t state = atomic::loadAcquire(&h.state);
  if (state == POLYLOC_STATE_INITIALISING)
    throw ShmError(Errc::NotReady, "segment " + name + " is initialising (polylocd is starting); retry");
  if (state > POLYLOC_STATE_STOPPED)
    throw ShmError(Errc::Bad, "segment " + name + ": unknown state " + std::to_string(state));
  m.channels = checkedChannels(name, h, m.size);
  m.generation = atomic::loadAcquire(&h.generation);
  return seg;
}

void Segment::unlink(const std::string& instance) {
  const std::string name = segmentName(instance);
  if (shm_unlink(name.c_str()) != 0 && errno != ENOENT)
    throw ShmError(Errc::System, sysText("cannot unlink segment " + name, errno));
}

Segment::Segment(Segment&&) noexcept = default;
Segment& Segment::operator=(Segment&&) noexcept = default;
Segment::~Segment() = default;

const polyloc_shm_header& Segment::header() const { return *impl_->header(); }
const std::string& Segment::instance() const { return impl_->instance; }
const std::string& Segment::name() const { return impl_->name; }
uint32_t Segment::generation() const { return impl_->generation; }

bool Segment::stale() const {
  const polyloc_shm_header& h = header();
  if (atomic::loadAcquire(&h.state) == POLYLOC_STATE_STOPPED) return true;
  if (processGone(atomic::loadRelaxed(&h.owner_pid))) return true;
  // The name may now hold another object (a restart whose replacement we could not mark).
  const int fd = shm_open(impl_->name.c_str(), O_RDONLY, 0);
  if (fd < 0) return errno == ENOENT;  // other failures (EMFILE) say nothing about the segment
  struct stat st {};
  uint32_t generation = 0;
  const bool same = fstat(fd, &st) == 0 && st.st_dev == impl_->dev && st.st_ino == impl_->ino &&
                    pread(fd, &generation, sizeof generation, offsetof(polyloc_shm_header, generation)) ==
                        static_cast<ssize_t>(sizeof generation) &&
                    generation == impl_->generation;
  close(fd);
  return !same;
}

void Segment::ready() {
  if (!impl_->owner) throw std::logic_error("segment " + impl_->name + ": only its creator sets it ready");
  atomic::storeRelease(&impl_->header()->state, uint32_t{POLYLOC_STATE_READY});
}

void Segment::stop() {
  if (!impl_->owner) throw std::logic_error("segment " + impl_->name + ": only its creator stops it");
  atomic::storeRelease(&impl_->header()->state, uint32_t{POLYLOC_STATE_STOPPED});
}

int Segment::find(const std::string& channel) const {
  for (size_t i = 0; i < impl_->channels.size(); ++i)
    if (fieldName(impl_->channels[i].name, POLYLOC_NAME_LEN) == channel) return static_cast<int>(i);
  return -1;
}

int Segment::channelCount() const { return static_cast<int>(impl_->channels.size()); }

const polyloc_channel_desc& Segment::channel(int index) const {
  if (index < 0 || index >= channelCount())
    throw std::out_of_range("segment " + impl_->name + ": no channel " + std::to_string(index) + " (it has " +
                            std::to_string(channelCount()) + ")");
  return impl_->channels[index];
}

polyloc_ring_control* Segment::ring(int index) const {
  return reinterpret_cast<polyloc_ring_control*>(impl_->base + channel(index).offset);
}

polyloc_slot_header* Segment::slot(int index, uint64_t frame) const {
  const polyloc_channel_desc& d = channel(index);
  const uint64_t k = frame & (d.slot_count - 1);
  return reinterpret_cast<polyloc_slot_header*>(impl_->base + d.offset + sizeof(polyloc_ring_control) + k * d.slot_size);
}

uint8_t* Segment::base() const { return impl_->base; }
size_t Segment::size() const { return impl_->size; }

}  // namespace polyloc::shm
