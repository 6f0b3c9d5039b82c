// Microsoft 7-Scenes layout: frame-NNNNNN.depth.png (16-bit, mm; 0 and 65535 invalid) and
// frame-NNNNNN.pose.txt (4x4 camera-to-world of the depth camera's optical frame), optionally
// camera-intrinsics.txt (a 3x3 K). No stamps: frame n is stamped n / rate_hz after 1 s (30 Hz;
// the first frame at 1 s, not at 0, which stamp checks take for "no stamp").
#include "rgbd_frames.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>

namespace polyloc {
namespace {

namespace fs = std::filesystem;

// "frame-000123.depth.png" -> 123; -1 when the name is not a 7-Scenes depth frame.
long frameNumber(const std::string& name) {
  static const std::regex re(R"(frame-(\d{1,9})\.depth\.png)");
  std::smatch m;
  return std::regex_match(name, m, re) ? std::stol(m[1]) : -1;
}

// Reads up to n numbers; false when the file has fewer, or one is not a finite number.
bool readNumbers(const fs::path& p, double* out, int n, std::string& why) {
  std::ifstream in(p);
  if (!in) return why = "cannot be opened", false;
  for (int i = 0; i < n; ++i) {
    std::string tok;
    if (!(in >> tok)) return why = fmt::format("has {} numbers, needs {}", i, n), false;
    char* end = nullptr;
    out[i] = std::strtod(tok.c_str(), &end);
    if (end == tok.c_str() || *end || !std::isfinite(out[i]))
      return why = fmt::format("value {} '{}' is not a finite number", i + 1, tok), false;
  }
  return true;
}

}  // namespace

RgbdIntrinsics sevenScenesIntrinsics() {
  RgbdIntrinsics k;
  k.fx = k.fy = 585.0;
  k.cx = 320.0, k.cy = 240.0;
  k.depth_scale = 1000.0;
  k.source = "7-Scenes' published depth intrinsics";
  return k;
}

bool isSevenScenes(const std::string& dir) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return false;
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (frameNumber(e.path().filename().string()) >= 0) return true;
  return false;
}

std::unique_ptr<RecordingReader> openSevenScenes(const std::string& dir, const std::string& intrinsics_file) {
  std::error_code ec;
  std::vector<std::pair<long, fs::path>> depth;
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (const long n = frameNumber(e.path().filename().string()); n >= 0) depth.emplace_back(n, e.path());
  if (depth.empty()) throw IoError(dir + ": no frame-NNNNNN.depth.png (7-Scenes layout)");
  std::sort(depth.begin(), depth.end());

  ReadStats stats;
  RgbdIntrinsics layout = sevenScenesIntrinsics();
  if (const fs::path kfile = fs::path(dir) / "camera-intrinsics.txt"; fs::exists(kfile, ec)) {
    double k[9];
    std::string why;
    if (!readNumbers(kfile, k, 9, why)) throw IoError(fmt::format("{}: {}", kfile.string(), why));
    if (!(k[0] > 0 && k[4] > 0 && k[1] == 0 && k[3] == 0 && k[6] == 0 && k[7] == 0 && k[8] == 1))
      throw IoError(kfile.string() + ": not a pinhole K (fx 0 cx / 0 fy cy / 0 0 1 with positive focal lengths)");
    layout.fx = k[0], layout.fy = k[4], layout.cx = k[2], layout.cy = k[5];
    layout.source = kfile.string();
  }
  const RgbdIntrinsics intr = io_detail::chooseIntrinsics(dir, intrinsics_file, layout, stats);
  stats.note(fmt::format("{}: 7-Scenes has no stamps: frame n is stamped 1 s + n / {:g} Hz", dir, intr.rate_hz));

  std::vector<io_detail::RgbdFrame> frames;
  size_t without_pose = 0;
  for (const auto& [n, path] : depth) {
    io_detail::RgbdFrame f;
    f.stamp_ns = 1000000000 + std::llround(double(n) * 1e9 / intr.rate_hz);
    f.depth_path = path.string();
    const fs::path pose_file = fs::path(dir) / fmt::format("frame-{:06d}.pose.txt", n);
    if (!fs::exists(pose_file, ec)) {
      ++without_pose;
    } else {
      double m[16];
      std::string why;
      Eigen::Matrix4d t;
      if (readNumbers(pose_file, m, 16, why)) {
        for (int i = 0; i < 16; ++i) t(i / 4, i % 4) = m[i];
        const Eigen::Matrix3d r = t.block<3, 3>(0, 0);
        const double ortho = (r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
        if (t.row(3) != Eigen::RowVector4d(0, 0, 0, 1)) why = "last row is not 0 0 0 1";
        else if (ortho > 1e-2 || r.determinant() < 0) why = fmt::format("rotation is not orthonormal (off by {:.3g})", ortho);
        else if (t.block<3, 1>(0, 3).cwiseAbs().maxCoeff() > 1e4) why = "translation beyond 10 km";
      }
      if (why.empty()) f.world_T_optical = Pose::fromMatrix(t);
      else stats.warn(fmt::format("{}: {}: pose skipped, frame kept", pose_file.string(), why));
    }
    frames.push_back(std::move(f));
  }
  if (without_pose) stats.note(fmt::format("{}: {} of {} frames have no pose file", dir, without_pose, frames.size()));
  return std::make_unique<io_detail::RgbdFrameReader>(dir, "7scenes", std::move(frames), intr, std::move(stats));
}

}  // namespace polyloc
