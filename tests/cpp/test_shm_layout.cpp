// The segment layout as docs/interface.md documents it: struct sizes and field offsets, where
// rings and slots land in a real segment, and what payloadSize gives per kind.
#include "shm/layout.hpp"
#include "shm_fixtures.hpp"

#include <gtest/gtest.h>

#include <cstddef>

namespace polyloc {
namespace {

TEST(ShmLayout, StructSizesAndOffsetsAreTheDocumentedOnes) {
  EXPECT_EQ(sizeof(polyloc_shm_header), 3176u);
  EXPECT_EQ(offsetof(polyloc_shm_header, generation), 24u);   // stable across ABI versions
  EXPECT_EQ(offsetof(polyloc_shm_header, doorbell), 80u);
  EXPECT_EQ(offsetof(polyloc_shm_header, channels), 104u);
  EXPECT_EQ(sizeof(polyloc_channel_desc), 96u);
  EXPECT_EQ(offsetof(polyloc_channel_desc, offset), 48u);
  EXPECT_EQ(sizeof(polyloc_ring_control), 64u);
  EXPECT_EQ(offsetof(polyloc_ring_control, notify), 8u);
  EXPECT_EQ(offsetof(polyloc_ring_control, writer_pid), 12u);
  EXPECT_EQ(sizeof(polyloc_slot_header), 64u);
  EXPECT_EQ(offsetof(polyloc_slot_header, publish_ns), 24u);
  EXPECT_EQ(offsetof(polyloc_ranges, ranges), 16u);
  EXPECT_EQ(offsetof(polyloc_depth, data), 24u);
  EXPECT_EQ(sizeof(polyloc_odometry), 88u);
  EXPECT_EQ(sizeof(polyloc_pose), 440u);
  EXPECT_EQ(offsetof(polyloc_pose, latency_ns), 432u);
  EXPECT_EQ(offsetof(polyloc_vrs, ranges), 32u);
  EXPECT_EQ(sizeof(polyloc_track), 72u);
  EXPECT_EQ(sizeof(polyloc_tracks), 4624u);
  EXPECT_EQ(sizeof(polyloc_input_health), 64u);
  EXPECT_EQ(sizeof(polyloc_health), 1600u);
}

TEST(ShmLayout, PayloadSizePerKind) {
  using test::spec;
  EXPECT_EQ(shm::payloadSize(spec("s", POLYLOC_KIND_RANGES, 0, 8, 541)), 16u + 541 * 4);
  EXPECT_EQ(shm::payloadSize(spec("d", POLYLOC_KIND_DEPTH, 0, 8, 0, 64, 50)), 24u + 2 * 64 * 50 * 4);
  EXPECT_EQ(shm::payloadSize(spec("o", POLYLOC_KIND_ODOMETRY, 0)), 88u);
  EXPECT_EQ(shm::payloadSize(spec("p", POLYLOC_KIND_POSE, 1)), 440u);
  EXPECT_EQ(shm::payloadSize(spec("v", POLYLOC_KIND_VRS, 1, 8, 360)), 32u + 360 * 4);
  EXPECT_EQ(shm::payloadSize(spec("t", POLYLOC_KIND_TRACKS, 1)), 4624u);
  EXPECT_EQ(shm::payloadSize(spec("h", POLYLOC_KIND_HEALTH, 1)), 1600u);
  EXPECT_THROW(shm::payloadSize(spec("x", 99, 0)), shm::ShmError);
}

TEST(ShmLayout, RingsAndSlotsLandWhereTheSpecSays) {
  test::ShmName name;
  auto seg = shm::Segment::create(name, test::rigChannels());
  const polyloc_shm_header& h = seg.header();
  EXPECT_EQ(h.magic, POLYLOC_SHM_MAGIC);
  EXPECT_EQ(h.abi_version, POLYLOC_SHM_ABI_VERSION);
  EXPECT_EQ(h.header_size, sizeof(polyloc_shm_header));
  EXPECT_EQ(h.channel_count, 7u);
  EXPECT_EQ(h.total_size, seg.size());
  EXPECT_EQ(h.state, uint32_t{POLYLOC_STATE_INITIALISING});
  uint64_t offset = 3200;  // the header rounded up to 64 bytes
  for (int i = 0; i < seg.channelCount(); ++i) {
    const polyloc_channel_desc& d = seg.channel(i);
    SCOPED_TRACE(d.name);
    EXPECT_EQ(d.offset, offset);
    EXPECT_EQ(d.slot_size % 64, 0u);
    EXPECT_EQ(d.payload_max, d.slot_size - 64u);
    EXPECT_EQ(reinterpret_cast<uint8_t*>(seg.ring(i)), seg.base() + offset);
    // Slot k of the ring: after the 64-byte ring control, k * slot_size; frame n in slot n % count.
    EXPECT_EQ(reinterpret_cast<uint8_t*>(seg.slot(i, 3)), seg.base() + offset + 64 + (3 % d.slot_count) * d.slot_size);
    EXPECT_EQ(seg.slot(i, d.slot_count + 1), seg.slot(i, 1));
    EXPECT_EQ(seg.slot(i, 0)->kind, d.kind);
    offset += shm::alignUp(64 + uint64_t{d.slot_count} * d.slot_size);
  }
  EXPECT_EQ(h.total_size, offset);
  // scan/front: 16 + 541 * 4 = 2180 payload bytes -> 2244 with its header -> 2304-byte slots.
  EXPECT_EQ(seg.channel(0).slot_size, 2304u);
  EXPECT_EQ(seg.channel(0).slot_count, 8u);
}

TEST(ShmLayout, SlotCountsRoundUpToPowersOfTwo) {
  test::ShmName name;
  auto seg = shm::Segment::create(name, {test::spec("odom", POLYLOC_KIND_ODOMETRY, POLYLOC_DIR_INPUT, 5)});
  EXPECT_EQ(seg.channel(0).slot_count, 8u);
}

TEST(ShmLayout, BadChannelSpecsAreErrorsNamingTheChannel) {
  test::ShmName name;
  using test::spec;
  const auto expectError = [&](std::vector<shm::ChannelSpec> specs, const std::string& part) {
    try {
      shm::Segment::create(name, specs);
      ADD_FAILURE() << "no error for " << part;
    } catch (const shm::ShmError& e) {
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
    }
  };
  expectError({spec("odom", POLYLOC_KIND_ODOMETRY, 0), spec("odom", POLYLOC_KIND_ODOMETRY, 0)}, "'odom': the name is used twice");
  expectError({spec("", POLYLOC_KIND_ODOMETRY, 0)}, "a name needs");
  expectError({spec(std::string(40, 'x'), POLYLOC_KIND_ODOMETRY, 0)}, "a name needs");
  expectError({spec("odom", 77, 0)}, "unknown kind 77");
  expectError({spec("odom", POLYLOC_KIND_ODOMETRY, 5)}, "direction 5");
  expectError({spec("odom", POLYLOC_KIND_ODOMETRY, 0, 0)}, "slot_count 0");
  auto small = spec("scan", POLYLOC_KIND_RANGES, 0, 8, 100);
  small.payload_max = 100;
  expectError({small}, "'scan': payload_max 100 is less than");
  EXPECT_THROW(shm::segmentName("a/b"), shm::ShmError);
  EXPECT_THROW(shm::segmentName(""), shm::ShmError);
  EXPECT_EQ(shm::segmentName("lab"), "/polyloc.lab");
}

}  // namespace
}  // namespace polyloc
