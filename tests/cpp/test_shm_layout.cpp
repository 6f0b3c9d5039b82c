// The segment layout as docs/interface.md documents it: the document's tables against the
// compiled structs, where rings and slots land in a real segment (the document's example), and
// what payloadSize gives per kind.
#include "shm/layout.hpp"
#include "shm_fixtures.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cstddef>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace polyloc::t_shm_layout {  // the file's own: the suite is compiled in batches (unity build)
namespace {

// Every field of the ABI structs, as the compiler lays it out.
struct Field {
  std::string type, name;
  size_t offset, size;
};
#define POLYLOC_FIELD(T, m) Field{#T, #m, offsetof(T, m), sizeof(T::m)}
const std::vector<Field>& abiFields() {
  static const std::vector<Field> fields{
      POLYLOC_FIELD(polyloc_shm_header, magic), POLYLOC_FIELD(polyloc_shm_header, abi_version),
      POLYLOC_FIELD(polyloc_shm_header, header_size), POLYLOC_FIELD(polyloc_shm_header, total_size),
      POLYLOC_FIELD(polyloc_shm_header, generation), POLYLOC_FIELD(polyloc_shm_header, state),
      POLYLOC_FIELD(polyloc_shm_header, owner_pid), POLYLOC_FIELD(polyloc_shm_header, channel_count),
      POLYLOC_FIELD(polyloc_shm_header, created_ns), POLYLOC_FIELD(polyloc_shm_header, instance),
      POLYLOC_FIELD(polyloc_shm_header, doorbell), POLYLOC_FIELD(polyloc_shm_header, reserved),
      POLYLOC_FIELD(polyloc_shm_header, channels),
      POLYLOC_FIELD(polyloc_channel_desc, name), POLYLOC_FIELD(polyloc_channel_desc, kind),
      POLYLOC_FIELD(polyloc_channel_desc, direction), POLYLOC_FIELD(polyloc_channel_desc, slot_count),
      POLYLOC_FIELD(polyloc_channel_desc, slot_size), POLYLOC_FIELD(polyloc_channel_desc, offset),
      POLYLOC_FIELD(polyloc_channel_desc, payload_max), POLYLOC_FIELD(polyloc_channel_desc, sensor),
      POLYLOC_FIELD(polyloc_channel_desc, count), POLYLOC_FIELD(polyloc_channel_desc, width),
      POLYLOC_FIELD(polyloc_channel_desc, height), POLYLOC_FIELD(polyloc_channel_desc, reserved),
      POLYLOC_FIELD(polyloc_ring_control, write_count), POLYLOC_FIELD(polyloc_ring_control, notify),
      POLYLOC_FIELD(polyloc_ring_control, writer_pid), POLYLOC_FIELD(polyloc_ring_control, writer_claims),
      POLYLOC_FIELD(polyloc_ring_control, reserved),
      POLYLOC_FIELD(polyloc_slot_header, seq), POLYLOC_FIELD(polyloc_slot_header, size),
      POLYLOC_FIELD(polyloc_slot_header, kind), POLYLOC_FIELD(polyloc_slot_header, stamp_ns),
      POLYLOC_FIELD(polyloc_slot_header, publish_ns), POLYLOC_FIELD(polyloc_slot_header, reserved),
      POLYLOC_FIELD(polyloc_ranges, stamp_ns), POLYLOC_FIELD(polyloc_ranges, count), POLYLOC_FIELD(polyloc_ranges, reserved),
      Field{"polyloc_ranges", "ranges", offsetof(polyloc_ranges, ranges), 0},
      POLYLOC_FIELD(polyloc_depth, stamp_ns), POLYLOC_FIELD(polyloc_depth, width), POLYLOC_FIELD(polyloc_depth, height),
      POLYLOC_FIELD(polyloc_depth, has_amplitude), POLYLOC_FIELD(polyloc_depth, reserved),
      Field{"polyloc_depth", "data", offsetof(polyloc_depth, data), 0},
      POLYLOC_FIELD(polyloc_odometry, stamp_ns), POLYLOC_FIELD(polyloc_odometry, x), POLYLOC_FIELD(polyloc_odometry, qw),
      POLYLOC_FIELD(polyloc_odometry, vx),
      POLYLOC_FIELD(polyloc_command, stamp_ns), POLYLOC_FIELD(polyloc_command, vx), POLYLOC_FIELD(polyloc_command, nav_state),
      POLYLOC_FIELD(polyloc_command, goal), POLYLOC_FIELD(polyloc_command, status),
      POLYLOC_FIELD(polyloc_pose, stamp_ns), POLYLOC_FIELD(polyloc_pose, x), POLYLOC_FIELD(polyloc_pose, qw),
      POLYLOC_FIELD(polyloc_pose, covariance), POLYLOC_FIELD(polyloc_pose, map_odom), POLYLOC_FIELD(polyloc_pose, status),
      POLYLOC_FIELD(polyloc_pose, particles), POLYLOC_FIELD(polyloc_pose, ess), POLYLOC_FIELD(polyloc_pose, updates),
      POLYLOC_FIELD(polyloc_pose, latency_ns),
      POLYLOC_FIELD(polyloc_vrs, stamp_ns), POLYLOC_FIELD(polyloc_vrs, angle_min), POLYLOC_FIELD(polyloc_vrs, count),
      POLYLOC_FIELD(polyloc_vrs, enabled), Field{"polyloc_vrs", "ranges", offsetof(polyloc_vrs, ranges), 0},
      POLYLOC_FIELD(polyloc_track, id), POLYLOC_FIELD(polyloc_track, status), POLYLOC_FIELD(polyloc_track, x),
      POLYLOC_FIELD(polyloc_track, covariance),
      POLYLOC_FIELD(polyloc_tracks, stamp_ns), POLYLOC_FIELD(polyloc_tracks, count), POLYLOC_FIELD(polyloc_tracks, tracks),
      POLYLOC_FIELD(polyloc_input_health, taken), POLYLOC_FIELD(polyloc_input_health, silent),
      POLYLOC_FIELD(polyloc_input_health, map_fit_permille),
      POLYLOC_FIELD(polyloc_health, stamp_ns), POLYLOC_FIELD(polyloc_health, cycles), POLYLOC_FIELD(polyloc_health, poses),
      POLYLOC_FIELD(polyloc_health, cycle_p50_ms), POLYLOC_FIELD(polyloc_health, cycle_p99_ms),
      POLYLOC_FIELD(polyloc_health, inputs), POLYLOC_FIELD(polyloc_health, flags), POLYLOC_FIELD(polyloc_health, input),
  };
  return fields;
}
#undef POLYLOC_FIELD

const Field* findField(const std::string& type, const std::string& name) {
  for (const Field& f : abiFields())
    if (f.type == type && f.name == name) return &f;
  return nullptr;
}

const std::map<std::string, size_t>& abiSizes() {
  static const std::map<std::string, size_t> sizes{
      {"polyloc_shm_header", sizeof(polyloc_shm_header)}, {"polyloc_channel_desc", sizeof(polyloc_channel_desc)},
      {"polyloc_ring_control", sizeof(polyloc_ring_control)}, {"polyloc_slot_header", sizeof(polyloc_slot_header)},
      {"polyloc_odometry", sizeof(polyloc_odometry)}, {"polyloc_pose", sizeof(polyloc_pose)},
      {"polyloc_command", sizeof(polyloc_command)},
      {"polyloc_tracks", sizeof(polyloc_tracks)}, {"polyloc_health", sizeof(polyloc_health)},
      {"polyloc_track", sizeof(polyloc_track)}, {"polyloc_input_health", sizeof(polyloc_input_health)}};
  return sizes;
}

std::vector<std::string> cells(const std::string& row) {
  std::vector<std::string> out;
  std::stringstream ss(row.substr(1));
  for (std::string c; std::getline(ss, c, '|');) {
    const size_t a = c.find_first_not_of(' '), b = c.find_last_not_of(' ');
    out.push_back(a == std::string::npos ? "" : c.substr(a, b - a + 1));
  }
  return out;
}

std::vector<std::string> backticked(const std::string& s) {
  std::vector<std::string> out;
  static const std::regex re("`([a-z_0-9]+)");
  for (auto it = std::sregex_iterator(s.begin(), s.end(), re); it != std::sregex_iterator(); ++it) out.push_back((*it)[1]);
  return out;
}

// The documented layout (docs/interface.md) against the compiler's: the offset and size of every
// row of the four layout tables, every field of those structs documented, the struct sizes in
// the headings, and every "`field` (offset)" of the payload table. layout.hpp's static_asserts
// pin the code; this pins the document to the code.
TEST(ShmLayout, TheDocumentedLayoutIsTheCompiledOne) {
  std::ifstream in(std::string(POLYLOC_SOURCE_DIR) + "/docs/interface.md");
  ASSERT_TRUE(in) << "docs/interface.md";
  std::string line, heading_type, table_type;
  std::set<std::string> documented;
  size_t rows = 0, payload_refs = 0;
  const std::regex heading(R"(^### .*\(`(polyloc_[a-z_]+)`, (\d+) bytes\))"), payload_ref(R"(`([a-z_0-9]+)(\[[^\]]*\])?` \((\d+)[,):])");
  const std::set<std::string> payloads{"polyloc_ranges", "polyloc_depth", "polyloc_odometry", "polyloc_command", "polyloc_pose",
                                       "polyloc_vrs", "polyloc_tracks", "polyloc_health"};
  std::smatch m;
  while (std::getline(in, line)) {
    if (std::regex_search(line, m, heading)) {
      heading_type = m[1];
      EXPECT_EQ(abiSizes().at(heading_type), std::stoul(m[2])) << line;
      continue;
    }
    if (line.rfind("| offset | size |", 0) == 0) {
      const std::string what = cells(line)[2];
      table_type = what == "ring control" ? "polyloc_ring_control" : what == "slot header" ? "polyloc_slot_header" : heading_type;
      continue;
    }
    if (line.empty() || line[0] != '|') {
      table_type.clear();
      continue;
    }
    const std::vector<std::string> c = cells(line);
    if (!table_type.empty() && c.size() >= 3 && !c[0].empty() && std::isdigit(static_cast<unsigned char>(c[0][0]))) {
      // | offset | size (or "32 x 96") | `field`[, `field`] | meaning |
      size_t size = 1;
      std::stringstream ss(c[1]);
      for (std::string f; ss >> f;)
        if (f != "x") size *= std::stoul(f);
      size_t total = 0;
      const std::vector<std::string> names = backticked(c[2]);
      ASSERT_FALSE(names.empty()) << line;
      for (const std::string& n : names) {
        const Field* f = findField(table_type, n);
        ASSERT_NE(f, nullptr) << table_type << "." << n << " is documented but not in the struct";
        total += f->size;
        documented.insert(table_type + "." + n);
      }
      EXPECT_EQ(findField(table_type, names[0])->offset, std::stoul(c[0])) << table_type << "." << names[0];
      EXPECT_EQ(total, size) << line;
      ++rows;
      continue;
    }
    if (c.size() >= 3 && c[0].size() > 2 && payloads.count(c[0].substr(1, c[0].size() - 2))) {
      // | `polyloc_pose` | 440 | `stamp_ns` ..., `latency_ns` (432): ... |
      const std::string type = c[0].substr(1, c[0].size() - 2);
      if (abiSizes().count(type) && std::all_of(c[1].begin(), c[1].end(), ::isdigit)) {
        EXPECT_EQ(abiSizes().at(type), std::stoul(c[1])) << type;
      }
      const std::string& text = c[2];
      for (auto it = std::sregex_iterator(text.begin(), text.end(), payload_ref); it != std::sregex_iterator(); ++it) {
        const std::string name = (*it)[1];
        const size_t at = static_cast<size_t>(it->position(0));
        if (at >= 3 && text.compare(at - 3, 3, "`, ") == 0) continue;  // "`width`, `height` (8, 12)": one offset each, in order
        const Field* f = findField(type, name);
        if (!f) f = findField("polyloc_track", name);  // the track fields are described inside polyloc_tracks' row
        if (!f) f = findField("polyloc_input_health", name);
        if (!f) continue;  // fields documented by a range ("8..20") are not pinned here
        EXPECT_EQ(f->offset, std::stoul((*it)[3])) << type << ": `" << name << "`";
        ++payload_refs;
      }
    }
  }
  EXPECT_EQ(rows, 13u + 11u + 5u + 6u) << "rows of the header, channel, ring and slot tables";
  EXPECT_GE(payload_refs, 23u);  // as many as the payload table pins today
  for (const Field& f : abiFields())
    if (f.type == "polyloc_shm_header" || f.type == "polyloc_channel_desc" || f.type == "polyloc_ring_control" ||
        f.type == "polyloc_slot_header") {
      EXPECT_TRUE(documented.count(f.type + "." + f.name)) << f.type << "." << f.name << " is not in docs/interface.md";
    }
}

TEST(ShmLayout, PayloadSizePerKind) {
  using test::spec;
  EXPECT_EQ(shm::payloadSize(spec("s", POLYLOC_KIND_RANGES, 0, 8, 541)), 16u + 541 * 4);
  EXPECT_EQ(shm::payloadSize(spec("d", POLYLOC_KIND_DEPTH, 0, 8, 0, 64, 50)), 24u + 2 * 64 * 50 * 4);
  EXPECT_EQ(shm::payloadSize(spec("o", POLYLOC_KIND_ODOMETRY, 0)), 88u);
  EXPECT_EQ(shm::payloadSize(spec("c", POLYLOC_KIND_COMMAND, 0)), 104u);
  EXPECT_EQ(shm::payloadSize(spec("p", POLYLOC_KIND_POSE, 1)), 440u);
  EXPECT_EQ(shm::payloadSize(spec("v", POLYLOC_KIND_VRS, 1, 8, 360)), 32u + 360 * 4);
  EXPECT_EQ(shm::payloadSize(spec("t", POLYLOC_KIND_TRACKS, 1)), 4624u);
  EXPECT_EQ(shm::payloadSize(spec("h", POLYLOC_KIND_HEALTH, 1)), 1792u);
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
