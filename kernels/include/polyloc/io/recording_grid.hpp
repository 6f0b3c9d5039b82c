// A 2D occupancy grid from a recording with known laser poses (a corrected CARMEN log: FLASER,
// RLASER and ROBOTLASER1 carry the laser's pose in the world): each LaserScan on one of the
// chosen topics is paired with the geometry_msgs/PoseStamped that follows it on
// `<topic>_pose` (the CARMEN reader sends it right after the scan) and integrated by a
// ScanMapper. Scans without a pose, or that the mapper refuses, are counted by reason.
#pragma once

#include <polyloc/io/recording.hpp>
#include <polyloc/map/scan_mapper.hpp>

#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace polyloc {

struct RecordingGridStats {
  uint64_t scans_used = 0;
  // reason -> scans: "no_pose" (no pose before the next scan or the end), "bad_pose",
  // "bad_geometry", "no_valid_ranges", "too_large" (see ScanMapper::Added)
  std::map<std::string, uint64_t> skipped;
  std::vector<std::array<float, 2>> laser_path;  // x, y of every used scan's laser, in order
  uint64_t scansSkipped() const {
    uint64_t n = 0;
    for (const auto& [why, count] : skipped) n += count;
    return n;
  }
};

// Which of the scans with a pose are used, by their number k (0, 1, 2, ... in file order, per
// topic): k % every == offset. {2, 0}: the even scans (the map of the real-log protocol, whose
// odd scans are localised: docs/localization.md "Real logs").
struct ScanSelection {
  size_t every = 1, offset = 0;
};

// Reads the reader to its end. Other topics and message types are ignored. The grid is empty
// (0 x 0) when no scan was used. Scans left out by `select` are counted as "not_selected".
OccupancyGrid gridFromRecording(RecordingReader& reader, const std::vector<std::string>& scan_topics,
                                const ScanMapperConfig& config = {}, RecordingGridStats* stats = nullptr,
                                const ScanSelection& select = {});

}  // namespace polyloc
