#include <polyloc/map/scan_mapper.hpp>
#include <polyloc/map/grid_walk.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace polyloc {
namespace {

double logit(double p) { return std::log(p / (1 - p)); }

// Cells are at most this far from the world origin: beyond it the int64 index math is unsafe,
// and such a pose is garbage anyway.
constexpr double kMaxCellIndex = 1e12;
constexpr int64_t kMinGrowth = 64;  // cells added on a side when the grid grows

}  // namespace

ScanMapper::ScanMapper(const ScanMapperConfig& c) : config_(c) {
  const auto bad = [](const std::string& what) { throw std::invalid_argument("ScanMapperConfig: " + what); };
  if (!(c.resolution > 0) || !std::isfinite(c.resolution)) bad("resolution must be > 0");
  if (!(c.hit > 0)) bad("hit must be > 0 (log-odds)");
  if (!(c.miss < 0)) bad("miss must be < 0 (log-odds)");
  if (!(c.free_thresh > 0 && c.free_thresh < c.occupied_thresh && c.occupied_thresh < 1))
    bad("thresholds must satisfy 0 < free_thresh < occupied_thresh < 1");
  // Otherwise a cell could never become free (or occupied).
  if (!(c.clamp_min < logit(c.free_thresh))) bad("clamp_min must be below the free threshold's log-odds");
  if (!(c.clamp_max > logit(c.occupied_thresh))) bad("clamp_max must be above the occupied threshold's log-odds");
  if (!(c.max_range > 0) || !std::isfinite(c.max_range)) bad("max_range must be a finite number > 0");
  if (!(c.hit_beyond >= 0 && c.hit_beyond <= 2)) bad("hit_beyond must be in [0, 2] cells");
  // Cell offsets go to walkCells as int32.
  if (c.max_cells == 0 || c.max_cells > (size_t(1) << 31)) bad("max_cells must be in 1..2^31");
}

bool ScanMapper::reserve(int64_t i0, int64_t j0, int64_t i1, int64_t j1) {
  if (w_ > 0 && i0 >= ox_ && j0 >= oy_ && i1 < ox_ + int64_t(w_) && j1 < oy_ + int64_t(h_)) return true;
  const auto span = [](int64_t lo, int64_t hi) { return hi - lo + 1; };
  const auto fits = [this, &span](int64_t a0, int64_t b0, int64_t a1, int64_t b1) {
    return double(span(a0, a1)) * double(span(b0, b1)) <= double(config_.max_cells);
  };
  // What must be held: the cells observed so far (every touched cell lies in their bounds) and
  // this scan's. Whether a scan is taken depends on that alone, not on the margins allocated.
  int64_t ei0 = i0, ej0 = j0, ei1 = i1, ej1 = j1;
  if (seen_i1_ >= seen_i0_)
    ei0 = std::min(ei0, seen_i0_), ej0 = std::min(ej0, seen_j0_), ei1 = std::max(ei1, seen_i1_), ej1 = std::max(ej1, seen_j1_);
  if (!fits(ei0, ej0, ei1, ej1)) return false;
  // Grow in large steps (half the current size, at least kMinGrowth) on the sides that need it,
  // so that a robot driving on costs a copy per doubling, not one per scan; near max_cells the
  // margin is halved until it fits (growing to the exact size would copy the grid every scan).
  const int64_t gx = std::max<int64_t>(kMinGrowth, int64_t(w_) / 2), gy = std::max<int64_t>(kMinGrowth, int64_t(h_) / 2);
  const bool have = w_ > 0;
  const int64_t mi0 = !have || i0 < ox_ ? gx : 0, mj0 = !have || j0 < oy_ ? gy : 0;
  const int64_t mi1 = !have || i1 >= ox_ + int64_t(w_) ? gx : 0, mj1 = !have || j1 >= oy_ + int64_t(h_) ? gy : 0;
  int shift = 0;  // the exact box fits (above), so a shift that leaves no margin always does
  while (!fits(ei0 - (mi0 >> shift), ej0 - (mj0 >> shift), ei1 + (mi1 >> shift), ej1 + (mj1 >> shift))) ++shift;
  const int64_t ni0 = ei0 - (mi0 >> shift), nj0 = ej0 - (mj0 >> shift), ni1 = ei1 + (mi1 >> shift), nj1 = ej1 + (mj1 >> shift);
  const size_t nw = size_t(span(ni0, ni1)), nh = size_t(span(nj0, nj1));
  ZeroBuffer<float> lo(nw * nh);
  ZeroBuffer<uint32_t> last(nw * nh);
  // Copy the old buffers' part inside the new bounds (it holds every observed cell), skipping
  // the runs never observed: they are zero in both, and leaving them unwritten keeps them free.
  const int64_t ci0 = std::max(ox_, ni0), ci1 = std::min(ox_ + int64_t(w_) - 1, ni1);
  const int64_t cj0 = std::max(oy_, nj0), cj1 = std::min(oy_ + int64_t(h_) - 1, nj1);
  constexpr int64_t kRun = 1024;  // cells: a page of each buffer
  if (have && ci0 <= ci1)
    for (int64_t j = cj0; j <= cj1; ++j)
      for (int64_t i = ci0; i <= ci1; i += kRun) {
        const size_t from = size_t(j - oy_) * w_ + size_t(i - ox_), to = size_t(j - nj0) * nw + size_t(i - ni0);
        const int64_t n = std::min(kRun, ci1 - i + 1);
        const uint32_t* seen = last_scan_.data() + from;
        if (std::all_of(seen, seen + n, [](uint32_t v) { return v == 0; })) continue;
        std::copy_n(logodds_.data() + from, n, lo.data() + to);
        std::copy_n(seen, n, last.data() + to);
      }
  logodds_ = std::move(lo);
  last_scan_ = std::move(last);
  ox_ = ni0, oy_ = nj0, w_ = nw, h_ = nh;
  return true;
}

// last_scan_ holds 2 x scan number + 1 if that scan hit the cell: one update per cell and scan.
void ScanMapper::touch(int64_t i, int64_t j, bool hit) {
  const size_t idx = size_t(j - oy_) * w_ + size_t(i - ox_);
  const uint32_t now = uint32_t(scans_ + 1) * 2;
  uint32_t& last = last_scan_[idx];
  if ((last & ~1u) != now) {
    last = now | uint32_t(hit);
    touched_.push_back(idx);
  } else if (hit) {
    last |= 1u;
  }
}

ScanMapper::Added ScanMapper::add(double x, double y, double yaw, const float* ranges, size_t n, double angle_min,
                                  double angle_increment, double range_min, double range_max) {
  if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(yaw)) return Added::BadPose;
  if (!std::isfinite(angle_min) || !std::isfinite(angle_increment) || !(range_max > 0)) return Added::BadGeometry;
  const double res = config_.resolution;
  if (std::fabs(x) / res > kMaxCellIndex || std::fabs(y) / res > kMaxCellIndex) return Added::TooLarge;
  const double limit = std::min(range_max, config_.max_range);
  const double r_min = std::isfinite(range_min) ? std::max(range_min, 0.0) : 0.0;
  const auto cell = [res](double v) { return int64_t(std::floor(v / res)); };

  // End points first: the grid grows once per scan, before any cell index is taken.
  std::vector<Beam>& beams = beams_;
  beams.clear();
  const int64_t li = cell(x), lj = cell(y);
  int64_t i0 = li, j0 = lj, i1 = li, j1 = lj;
  for (size_t k = 0; k < n; ++k) {
    const double r = ranges[k];
    if (std::isnan(r) || !(r > 0) || r < r_min) continue;  // no reading (CARMEN writes 0), too close
    const bool hit = r < limit;
    const double d = hit ? r + config_.hit_beyond * res : limit, a = yaw + angle_min + double(k) * angle_increment;
    const Beam b{cell(x + d * std::cos(a)), cell(y + d * std::sin(a)), hit};
    i0 = std::min(i0, b.i), j0 = std::min(j0, b.j), i1 = std::max(i1, b.i), j1 = std::max(j1, b.j);
    beams.push_back(b);
  }
  if (beams.empty()) return Added::NoBeams;
  if (!reserve(i0, j0, i1, j1)) return Added::TooLarge;

  touched_.clear();
  for (const Beam& b : beams)
    walkCells(int32_t(li - ox_), int32_t(lj - oy_), int32_t(b.i - ox_), int32_t(b.j - oy_), [&](int32_t ci, int32_t cj) {
      touch(ci + ox_, cj + oy_, b.hit && ci + ox_ == b.i && cj + oy_ == b.j);
      return false;
    });
  const double occupied = logit(config_.occupied_thresh);
  for (size_t idx : touched_) {
    float& v = logodds_[idx];
    const bool hit = last_scan_[idx] & 1u;
    if (!hit && config_.sticky_hits && v > occupied) continue;
    v = float(std::clamp(double(v) + (hit ? config_.hit : config_.miss), config_.clamp_min, config_.clamp_max));
  }
  if (seen_i1_ < seen_i0_) seen_i0_ = i0, seen_j0_ = j0, seen_i1_ = i1, seen_j1_ = j1;
  seen_i0_ = std::min(seen_i0_, i0), seen_j0_ = std::min(seen_j0_, j0);
  seen_i1_ = std::max(seen_i1_, i1), seen_j1_ = std::max(seen_j1_, j1);
  ++scans_;
  return Added::Used;
}

OccupancyGrid ScanMapper::grid() const {
  OccupancyGrid g;
  g.resolution = config_.resolution;
  if (seen_i1_ < seen_i0_) return g;
  const int64_t pad = int64_t(config_.padding);
  const int64_t gi0 = seen_i0_ - pad, gj0 = seen_j0_ - pad;
  g.resize(size_t(seen_i1_ - seen_i0_ + 1 + 2 * pad), size_t(seen_j1_ - seen_j0_ + 1 + 2 * pad), OccupancyGrid::kUnknown);
  g.origin_x = double(gi0) * config_.resolution;
  g.origin_y = double(gj0) * config_.resolution;
  const double occ = logit(config_.occupied_thresh), fre = logit(config_.free_thresh);
  for (size_t y = 0; y < g.height; ++y)
    for (size_t x = 0; x < g.width; ++x) {
      const int64_t i = gi0 + int64_t(x) - ox_, j = gj0 + int64_t(y) - oy_;
      if (i < 0 || j < 0 || i >= int64_t(w_) || j >= int64_t(h_)) continue;
      const size_t idx = size_t(j) * w_ + size_t(i);
      if (last_scan_[idx] == 0) continue;  // never observed
      const float v = logodds_[idx];
      if (v > occ) g.at(x, y) = OccupancyGrid::kOccupied;
      else if (v < fre) g.at(x, y) = OccupancyGrid::kFree;
    }
  return g;
}

}  // namespace polyloc
