// libFuzzer target for the CARMEN log reader: the input is the text of a log (any bytes, lines
// of any length, any numbers: 1e19, nan, -0, 1e-300). Checks: the reader never crashes or reads
// out of bounds (ASan), every message it yields holds only finite numbers within the domain a
// CARMEN line may hold (+-1e6, docs/failure.md), and every rejected line is counted with a reason.
#include <polyloc/io/recording.hpp>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <unistd.h>
#include <variant>

using namespace polyloc;

namespace {
void check(bool ok, const char* what) {
  if (ok) return;
  std::fprintf(stderr, "fuzz_carmen_lines: %s\n", what);
  std::abort();
}
bool sane(double v) { return std::isfinite(v) && std::fabs(v) <= 1e6; }
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::string path = "/tmp/fuzz_carmen_" + std::to_string(::getpid()) + ".log";
  FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return 0;
  std::fwrite(data, 1, size, f);
  std::fclose(f);
  try {
    auto reader = openCarmen(path);
    RecordedMessage m;
    while (reader->next(m)) {
      if (const auto* o = std::get_if<msg::Odometry>(&m.message)) {
        check(sane(o->pose.pose.position.x) && sane(o->pose.pose.position.y), "odometry outside the domain");
        check(std::isfinite(o->pose.pose.orientation.w), "odometry orientation not finite");
      } else if (const auto* p = std::get_if<msg::PoseStamped>(&m.message)) {
        check(sane(p->pose.position.x) && sane(p->pose.position.y), "pose outside the domain");
      } else if (const auto* s = std::get_if<msg::LaserScan>(&m.message)) {
        check(std::isfinite(s->angle_min) && std::isfinite(s->angle_increment), "scan angles not finite");
      }
    }
    const ReadStats& st = reader->stats();
    check(st.warnings.size() <= st.rejected, "a warning without a rejection");
  } catch (const std::exception&) {
    // A documented error (IoError naming the file) is a fine answer to a broken file.
  }
  return 0;
}
