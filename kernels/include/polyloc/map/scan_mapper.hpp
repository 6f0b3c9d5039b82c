// A 2D occupancy grid built from planar scans taken at known laser poses (mapping with known
// poses, as from a corrected CARMEN log): each beam is walked cell by cell (Bresenham) from the
// laser's cell; the cells it crosses get a "miss", the cell of its end point a "hit", both as
// log-odds increments, clamped. A cell is updated at most once per scan (a hit wins over a miss),
// so that the many beams crossing the cells near the laser do not count as many observations.
// grid() thresholds the log-odds into map_server's trinary grid: occupied, free, or unknown
// (never observed, or not yet sure either way).
//
// The grid grows as scans arrive rather than being sized by a first pass over the data: a
// recording is a stream (readers keep memory flat and may not be rewindable), and growing in
// large steps costs one copy per doubling. `max_cells` bounds it, so that one absurd pose in a
// corrupt log cannot take all memory: a scan that would grow the grid beyond it is refused (the
// scans already integrated decide where the grid is).
#pragma once

#include <polyloc/map/grid_map.hpp>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <new>
#include <vector>

namespace polyloc {

struct ScanMapperConfig {
  double resolution = 0.05;     // m per cell
  double hit = 0.85;            // log-odds added to a beam's end cell (p = 0.70 after one hit)
  double miss = -0.4;           // log-odds added to a cell a beam crosses (p = 0.40 after one)
  double clamp_min = -2.0;      // log-odds bounds, so that a cell can still change its mind
  double clamp_max = 3.5;
  double max_range = 30.0;      // m; beams at or beyond min(range_max, this) clear free space up
                                // to it and mark no hit (no return, or a return too far to trust)
  double occupied_thresh = 0.65;  // p above: occupied (map_saver's thresholds)
  double free_thresh = 0.196;     // p below: free; a free cell needs 4 misses with the defaults
  size_t padding = 2;           // cells of unknown around the observed area in grid()
  // Cells: a beam's hit is the cell this far beyond its end point. The occupied cell is extruded
  // whole, so with 0 its near face lies up to a cell (half on average) in front of the surface
  // the beam saw, and a forward-looking scanner fits the map half a cell back; with 0.5 the
  // near face straddles the surface (floor of the real-log protocol 4.6 -> 2.6 cm on seattle).
  double hit_beyond = 0.5;
  // A cell once occupied stays so (misses no longer lower it): an end-point map, as simple map
  // tools mark every cell a return fell in, without the free-space carving that trims the cells
  // grazing beams cross.
  bool sticky_hits = false;
  size_t max_cells = size_t(1) << 25;  // 8 bytes a cell: 268 MB, 290 m x 290 m at 5 cm
};

class ScanMapper {
 public:
  // Throws std::invalid_argument naming the bad field (resolution <= 0, hit <= 0, miss >= 0,
  // clamp_min >= 0 or clamp_max <= 0, thresholds not 0 < free < occupied < 1, max_range <= 0).
  explicit ScanMapper(const ScanMapperConfig& config = {});

  enum class Added {
    Used,        // at least one beam integrated
    BadPose,     // laser pose not finite
    BadGeometry, // angle_min/angle_increment not finite, range_max not > 0
    NoBeams,     // every range NaN, below range_min or negative (nothing to integrate)
    TooLarge,    // integrating it would grow the grid beyond max_cells
  };
  // One scan: laser at (x, y) in the world, facing yaw; beam k at angle_min + k * angle_increment
  // in the laser frame. Ranges NaN, <= 0 (CARMEN's "no reading") or < range_min are skipped;
  // +inf, >= range_max or >= max_range clear free space up to min(range_max, max_range), no hit.
  Added add(double x, double y, double yaw, const float* ranges, size_t n, double angle_min,
            double angle_increment, double range_min, double range_max);

  // Trinary grid over the observed cells plus `padding`, origin in world coordinates (yaw 0).
  // Empty (0 x 0) before any scan was used.
  OccupancyGrid grid() const;
  size_t scans() const { return scans_; }
  const ScanMapperConfig& config() const { return config_; }

 private:
  bool reserve(int64_t i0, int64_t j0, int64_t i1, int64_t j1);  // cells [i0, i1] x [j0, j1]
  void touch(int64_t i, int64_t j, bool hit);

  ScanMapperConfig config_;
  // Cell (i, j) of the world covers [i res, (i + 1) res) x [j res, (j + 1) res); the buffers
  // hold cells [ox_, ox_ + w_) x [oy_, oy_ + h_), row-major from the bottom row.
  int64_t ox_ = 0, oy_ = 0;
  size_t w_ = 0, h_ = 0;
  // calloc'd: the system hands out large blocks as zero pages on demand, so the cells never
  // observed (most of a long corridor's bounding box) cost no memory and no clearing.
  template <class T> struct ZeroBuffer {
    struct Free { void operator()(T* p) const { std::free(p); } };
    std::unique_ptr<T, Free> p;
    ZeroBuffer() = default;
    explicit ZeroBuffer(size_t n) : p(static_cast<T*>(std::calloc(n ? n : 1, sizeof(T)))) {
      if (!p) throw std::bad_alloc();
    }
    T* data() const { return p.get(); }
    T& operator[](size_t i) const { return p.get()[i]; }
  };
  ZeroBuffer<float> logodds_;
  ZeroBuffer<uint32_t> last_scan_;  // 2 x (scan number + 1), +1 if that scan hit it; 0: never observed
  struct Beam { int64_t i, j; bool hit; };  // end cell of a beam of the current scan
  std::vector<Beam> beams_;          // scratch of add(), kept to not allocate per scan
  std::vector<size_t> touched_;      // cells the current scan updates
  int64_t seen_i0_ = 0, seen_j0_ = 0, seen_i1_ = -1, seen_j1_ = -1;  // observed bounds
  size_t scans_ = 0;
};

}  // namespace polyloc
