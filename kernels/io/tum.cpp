// TUM trajectory files. Time is kept as exact decimal text <-> int64 ns (no double rounding);
// positions and quaternions are written with 9 decimals (1 nm, far below any sensor's noise).
#include <polyloc/io/tum.hpp>

#include "decimal_seconds.hpp"

#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <string_view>

namespace polyloc {
namespace {

constexpr size_t kMaxWarnings = 100;  // as ReadStats: count all, keep the first few

bool parseDouble(std::string_view s, double& v) {
  auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  return ec == std::errc() && p == s.data() + s.size() && std::isfinite(v);
}

// Splits on spaces, tabs and commas (some tools write comma-separated TUM).
size_t split(std::string_view line, std::array<std::string_view, 9>& out) {
  size_t n = 0, i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == ',' || line[i] == '\r')) ++i;
    if (i == line.size()) break;
    size_t j = i;
    while (j < line.size() && line[j] != ' ' && line[j] != '\t' && line[j] != ',' && line[j] != '\r') ++j;
    if (n < out.size()) out[n] = line.substr(i, j - i);
    ++n;
    i = j;
  }
  return n;
}

}  // namespace

TumReader::TumReader(const std::string& path) : path_(path), in_(path) {
  if (!in_) throw IoError(path + ": cannot open TUM trajectory file");
}

bool TumReader::next(StampedPose& out) {
  std::string line;
  while (std::getline(in_, line)) {
    ++line_;
    std::string_view v(line);
    const size_t start = v.find_first_not_of(" \t\r");
    if (start == std::string_view::npos || v[start] == '#') continue;  // blank or comment
    auto bad = [&](const std::string& why) {
      ++rejected_;
      if (warnings_.size() < kMaxWarnings)
        warnings_.push_back(path_ + ":" + std::to_string(line_) + ": " + why);
    };
    std::array<std::string_view, 9> f;
    const size_t n = split(v, f);
    if (n != 8) {
      bad("expected 8 fields (timestamp x y z qx qy qz qw), got " + std::to_string(n));
      continue;
    }
    const auto stamp = io_detail::parseSecondsNs(f[0]);
    if (!stamp) {
      bad("timestamp is not a number: '" + std::string(f[0].substr(0, 40)) + "'");
      continue;
    }
    std::array<double, 7> x{};
    size_t k = 0;
    for (; k < 7 && parseDouble(f[k + 1], x[k]); ++k) {
    }
    if (k < 7) {
      bad("field " + std::to_string(k + 2) + " is not a finite number: '" +
          std::string(f[k + 1].substr(0, 40)) + "'");
      continue;
    }
    const Eigen::Quaterniond q(x[6], x[3], x[4], x[5]);  // file order qx qy qz qw
    if (!(q.norm() > 1e-6)) {
      bad("quaternion has zero length");
      continue;
    }
    out.stamp_ns = *stamp;
    out.pose = Pose(q.normalized(), Eigen::Vector3d(x[0], x[1], x[2]));
    return true;
  }
  return false;
}

std::vector<StampedPose> readTum(const std::string& path) {
  TumReader reader(path);
  std::vector<StampedPose> poses;
  StampedPose p;
  while (reader.next(p)) poses.push_back(p);
  return poses;
}

TumWriter::TumWriter(const std::string& path) : path_(path), file_(path), out_(file_.tmp()) {
  if (!out_) throw IoError(path + ": cannot create TUM trajectory file");
  out_ << "# timestamp x y z qx qy qz qw\n";
}

TumWriter::~TumWriter() {
  if (out_.is_open()) out_.close();  // file_ then commits, or discards while an exception unwinds
}

void TumWriter::close() {
  out_.close();
  if (!out_) throw IoError(path_ + ": writing the TUM trajectory failed");
  file_.commit();
}

void TumWriter::write(const StampedPose& p) {
  const Eigen::Quaterniond& q = p.pose.rotation();
  const Eigen::Vector3d& t = p.pose.translation();
  char buf[256];
  std::snprintf(buf, sizeof buf, " %.9f %.9f %.9f %.9f %.9f %.9f %.9f\n", t.x(), t.y(), t.z(),
                q.x(), q.y(), q.z(), q.w());
  out_ << io_detail::formatSecondsNs(p.stamp_ns) << buf;
  if (!out_) throw IoError(path_ + ": writing the TUM trajectory failed");
}

}  // namespace polyloc
