// Sizes and offsets of the segment layout (service/shm/include/polyloc_shm.h). The static_asserts pin
// every struct to the byte offsets docs/interface.md documents: changing one is an ABI change
// (bump POLYLOC_SHM_ABI_VERSION and the spec), never an accident.
#pragma once

#include <polyloc_shm.h>

#include <cstddef>
#include <cstdint>

namespace polyloc::shm {

inline constexpr uint64_t kAlign = 64;  // rings and slots: one cache line, no false sharing
constexpr uint64_t alignUp(uint64_t v, uint64_t a = kAlign) { return (v + a - 1) / a * a; }

// Where ring 0 starts: right after the header, 64-byte aligned.
inline constexpr uint64_t kFirstRingOffset = alignUp(sizeof(polyloc_shm_header));
// A slot holding payload_max bytes: header + payload, rounded up to 64 bytes.
constexpr uint64_t slotSize(uint64_t payload_max) { return alignUp(sizeof(polyloc_slot_header) + payload_max); }
constexpr uint64_t ringBytes(uint64_t slot_count, uint64_t slot_size) {
  return sizeof(polyloc_ring_control) + slot_count * slot_size;
}

static_assert(sizeof(polyloc_channel_desc) == 96);
static_assert(offsetof(polyloc_channel_desc, kind) == 32 && offsetof(polyloc_channel_desc, direction) == 36);
static_assert(offsetof(polyloc_channel_desc, slot_count) == 40 && offsetof(polyloc_channel_desc, slot_size) == 44);
static_assert(offsetof(polyloc_channel_desc, offset) == 48 && offsetof(polyloc_channel_desc, payload_max) == 56);
static_assert(offsetof(polyloc_channel_desc, sensor) == 60 && offsetof(polyloc_channel_desc, count) == 64);
static_assert(offsetof(polyloc_channel_desc, width) == 68 && offsetof(polyloc_channel_desc, height) == 72);

static_assert(offsetof(polyloc_shm_header, magic) == 0 && offsetof(polyloc_shm_header, abi_version) == 8);
static_assert(offsetof(polyloc_shm_header, header_size) == 12 && offsetof(polyloc_shm_header, total_size) == 16);
static_assert(offsetof(polyloc_shm_header, generation) == 24 && offsetof(polyloc_shm_header, state) == 28);
static_assert(offsetof(polyloc_shm_header, owner_pid) == 32 && offsetof(polyloc_shm_header, channel_count) == 36);
static_assert(offsetof(polyloc_shm_header, created_ns) == 40 && offsetof(polyloc_shm_header, instance) == 48);
static_assert(offsetof(polyloc_shm_header, doorbell) == 80 && offsetof(polyloc_shm_header, channels) == 104);
static_assert(sizeof(polyloc_shm_header) == 3176 && kFirstRingOffset == 3200);

static_assert(sizeof(polyloc_ring_control) == 64);
static_assert(offsetof(polyloc_ring_control, write_count) == 0 && offsetof(polyloc_ring_control, notify) == 8);
static_assert(offsetof(polyloc_ring_control, writer_pid) == 12 && offsetof(polyloc_ring_control, writer_claims) == 16);

static_assert(sizeof(polyloc_slot_header) == 64);
static_assert(offsetof(polyloc_slot_header, seq) == 0 && offsetof(polyloc_slot_header, size) == 8);
static_assert(offsetof(polyloc_slot_header, kind) == 12 && offsetof(polyloc_slot_header, stamp_ns) == 16);
static_assert(offsetof(polyloc_slot_header, publish_ns) == 24);

static_assert(offsetof(polyloc_ranges, count) == 8 && offsetof(polyloc_ranges, ranges) == 16);
static_assert(offsetof(polyloc_depth, width) == 8 && offsetof(polyloc_depth, height) == 12);
static_assert(offsetof(polyloc_depth, has_amplitude) == 16 && offsetof(polyloc_depth, data) == 24);
static_assert(sizeof(polyloc_odometry) == 88 && offsetof(polyloc_odometry, qw) == 32 && offsetof(polyloc_odometry, vx) == 64);
static_assert(sizeof(polyloc_command) == 104 && offsetof(polyloc_command, nav_state) == 32 && offsetof(polyloc_command, status) == 40);
static_assert(sizeof(polyloc_pose) == 440 && offsetof(polyloc_pose, covariance) == 64);
static_assert(offsetof(polyloc_pose, map_odom) == 352 && offsetof(polyloc_pose, status) == 408);
static_assert(offsetof(polyloc_pose, ess) == 416 && offsetof(polyloc_pose, latency_ns) == 432);
static_assert(offsetof(polyloc_vrs, angle_min) == 8 && offsetof(polyloc_vrs, count) == 24 && offsetof(polyloc_vrs, ranges) == 32);
static_assert(sizeof(polyloc_track) == 72 && offsetof(polyloc_track, x) == 8 && offsetof(polyloc_track, covariance) == 40);
static_assert(sizeof(polyloc_tracks) == 4624 && offsetof(polyloc_tracks, tracks) == 16);
static_assert(sizeof(polyloc_input_health) == 72 && offsetof(polyloc_input_health, last_stamp_ns) == 48 &&
              offsetof(polyloc_input_health, extrapolated) == 64);
static_assert(sizeof(polyloc_health) == 1792 && offsetof(polyloc_health, inputs) == 56 && offsetof(polyloc_health, input) == 64);

}  // namespace polyloc::shm
