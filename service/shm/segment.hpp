// One polylocd instance's shared-memory segment (bindings/c/polyloc_shm.h, docs/interface.md):
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
class ShmError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
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
  static Segment create(const std::string& instance, const std::vector<ChannelSpec>& channels);
  // A client: maps an existing segment; checks magic, ABI version, sizes, state != INITIALISING.
  static Segment attach(const std::string& instance);
  // Removes the name (polylocd at shutdown, after stop()); mapped segments stay valid.
  static void unlink(const std::string& instance);

  Segment(Segment&&) noexcept;
  Segment& operator=(Segment&&) noexcept;
  ~Segment();

  const polyloc_shm_header& header() const;
  uint32_t generation() const;   // as attached
  // True when the segment was re-created (generation changed under this name), its owner stopped
  // or died: re-attach.
  bool stale() const;
  void ready();                  // state READY (owner)
  void stop();                   // state STOPPED (owner)

  int find(const std::string& channel) const;   // index, or -1
  const polyloc_channel_desc& channel(int index) const;
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
