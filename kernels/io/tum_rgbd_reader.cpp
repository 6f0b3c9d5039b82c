// TUM RGB-D benchmark layout: depth.txt ("timestamp depth/NAME.png" per line, '#' comments),
// 16-bit depth PNGs at 5000 units per metre, groundtruth.txt (TUM trajectory of the colour
// camera's optical frame from motion capture; the depth images are registered to it). Ground
// truth comes at its own rate (100 Hz): a frame gets the pose interpolated between the samples
// around its stamp when both lie within kMaxTruthGap of it, and none otherwise (counted).
#include "decimal_seconds.hpp"
#include "rgbd_frames.hpp"

#include <polyloc/io/tum.hpp>

#include <fmt/core.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace polyloc {
namespace {

namespace fs = std::filesystem;
constexpr int64_t kMaxTruthGap = 50'000'000;  // 50 ms: five missed motion-capture samples

std::string lower(std::string s) {
  for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

}  // namespace

RgbdIntrinsics tumIntrinsics(const std::string& folder) {
  // The benchmark's calibrated intrinsics per camera (its "Intrinsic Camera Calibration" page).
  // The folder's own name, also for "." or "dir/".
  std::error_code ec;
  fs::path path = fs::weakly_canonical(fs::absolute(folder, ec), ec);
  if (path.filename().empty()) path = path.parent_path();
  const std::string name = lower(path.filename().string());
  RgbdIntrinsics k;
  k.depth_scale = 5000.0;
  if (name.find("freiburg1") != std::string::npos) {
    k.fx = 517.3, k.fy = 516.5, k.cx = 318.6, k.cy = 255.3, k.source = "TUM freiburg1 (by the folder's name)";
  } else if (name.find("freiburg2") != std::string::npos) {
    k.fx = 520.9, k.fy = 521.0, k.cx = 325.1, k.cy = 249.7, k.source = "TUM freiburg2 (by the folder's name)";
  } else if (name.find("freiburg3") != std::string::npos) {
    k.fx = 535.4, k.fy = 539.2, k.cx = 320.1, k.cy = 247.6, k.source = "TUM freiburg3 (by the folder's name)";
  } else {
    k.source = "ROS's default Kinect intrinsics (the folder's name says no freiburg camera)";
  }
  return k;
}

bool isTumRgbd(const std::string& dir) {
  std::error_code ec;
  return fs::is_regular_file(fs::path(dir) / "depth.txt", ec);
}

std::unique_ptr<RecordingReader> openTumRgbd(const std::string& dir, const std::string& intrinsics_file) {
  const fs::path list = fs::path(dir) / "depth.txt";
  std::ifstream in(list);
  if (!in) throw IoError(list.string() + ": cannot be opened (TUM RGB-D layout)");
  ReadStats stats;
  const RgbdIntrinsics intr = io_detail::chooseIntrinsics(dir, intrinsics_file, tumIntrinsics(dir), stats);

  std::vector<io_detail::RgbdFrame> frames;
  std::string line;
  for (size_t lineno = 1; std::getline(in, line); ++lineno) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const size_t start = line.find_first_not_of(" \t");
    if (start == std::string::npos || line[start] == '#') continue;
    std::istringstream fields(line);
    std::string stamp, file, extra;
    fields >> stamp >> file;
    const std::optional<int64_t> ns = io_detail::parseSecondsNs(stamp);
    std::string why;
    if (file.empty()) why = "needs 'timestamp filename'";
    else if (fields >> extra) why = "has more than 'timestamp filename'";
    else if (!ns || *ns <= 0) why = fmt::format("timestamp '{}' is not a positive number of seconds", stamp);
    else if (!frames.empty() && *ns <= frames.back().stamp_ns) why = fmt::format("timestamp {} does not increase", stamp);
    if (!why.empty()) {
      stats.warn(fmt::format("{}:{}: {}: line skipped", list.string(), lineno, why));
      continue;
    }
    frames.push_back({*ns, (fs::path(dir) / file).string(), std::nullopt});
  }
  if (frames.empty()) throw IoError(list.string() + ": lists no depth image");

  const fs::path gt = fs::path(dir) / "groundtruth.txt";
  std::error_code ec;
  if (!fs::exists(gt, ec)) {
    stats.note(fmt::format("{}: no groundtruth.txt: frames have no ground truth", dir));
  } else {
    TumReader reader(gt.string());
    std::vector<StampedPose> truth;
    StampedPose p;
    while (reader.next(p)) {
      if (p.pose.translation().cwiseAbs().maxCoeff() > 1e4) {  // as 7-Scenes' pose files: no room is 10 km
        stats.warn(fmt::format("{}: pose at {:.6f} s is beyond 10 km: skipped", gt.string(), p.stamp_ns * 1e-9));
        continue;
      }
      if (truth.empty() || p.stamp_ns > truth.back().stamp_ns) truth.push_back(p);
    }
    for (const std::string& w : reader.warnings()) stats.warn(w);
    stats.rejected += reader.rejected() - reader.warnings().size();  // counted beyond the first warnings
    size_t without = 0;
    for (io_detail::RgbdFrame& f : frames) {
      auto hi = std::lower_bound(truth.begin(), truth.end(), f.stamp_ns,
                                 [](const StampedPose& s, int64_t t) { return s.stamp_ns < t; });
      if (hi != truth.end() && hi->stamp_ns == f.stamp_ns) {
        f.world_T_optical = hi->pose;
      } else if (hi != truth.begin() && hi != truth.end() && f.stamp_ns - (hi - 1)->stamp_ns <= kMaxTruthGap &&
                 hi->stamp_ns - f.stamp_ns <= kMaxTruthGap) {
        const StampedPose& lo = *(hi - 1);
        f.world_T_optical = Pose::interpolate(lo.pose, hi->pose, double(f.stamp_ns - lo.stamp_ns) / double(hi->stamp_ns - lo.stamp_ns));
      } else {
        ++without;
      }
    }
    if (without)
      stats.note(fmt::format("{}: {} of {} frames have no ground truth within {} ms of their stamp", dir, without,
                             frames.size(), kMaxTruthGap / 1000000));
  }
  return std::make_unique<io_detail::RgbdFrameReader>(dir, "tum-rgbd", std::move(frames), intr, std::move(stats));
}

}  // namespace polyloc
