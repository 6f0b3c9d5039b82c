// openRecording: which reader a path needs, by content first (MCAP magic, sqlite header) and
// then by name (bag directory, metadata.yaml, .db3, CARMEN extensions), and last by a sniff of
// the first message line for CARMEN logs without a telling extension.
#include <polyloc/io/recording.hpp>
#include <polyloc/io/rgbd_dataset.hpp>

#include <zlib.h>

#include <algorithm>
#include <cctype>
#include <array>
#include <filesystem>
#include <fstream>
#include <string_view>

namespace polyloc {
namespace {

namespace fs = std::filesystem;

std::string firstBytes(const std::string& path, size_t n) {
  std::ifstream in(path, std::ios::binary);
  std::string s(n, '\0');
  in.read(s.data(), static_cast<std::streamsize>(n));
  s.resize(static_cast<size_t>(std::max<std::streamsize>(in.gcount(), 0)));
  return s;
}

// True if the first line that is neither blank nor a '#' comment starts with a CARMEN message
// name. Reads through zlib, so a gzip log with an unusual name is found too.
bool looksLikeCarmen(const std::string& path) {
  static const std::array<std::string_view, 14> keywords = {
      "FLASER", "RLASER",    "ODOM",      "ROBOTLASER1", "ROBOTLASER2", "PARAM",     "SYNC",
      "TRUEPOS", "RAWLASER1", "RAWLASER2", "RAWLASER3",   "RAWLASER4",   "NMEAGGA", "NMEARMC"};
  gzFile f = gzopen(path.c_str(), "rb");
  if (!f) return false;
  std::string head(1 << 16, '\0');
  const int n = gzread(f, head.data(), static_cast<unsigned>(head.size()));
  gzclose(f);
  if (n <= 0) return false;
  head.resize(static_cast<size_t>(n));
  std::string_view rest(head);
  while (!rest.empty()) {
    const size_t eol = rest.find('\n');
    std::string_view line = rest.substr(0, eol);
    rest = eol == std::string_view::npos ? std::string_view{} : rest.substr(eol + 1);
    const size_t start = line.find_first_not_of(" \t\r");
    if (start == std::string_view::npos || line[start] == '#') continue;
    line.remove_prefix(start);
    const std::string_view word = line.substr(0, line.find_first_of(" \t\r"));
    return std::find(keywords.begin(), keywords.end(), word) != keywords.end();
  }
  return false;
}

}  // namespace

std::unique_ptr<RecordingReader> openRecording(const std::string& path) {
  std::error_code ec;
  const fs::path p(path);
  if (!fs::exists(p, ec)) throw IoError(path + ": does not exist");
  const std::string unreadable =
      path + ": not a recording polyloc can read (MCAP, ROS 2 bag, CARMEN log, TUM RGB-D or 7-Scenes folder)";
  if (fs::is_directory(p, ec)) {
    if (fs::exists(p / "metadata.yaml", ec)) return openRos2Bag(path);
    for (const auto& e : fs::directory_iterator(p, ec))
      if (e.path().extension() == ".db3") return openRos2Bag(path);
    if (isTumRgbd(path)) return openTumRgbd(path);
    if (isSevenScenes(path)) return openSevenScenes(path);
    throw IoError(unreadable);
  }
  const std::string magic = firstBytes(path, 16);
  if (magic.starts_with(std::string_view("\x89MCAP0\r\n", 8))) return openMcap(path);
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (p.filename() == "metadata.yaml" || ext == ".db3" ||
      magic == std::string_view("SQLite format 3\0", 16))
    return openRos2Bag(path);
  // .txt is too common (TUM trajectories, notes) to mean CARMEN by name alone: look inside.
  if (ext == ".log" || ext == ".clf" || ext == ".gz" || looksLikeCarmen(path))
    return openCarmen(path);
  throw IoError(unreadable);
}

RecordingSpan spanOf(const std::vector<TopicInfo>& topics) {
  RecordingSpan r;
  for (const TopicInfo& t : topics) {
    r.messages += t.count;
    if (t.count && (r.first_ns == 0 || t.first_ns < r.first_ns)) r.first_ns = t.first_ns;
    r.last_ns = std::max(r.last_ns, t.last_ns);
  }
  return r;
}

}  // namespace polyloc
