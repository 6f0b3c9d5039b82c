// The MCAP reader streams: reading a recording of 200 MB of image data must not raise the peak
// resident memory by more than a few chunks. The images are cheap to compress, so the file is
// small and the test fast.
#include "temp_dir.hpp"

#include <polyloc/io/recording.hpp>

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_mcap_memory {

using namespace polyloc;


// A field of /proc/self/status in kB ("VmHWM", "VmRSS"); -1 where there is none.
long statusKb(const std::string& key) {
  std::ifstream in("/proc/self/status");
  for (std::string line; std::getline(in, line);)
    if (line.rfind(key + ":", 0) == 0) return std::stol(line.substr(key.size() + 1));
  return -1;
}

// Resets VmHWM to the current RSS (Linux >= 4.0), so the peak measured is the reader's alone.
bool resetPeak() {
  std::ofstream out("/proc/self/clear_refs");
  out << "5";
  out.flush();
  return bool(out);
}


TEST(McapMemory, ReadingStaysFlat) {
  if (statusKb("VmHWM") < 0) GTEST_SKIP() << "no /proc/self/status";
  test::TempDir dir;
  const std::string path = dir.file("big.mcap");
  const size_t width = 1024, height = 512;  // 2 MiB of 32FC1 per image
  const int images = 100;                   // 200 MiB in all
  {
    auto w = createMcap(path, {"zstd", 1 << 20});
    msg::Image img;
    img.header.frame_id = "tof";
    img.height = static_cast<uint32_t>(height);
    img.width = static_cast<uint32_t>(width);
    img.encoding = "32FC1";
    img.step = static_cast<uint32_t>(width * 4);
    img.data.resize(width * height * 4);
    for (int i = 0; i < images; ++i) {
      for (size_t r = 0; r < height; r += 64) img.data[r * width * 4] = static_cast<uint8_t>(i + r);
      img.header.stamp = msg::fromNs(int64_t{i} * 50000000);
      w->write("/tof/depth", int64_t{i} * 50000000, img);
    }
    w->close();
  }
  const bool reset = resetPeak();
  const long before = reset ? statusKb("VmRSS") : statusKb("VmHWM");
  auto r = openMcap(path);
  RecordedMessage m;
  uint64_t count = 0, bytes = 0;
  while (r->next(m)) ++count, bytes += std::get<msg::Image>(m.message).data.size();
  const long growth_kb = statusKb("VmHWM") - before;
  EXPECT_EQ(count, uint64_t(images));
  EXPECT_EQ(bytes, uint64_t(images) * width * height * 4);
  EXPECT_TRUE(r->stats().warnings.empty());
  // One image is 2 MiB: a chunk compressed and decompressed, the decoded message and the one
  // handed out before it come to about 8 MiB; 24 MiB leaves room for the allocator.
  std::cout << "[ McapMemory ] read " << (bytes >> 20) << " MiB of images; peak RSS grew by "
            << growth_kb / 1024.0 << " MiB" << (reset ? "" : " (peak not resettable: upper bound)") << "\n";
  RecordProperty("peak_rss_growth_kb", std::to_string(growth_kb));
#if defined(__SANITIZE_ADDRESS__)
  // ASan holds freed blocks in its quarantine (256 MiB): the peak measures the sanitizer there.
  std::cout << "[ McapMemory ] AddressSanitizer: peak not checked\n";
#else
  EXPECT_LT(growth_kb, 24 * 1024);
#endif
}

}  // namespace polyloc::t_mcap_memory
