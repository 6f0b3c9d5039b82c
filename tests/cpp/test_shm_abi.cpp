// What attach refuses, each with a message naming the segment and what was wrong: another ABI
// version, a foreign object, sizes that do not add up, a corrupt channel table.
#include "shm/layout.hpp"
#include "shm_fixtures.hpp"

#include <gtest/gtest.h>

#include <fcntl.h>
#include <sys/mman.h>
#include <unistd.h>

namespace polyloc::t_shm_abi {  // the file's own: the suite is compiled in batches (unity build)
namespace {

using shm::Segment;
using shm::ShmError;

// attach's error: its code and message.
ShmError attachError(const std::string& name) {
  try {
    Segment::attach(name);
  } catch (const ShmError& e) {
    return e;
  }
  ADD_FAILURE() << "attach succeeded";
  return ShmError("none");
}

bool contains(const ShmError& e, const std::string& part) { return std::string(e.what()).find(part) != std::string::npos; }

TEST(ShmAbi, AnotherAbiVersionIsRefusedNamingBoth) {
  test::ShmName name;
  auto seg = Segment::create(name, test::rigChannels());
  seg.ready();
  reinterpret_cast<polyloc_shm_header*>(seg.base())->abi_version = POLYLOC_SHM_ABI_VERSION + 1;
  const ShmError e = attachError(name);
  EXPECT_EQ(e.code(), ShmError::Errc::Abi);
  EXPECT_TRUE(contains(e, "segment /polyloc." + name.str() + " has ABI version 3; this client speaks 2")) << e.what();
}

TEST(ShmAbi, ForeignOrBrokenSegmentsAreRefused) {
  test::ShmName name;
  auto seg = Segment::create(name, test::rigChannels());
  seg.ready();
  auto* h = reinterpret_cast<polyloc_shm_header*>(seg.base());
  const polyloc_shm_header saved = *h;
  const auto expect = [&](ShmError::Errc code, const std::string& part) {
    const ShmError e = attachError(name);
    EXPECT_EQ(e.code(), code) << e.what();
    EXPECT_TRUE(contains(e, part)) << e.what();
    *h = saved;
  };
  h->magic = 0x1234;
  expect(ShmError::Errc::Bad, "is not a polyloc segment (magic 0x0000000000001234");
  h->magic = 0;
  expect(ShmError::Errc::NotReady, "being created");
  h->header_size = 100;
  expect(ShmError::Errc::Bad, "header_size 100, expected 3176");
  h->total_size += 64;
  expect(ShmError::Errc::Bad, "but the object has");
  h->state = 9;
  expect(ShmError::Errc::Bad, "unknown state 9");
  h->channel_count = 40;
  expect(ShmError::Errc::Bad, "channel_count 40");
  h->channels[2].slot_count = 3;
  expect(ShmError::Errc::Bad, "channel 2 'odom': slot_count 3 is not a power of two");
  h->channels[1].offset = saved.total_size - 64;
  expect(ShmError::Errc::Bad, "channel 1 'depth/tof': its ring at offset");
  h->channels[0].payload_max = h->channels[0].slot_size;
  expect(ShmError::Errc::Bad, "channel 0 'scan/front': payload_max");
  EXPECT_NO_THROW(Segment::attach(name));
}

TEST(ShmAbi, TooSmallObjectIsRefused) {
  test::ShmName name;
  const std::string path = shm::segmentName(name);
  const int fd = shm_open(path.c_str(), O_CREAT | O_RDWR, 0600);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(ftruncate(fd, 100), 0);
  close(fd);
  const ShmError e = attachError(name);
  EXPECT_EQ(e.code(), ShmError::Errc::Bad);
  EXPECT_TRUE(contains(e, "has 100 bytes, less than its header's 3176")) << e.what();
  // create() replaces a foreign object under the name.
  auto seg = Segment::create(name, test::rigChannels());
  EXPECT_EQ(seg.generation(), 1u);
}

}  // namespace
}  // namespace polyloc
