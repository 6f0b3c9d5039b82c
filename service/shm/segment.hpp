// One polylocd instance's shared-memory segment (service/shm/include/polyloc_shm.h, docs/interface.md):
// created by polylocd with its channel table, attached by clients by instance name.
//
//   auto seg = shm::Segment::create("lab", specs);   // polylocd; bumps the generation
//   auto seg = shm::Segment::attach("lab");          // a client; throws ShmError
//   if (seg.stale()) seg = shm::Segment::attach("lab");   // polylocd restarted or stopped
#pragma once

#include <polyloc_shm.h>

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace polyloc::shm {

// Every failure to create or attach: names the segment and what was wrong (no such segment,
// bad magic, "ABI version 2, this client speaks 1", not ready, too small, ...).
// code() tells what kind of failure it was (the C ABI maps it to its error codes).
class ShmError : public std::runtime_error {
 public:
  enum class Errc {
    Other,      // anything else (a corrupt channel table, a claim lost to a take-over, ...)
    NotFound,   // no segment of that name
    Abi,        // the segment speaks another POLYLOC_SHM_ABI_VERSION
    NotReady,   // being created (magic not yet written, or state INITIALISING)
    Bad,        // not a polyloc segment, or sizes that do not add up
    Busy,       // a live process holds the writer role, or owns the segment being created
    System,     // a system call failed (permissions, memory, ...): errno text in the message
    Argument    // a bad channel spec or instance name
  };
  explicit ShmError(const std::string& what) : std::runtime_error(what) {}
  ShmError(Errc code, const std::string& what) : std::runtime_error(what), code_(code) {}
  Errc code() const { return code_; }

 private:
  Errc code_ = Errc::Other;
};

struct ChannelSpec {
  std::string name;          // < POLYLOC_NAME_LEN
  uint32_t kind = 0;         // POLYLOC_KIND_*
  uint32_t direction = POLYLOC_DIR_INPUT;
  uint32_t slot_count = 16;  // rounded up to a power of two
  uint32_t payload_max = 0;  // bytes; 0: from kind and count/width/height (payloadSize)
  int32_t sensor = -1;
  uint32_t count = 0, width = 0, height = 0;
};
// Payload bytes a frame of this spec takes at most (fixed part + arrays).
uint32_t payloadSize(const ChannelSpec& s);

// "/polyloc.<instance>" (instance: letters, digits, '_', '-', '.'; throws ShmError otherwise).
std::string segmentName(const std::string& instance);

class Segment {
 public:
  // polylocd: creates the segment (replacing one left by an earlier run: its generation + 1),
  // with state INITIALISING; call ready() when the pipeline runs, stop() at shutdown.
  // Throws ShmError (Busy) when the old segment's owner is another live process that has not
  // stopped: two daemons on one instance name would steal each other's clients.
  static Segment create(const std::string& instance, const std::vector<ChannelSpec>& channels);
  // A client: maps an existing segment; checks magic, ABI version, sizes, state != INITIALISING.
  static Segment attach(const std::string& instance);
  // Removes the name (polylocd at shutdown, after stop()); mapped segments stay valid.
  static void unlink(const std::string& instance);

  Segment(Segment&&) noexcept;
  Segment& operator=(Segment&&) noexcept;
  ~Segment();

  const polyloc_shm_header& header() const;
  const std::string& instance() const;
  const std::string& name() const;   // "/polyloc.<instance>"
  uint32_t generation() const;   // as attached
  // True when the segment was re-created (generation changed under this name), its owner stopped
  // or died: re-attach. A few system calls (kill, shm_open, pread): call it when a wait times
  // out or about once a second, not per frame.
  bool stale() const;
  void ready();                  // state READY (owner; std::logic_error for a client)
  void stop();                   // state STOPPED (owner; std::logic_error for a client)

  int find(const std::string& channel) const;   // index, or -1
  int channelCount() const;
  const polyloc_channel_desc& channel(int index) const;   // std::out_of_range for a bad index
  polyloc_ring_control* ring(int index) const;
  polyloc_slot_header* slot(int index, uint64_t frame) const;  // slot of frame n
  uint8_t* base() const;
  size_t size() const;

 private:
  Segment() = default;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace polyloc::shm
